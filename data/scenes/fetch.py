#!/usr/bin/env python3
"""Fetches the third-party models the scene files in data/scenes/ render.

The models are not part of the repository (their licences do not allow it, or ask for credit that a
copy here would hide), so this script gets them from their upstream archives and checks each file
against the SHA-256 that data/scenes/SHA256SUMS lists: a scene renders the same bytes on every
machine only if its models are the same bytes. Python 3 standard library only.
"""

import argparse
import dataclasses
import hashlib
import http.client
import os
import shutil
import struct
import sys
import tempfile
import urllib.parse
import urllib.request
import zipfile
from fractions import Fraction

HERE = os.path.dirname(os.path.abspath(__file__))
MANIFEST = os.path.join(HERE, "SHA256SUMS")
DEFAULT_DEST = os.path.join(HERE, "models")

UPSTREAM_REPOSITORY = "jvm-graphics-labs/awesome-3d-meshes"
RAW_BASE_URL = "https://raw.githubusercontent.com/" + UPSTREAM_REPOSITORY

MCGUIRE = "via Morgan McGuire's Computer Graphics Archive, cite as McGuire2017 (casual-effects.com/data)"
STANFORD_TERMS = ("Stanford 3D Scanning Repository terms (research use, credit the Stanford Computer Graphics "
                  "Laboratory, no commercial use without permission)")


@dataclasses.dataclass(frozen=True)
class Conversion:
    """A file the archive does not hold as such, made here from one it does."""

    source: str  # the archive's file
    source_sha256: str
    target: str  # the file the manifest lists
    title: str  # the first comment line of the written OBJ
    note: str  # the second


@dataclasses.dataclass(frozen=True)
class Scene:
    name: str  # as data/scenes/<name>.json
    folder: str  # under the destination, as the JSON's "models/<folder>/..." paths name it
    commit: str  # of the upstream repository: the zip's last change, so the URL never moves
    zip_path: str
    zip_sha256: str
    licence: str
    licence_short: str  # for the one-line summary
    conversion: Conversion = None


SCENES = [
    Scene("sponza", "dabrovic-sponza", "14b5a498c84d1df97cc65fba173b372dea7fe34f",
          "McGuire/Dabrovic Sponza/sponza.zip", "cf2a45b1d99eb8613db88c343537ec5643d54e4a89d047ff46de635e29953248",
          "CC BY-NC 3.0 US (non-commercial), (c) 2002 Marko Dabrovic, " + MCGUIRE, "CC BY-NC"),
    Scene("sibenik", "sibenik-cathedral", "0aee329b50237f9c9cd3fd43cc2dfffd2b26f731",
          "McGuire/Sibenik Cathedral/sibenik.zip", "8cd074b577b0511eae5a1d670a763cba519a17630b3df9b55ca5cfd997bf84b1",
          "CC BY-NC 3.0 US (non-commercial), (c) 2002 Marko Dabrovic, " + MCGUIRE, "CC BY-NC"),
    Scene("bunny", "stanford-bunny", "bc0650c006fc03d521a21a8ad750ecd0f54b9d11",
          "McGuire/Stanford Bunny/bunny.zip", "7082df1052c2a13263e5e83aee2b12af2345e2849592a69bfeebd0dc8cb46ef6",
          STANFORD_TERMS + ", (c) 1996 Stanford University, " + MCGUIRE, "Stanford terms"),
    Scene("armadillo", "stanford-armadillo", "bcfd81f45b11a94ede8ce3ae027efab63d6e5bd9",
          "Stanford 3D Scanning Repository/Armadillo/Armadillo.zip",
          "b770ef23a47bbde17513b811dc53bde460113f3bceffab6c86d3a4db271f63f3",
          STANFORD_TERMS, "Stanford terms",
          Conversion("Armadillo.ply", "483563fca686b66168e1e45339c50e71a5dc8a526a04a545a16b9237d5eaa023",
                     "armadillo.obj",
                     "Stanford Armadillo (Stanford 3D Scanning Repository, vrip reconstruction Armadillo.ply)",
                     'Converted losslessly from binary PLY: positions and triangle indices only; per-face '
                     '"intensity" byte dropped.')),
    Scene("teapot", "utah-teapot", "0aee329b50237f9c9cd3fd43cc2dfffd2b26f731",
          "McGuire/Teapot/teapot.zip", "a6163f5bd662915c21f5a40d2cf6a7231afe25f09cd34679a9d82948ed891ac4",
          "CC0, (c) 1975 Martin Newell, " + MCGUIRE, "CC0"),
]


