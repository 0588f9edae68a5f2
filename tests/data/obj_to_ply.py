#!/usr/bin/env python3
"""Writes the armadillo OBJ that data/scenes/fetch.py makes back as the binary PLY it was made from:
the upstream Armadillo.ply's header, big-endian float32 positions, faces as a uchar intensity (0
everywhere upstream) then a uchar count and int corners. Usage: obj_to_ply.py armadillo.obj out.ply

With it the converter can be checked without the upstream zip: the PLY written here must have the
upstream file's SHA-256, and converting it must give the OBJ back byte for byte."""

import struct
import sys


def main(obj_path, ply_path):
    positions, faces = [], []
    with open(obj_path, encoding="ascii") as lines:
        for line in lines:
            words = line.split()
            if words and words[0] == "v":
                positions.append(struct.pack(">3f", *map(float, words[1:4])))
            elif words and words[0] == "f":
                corners = [int(w) - 1 for w in words[1:]]
                faces.append(struct.pack(">BB%di" % len(corners), 0, len(corners), *corners))
    header = ("ply\nformat binary_big_endian 1.0\ncomment author: Paraform\n"
              "obj_info 3D colored patch boundaries \n"
              "element vertex %d\nproperty float x\nproperty float y\nproperty float z\n"
              "element face %d\nproperty uchar intensity\nproperty list uchar int vertex_indices\n"
              "end_header\n" % (len(positions), len(faces)))
    with open(ply_path, "wb") as out:
        out.write(header.encode("ascii"))
        out.write(b"".join(positions))
        out.write(b"".join(faces))


if __name__ == "__main__":
    main(*sys.argv[1:3])