class FetchError(Exception):
    pass


def zip_url(scene, base_url=RAW_BASE_URL):
    return "%s/%s/%s" % (base_url, scene.commit, urllib.parse.quote(scene.zip_path))


def shown(path):
    """`path` relative to the working folder where it is under it, for messages."""
    relative = os.path.relpath(path)
    return path if relative.startswith("..") else relative


def read_manifest(path=MANIFEST):
    """{folder: {file name: sha256}} from a sha256sum-format file of "<hash>  <folder>/<file>" lines."""
    manifest = {}
    with open(path, encoding="utf-8") as lines:
        for number, line in enumerate(lines, 1):
            line = line.rstrip("\n")
            if not line:
                continue
            digest, sep, name = line.partition("  ")
            folder, slash, file = name.partition("/")
            if not sep or not slash or len(digest) != 64 or "/" in file:
                raise FetchError("%s:%d: not a '<sha256>  <folder>/<file>' line" % (shown(path), number))
            manifest.setdefault(folder, {})[file] = digest
    return manifest


def sha256_of(path):
    digest = hashlib.sha256()
    with open(path, "rb") as stream:
        for block in iter(lambda: stream.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def copy_hashed(source, target):
    """Copies the stream `source` to the file `target` and returns the SHA-256 of what it wrote."""
    digest = hashlib.sha256()
    with open(target, "wb") as out:
        for block in iter(lambda: source.read(1 << 20), b""):
            digest.update(block)
            out.write(block)
    return digest.hexdigest()


def check_digest(what, actual, expected, listed_in):
    if actual != expected:
        raise FetchError("%s: SHA-256 does not match: it is %s, %s gives %s" % (what, actual, listed_in, expected))


def verified(folder, files):
    """True when `folder` holds every listed file with its listed hash."""
    return all(os.path.isfile(os.path.join(folder, f)) and sha256_of(os.path.join(folder, f)) == digest
               for f, digest in files.items())


# --- PLY to OBJ -------------------------------------------------------------------------------------

PLY_TYPES = {"char": "b", "int8": "b", "uchar": "B", "uint8": "B", "short": "h", "int16": "h", "ushort": "H",
             "uint16": "H", "int": "i", "int32": "i", "uint": "I", "uint32": "I", "float": "f", "float32": "f",
             "double": "d", "float64": "d"}

CORNER_NAMES = ("vertex_indices", "vertex_index")

_FLOAT32 = struct.Struct("<f")
_UINT32 = struct.Struct("<I")


def _float32(value):
    return _FLOAT32.unpack(_FLOAT32.pack(value))[0]


def _reads_back_as(text, value):
    """Whether the decimal `text` reads back as the float32 `value` under round-to-nearest-even.

    Parsing to a double and then to float32 rounds twice; that can only go wrong where the double
    lands exactly on the midpoint between two float32s, and there the decimal is compared exactly."""
    double = float(text)
    try:
        single = _float32(double)
    except OverflowError:
        return False
    if double != single:
        bits = _UINT32.unpack(_FLOAT32.pack(single))[0]
        bits += 1 if (double > single) == (single > 0 or (single == 0 and double > 0)) else -1
        if single == 0:
            bits = 1 | (0x80000000 if double < 0 else 0)
        neighbour = _FLOAT32.unpack(_UINT32.pack(bits))[0]
        midpoint = (single + neighbour) / 2
        if double == midpoint:
            exact = Fraction(text)
            if exact != Fraction(midpoint):
                nearer = single if abs(exact - Fraction(single)) < abs(exact - Fraction(neighbour)) else neighbour
                return nearer == value
    return single == value


def shortest_float32(value):
    """The shortest decimal that reads back as the float32 `value` (the nearest one among equals), as
    positional text: "5.8945775", "-0.0024965196", "12.0"."""
    if value != value or value in (float("inf"), float("-inf")):
        raise FetchError("a PLY vertex is not finite: %r" % value)
    sign = "-" if str(value).startswith("-") else ""
    if value == 0:
        return sign + "0.0"
    # Any decimal of 6 or fewer digits within half a float32 step of the value is also its nearest
    # 6-digit decimal (a 6-digit half unit is wider than a float32 half step), so one look covers
    # lengths 1 to 6; from 7 digits on, where the float32 step can be wider than the decimal one,
    # the nearest decimal may miss while its neighbour on the other side (a power of two's
    # narrower lower half step) reads back.
    digits = None
    for precision in range(6, 10):
        mantissa, _, exponent = ("%.*e" % (precision - 1, abs(value))).partition("e")
        nearest = int(mantissa.replace(".", ""))
        scale = int(exponent) - (precision - 1)
        candidates = [nearest] if precision == 6 else [nearest, nearest - 1, nearest + 1]
        found = [c for c in candidates if _reads_back_as("%s%de%d" % (sign, c, scale), value)]
        if found:
            digits, exponent10 = found[0], scale
            break
    if digits is None:
        raise FetchError("no decimal of 9 digits reads back as %r" % value)
    text = str(digits).rstrip("0")
    exponent10 += len(str(digits)) - len(text)
    point = len(text) + exponent10
    if point <= 0:
        text = "0." + "0" * -point + text
    elif point >= len(text):
        text = text + "0" * (point - len(text)) + ".0"
    else:
        text = text[:point] + "." + text[point:]
    return sign + text


def _read_ply_header(data, name):
    end = data.find(b"end_header\n")
    if not data.startswith(b"ply\n") or end < 0:
        raise FetchError("%s: not a PLY file" % name)
    body = end + len(b"end_header\n")
    endian, elements = None, []
    for line in data[:end].decode("ascii").split("\n")[1:]:
        words = line.split()
        if not words or words[0] in ("comment", "obj_info"):
            continue
        if words[0] == "format":
            endian = {"binary_big_endian": ">", "binary_little_endian": "<"}.get(words[1])
            if endian is None:
                raise FetchError("%s: PLY format %s is not read here (binary only)" % (name, words[1]))
        elif words[0] == "element":
            elements.append((words[1], int(words[2]), []))
        elif words[0] == "property" and elements:
            if words[1] == "list":
                elements[-1][2].append((words[4], PLY_TYPES[words[2]], PLY_TYPES[words[3]]))
            else:
                elements[-1][2].append((words[2], PLY_TYPES[words[1]], None))
        else:
            raise FetchError("%s: PLY header line %r is not understood" % (name, line))
    if endian is None:
        raise FetchError("%s: PLY header has no format line" % name)
    return endian, elements, body


def ply_to_obj(data, conversion, name):
    try:
        return _ply_to_obj(data, conversion, name)
    except struct.error:
        raise FetchError("%s: PLY is shorter than its header describes" % name) from None


def _ply_to_obj(data, conversion, name):
    """The OBJ of the binary PLY `data`: positions exact to the float32 ("v x y z", shortest decimals),
    faces 1-based in the PLY's order and winding ("f a b c"), every other property dropped."""
    endian, elements, offset = _read_ply_header(data, name)
    positions, faces = [], []
    for element, count, properties in elements:
        names = [p[0] for p in properties]
        if element == "vertex":
            if any(p[2] is not None for p in properties):
                raise FetchError("%s: PLY vertices with list properties are not read here" % name)
            record = struct.Struct(endian + "".join(p[1] for p in properties))
            try:
                axes = [names.index(a) for a in "xyz"]
            except ValueError:
                raise FetchError("%s: PLY vertices have no x, y, z" % name) from None
            if any(properties[a][1] != "f" for a in axes):
                raise FetchError("%s: PLY positions are not float32" % name)
            size = record.size * count
            rows = record.iter_unpack(data[offset:offset + size])
            positions = [" ".join(shortest_float32(row[a]) for a in axes) for row in rows]
            offset += size
        else:
            corners = next((i for i, n in enumerate(names) if element == "face" and n in CORNER_NAMES), -1)
            readers = [(struct.Struct(endian + kind), item and struct.Struct(endian + item).size, item)
                       for _, kind, item in properties]
            for _ in range(count):
                for i, (scalar, item_size, item) in enumerate(readers):
                    if item is None:
                        offset += scalar.size
                        continue
                    (n,) = scalar.unpack_from(data, offset)
                    offset += scalar.size
                    if i == corners:
                        faces.append(struct.unpack_from(endian + item * n, data, offset))
                    offset += item_size * n
    if offset != len(data):
        raise FetchError("%s: PLY holds %d bytes, its header describes %d" % (name, len(data), offset))
    for face in faces:
        if len(face) < 3 or min(face) < 0 or max(face) >= len(positions):
            raise FetchError("%s: a PLY face has corners %s (%d vertices)" % (name, face, len(positions)))
    kind = "triangles" if all(len(f) == 3 for f in faces) else "faces"
    lines = ["# " + conversion.title, "# " + conversion.note,
             "# %d vertices, %d %s. Source PLY sha256 %s" % (len(positions), len(faces), kind,
                                                             hashlib.sha256(data).hexdigest())]
    lines += ["v " + p for p in positions]
    lines += ["f " + " ".join(str(i + 1) for i in face) for face in faces]
    return ("\n".join(lines) + "\n").encode("ascii")


def convert(scene, source_path, folder, source_name):
    conversion = scene.conversion
    check_digest(source_name, sha256_of(source_path), conversion.source_sha256, "the upstream file's hash in fetch.py")
    with open(source_path, "rb") as stream:
        data = stream.read()
    with open(os.path.join(folder, conversion.target), "wb") as out:
        out.write(ply_to_obj(data, conversion, source_name))


# --- Getting a scene -------------------------------------------------------------------------------


def stage_from_mirror(scene, files, mirror, folder, work):
    """Copies the scene's files from `mirror`/<folder>/ into `folder`, checking each."""
    source_folder = os.path.join(mirror, scene.folder)
    conversion = scene.conversion
    for file, digest in sorted(files.items()):
        source = os.path.join(source_folder, file)
        if conversion and file == conversion.target and not os.path.isfile(source):
            ply = os.path.join(source_folder, conversion.source)
            if os.path.isfile(ply):
                convert(scene, ply, folder, shown(ply))
                check_digest(shown(ply) + " converted to " + file, sha256_of(os.path.join(folder, file)), digest,
                             shown(MANIFEST))
                continue
        if not os.path.isfile(source):
            raise FetchError("%s: missing from the mirror" % shown(source))
        with open(source, "rb") as stream:
            check_digest(shown(source), copy_hashed(stream, os.path.join(folder, file)), digest, shown(MANIFEST))


def stage_from_upstream(scene, files, folder, work, base_url=RAW_BASE_URL, quiet=False):
    """Downloads the scene's zip, checks its hash before opening it, and extracts the listed files."""
    url = zip_url(scene, base_url)
    archive = os.path.join(work, "upstream.zip")
    if not quiet:
        print("%s: downloading %s" % (scene.name, url), flush=True)
    request = urllib.request.Request(url, headers={"User-Agent": "ssgi-fetch-scenes"})
    try:
        with urllib.request.urlopen(request, timeout=60) as response:
            actual = copy_hashed(response, archive)
    except (OSError, http.client.HTTPException) as error:
        raise FetchError("%s: cannot download: %s" % (url, error or type(error).__name__)) from None
    check_digest(url, actual, scene.zip_sha256, "the zip's hash in fetch.py")
    conversion = scene.conversion
    wanted = set(files) | ({conversion.source} if conversion else set())
    with zipfile.ZipFile(archive) as zipped:
        members = [m for m in zipped.infolist()
                   if not m.is_dir() and m.filename.split("/")[0] != "__MACOSX"]
        parts = [m.filename.split("/") for m in members]
        # A zip that wraps everything in one folder is read as if it did not.
        strip = 1 if parts and all(len(p) > 1 and p[0] == parts[0][0] for p in parts) else 0
        for member, path in zip(members, parts):
            name = "/".join(path[strip:])
            if name not in wanted:
                if not quiet:
                    print("%s: %s in the zip is not listed in %s: left out" % (scene.name, name, shown(MANIFEST)))
                continue
            target = os.path.join(work if conversion and name == conversion.source else folder, name)
            with zipped.open(member) as stream:
                actual = copy_hashed(stream, target)
            if name in files:
                check_digest("%s!%s" % (url, member.filename), actual, files[name], shown(MANIFEST))
            wanted.discard(name)
    if conversion and conversion.source not in wanted:
        convert(scene, os.path.join(work, conversion.source), folder, "%s!%s" % (url, conversion.source))
        target = conversion.target
        check_digest("%s converted to %s" % (conversion.source, target), sha256_of(os.path.join(folder, target)),
                     files[target], shown(MANIFEST))
        wanted.discard(target)
    if wanted:
        raise FetchError("%s: %s not in the zip" % (url, ", ".join(sorted(wanted))))


def install(scene, files, dest, stage):
    """Builds the scene's folder in a temporary folder beside its place and moves it in only once every
    file is there and verified, so a failure leaves the old folder (or none) and no partial one."""
    os.makedirs(dest, exist_ok=True)
    work = tempfile.mkdtemp(prefix=".fetch-%s-" % scene.folder, dir=dest)
    try:
        folder = os.path.join(work, scene.folder)
        os.mkdir(folder)
        stage(folder, work)
        # Every file once more, as it lies on disk where it will be used.
        for file, digest in sorted(files.items()):
            check_digest(os.path.join(scene.folder, file), sha256_of(os.path.join(folder, file)), digest,
                         shown(MANIFEST))
        unlisted = sorted(set(os.listdir(folder)) - set(files))
        if unlisted:
            raise FetchError("%s: %s not listed in %s" % (scene.folder, ", ".join(unlisted), shown(MANIFEST)))
        final = os.path.join(dest, scene.folder)
        if os.path.lexists(final):
            os.rename(final, os.path.join(work, "previous"))
        os.rename(folder, final)
    finally:
        shutil.rmtree(work, ignore_errors=True)


def main(argv):
    names = [s.name for s in SCENES]
    parser = argparse.ArgumentParser(
        prog="fetch.sh",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        description="Fetches the third-party models that data/scenes/*.json render into data/scenes/models/"
                    "<folder>/ (not part of the repository; git ignores it), checking every file against "
                    "data/scenes/SHA256SUMS. Without --from it downloads each scene's zip from the "
                    "upstream archive (%s at a fixed commit on GitHub) and checks the zip's SHA-256 "
                    "before opening it. A scene whose files are all present and verified is left as "
                    "it is; any other is fetched whole and replaces its folder only once every file "
                    "checks out." % UPSTREAM_REPOSITORY,
        epilog="scenes:\n" + "\n".join("  %-10s %s: %s" % (s.name, s.folder, s.licence) for s in SCENES) +
               "\n\nexamples:\n  data/scenes/fetch.sh                           download all five\n"
               "  data/scenes/fetch.sh --from ../shared/scenes   copy from a local mirror\n"
               "  data/scenes/fetch.sh sponza teapot             only these two")
    parser.add_argument("scenes", nargs="*", metavar="SCENE", help="scenes to fetch (default: all): " +
                        ", ".join(names))
    parser.add_argument("--from", dest="mirror", metavar="DIR",
                        help="copy from a local folder laid out as DIR/<folder>/<files> instead of downloading "
                             "(the armadillo may be there as the upstream Armadillo.ply, converted to OBJ here)")
    parser.add_argument("--dest", metavar="DIR", default=DEFAULT_DEST,
                        help="where the scene folders go (default: data/scenes/models)")
    parser.add_argument("--quiet", action="store_true", help="print one summary line instead of one per scene")
    args = parser.parse_args(argv)
    unknown = [n for n in args.scenes if n not in names]
    if unknown:
        parser.error("unknown scene %s (scenes: %s)" % (", ".join(unknown), ", ".join(names)))
    if args.mirror is not None and not os.path.isdir(args.mirror):
        parser.error("--from %s: not a folder" % args.mirror)
    chosen = [s for s in SCENES if not args.scenes or s.name in args.scenes]

    try:
        manifest = read_manifest()
        fetched, present = [], []
        for scene in chosen:
            files = manifest.get(scene.folder)
            if not files:
                raise FetchError("%s lists no files of %s" % (shown(MANIFEST), scene.folder))
            place = os.path.join(args.dest, scene.folder)
            if verified(place, files):
                present.append(scene)
                how = "already present, verified"
            else:
                if args.mirror is not None:
                    stage = lambda folder, work: stage_from_mirror(scene, files, args.mirror, folder, work)
                else:
                    stage = lambda folder, work: stage_from_upstream(scene, files, folder, work, quiet=args.quiet)
                install(scene, files, args.dest, stage)
                fetched.append(scene)
                how = "fetched and verified"
            if not args.quiet:
                print("%s: %s (%d file%s, %s)\n    licence: %s" % (scene.name, shown(place), len(files),
                                                                     "" if len(files) == 1 else "s", how,
                                                                     scene.licence))
        if args.quiet:
            licences = {}
            for scene in chosen:
                licences.setdefault(scene.licence_short, []).append(scene.name)
            print("scenes: %d fetched, %d already present, verified in %s (%s)" % (
                len(fetched), len(present), shown(args.dest),
                "; ".join("%s: %s" % (", ".join(n), l) for l, n in licences.items())))
    except FetchError as error:
        print("fetch.sh: error: %s" % error, file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        return 130
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
