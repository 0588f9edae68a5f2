#!/usr/bin/env python3
r"""The direct light of a frame against the Embree reference's, per metal object and per distance from
the sun's highlight: how well the screen-space direct light's area-light approximation
(docs/pipeline.md "Direct light") matches the reference, which samples the sun's disk.

    mkdir -p /tmp/sun && ln -sf $PWD/data/*.obj $PWD/data/*.mtl /tmp/sun/
    sed 's/"cast_shadows": true/"cast_shadows": false/' data/default.json > /tmp/sun/sun.json
    build/cli/ssgi render /tmp/sun/sun.json --size 1024x1024 --shadows off --reflections off \
        --sky off --dump /tmp/sun/frame.exr -o /tmp/sun/frame.png
    build/cli/ssgi reference /tmp/sun/sun.json --transport paper --size 1024x1024 --spp 512 \
        -o /tmp/sun/reference.exr
    python3 bench/sun_highlight.py /tmp/sun/sun.json /tmp/sun/frame.exr /tmp/sun/reference.exr

The scene's first directional light is the sun; it must not cast shadows (the reference shadows
every shadow-casting light, the frame above none), hence the copy of the default scene. Each metal
object (metallic 1 in its "*" material override) is found in the dump by its base colour; its
pixels are split by the angle between the view's mirror direction and the sun's centre: on the
highlight (below twice the sun's angular radius), its shoulder (two to four times) and off it
(above four times). Each row gives the pixel count, the mean luminance of frame and reference, the
ratio of the means and the median of the per-pixel ratios.

Needs numpy and OpenImageIO's Python bindings (Debian: apt-get install python3-numpy
python3-openimageio)."""
import json
import math
import sys

import numpy as np
import OpenImageIO as oiio


def read_channels(path, names):
    """The named channels of the first part of an EXR that has them, as H x W float arrays."""
    image = oiio.ImageInput.open(path)
    if image is None:
        sys.exit("cannot open %s: %s" % (path, oiio.geterror()))
    part = 0
    while image.seek_subimage(part, 0):
        spec = image.spec()
        if all(name in spec.channelnames for name in names):
            pixels = image.read_image(0, 0, 0, spec.nchannels, "float")
            image.close()
            return [pixels[:, :, spec.channelnames.index(name)] for name in names]
        part += 1
    image.close()
    sys.exit("%s has no part with the channels %s" % (path, ", ".join(names)))


def luminance(rgb):
    return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]


def normalize(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def look_at_rotation(position, target, up):
    """The rows of glm::lookAt's rotation: world to view space."""
    forward = normalize(np.asarray(target, float) - np.asarray(position, float))
    side = normalize(np.cross(forward, up))
    return np.array([side, np.cross(side, forward), -forward])


def mirror_angle_degrees(scene, normal, width, height):
    """Per pixel, the angle between the mirror direction of the view and the sun's centre."""
    camera = scene["camera"]
    sun = next(light for light in scene["lights"] if light["type"] == "directional")
    rotation = look_at_rotation(camera["position"], camera["target"], camera.get("up", [0, 1, 0]))
    to_sun = -normalize(rotation @ np.asarray(sun["direction"], float))
    tan_half_y = math.tan(math.radians(camera.get("fov_y_deg", 45.0)) * 0.5)
    tan_half_x = tan_half_y * width / height
    px, py = np.meshgrid(np.arange(width) + 0.5, np.arange(height) + 0.5)
    ray = np.stack([(2 * px / width - 1) * tan_half_x, (1 - 2 * py / height) * tan_half_y, -np.ones_like(px)], -1)
    to_viewer = -normalize(ray)
    n_dot_v = np.sum(normal * to_viewer, -1, keepdims=True)
    mirror = normal * (2 * n_dot_v) - to_viewer
    return np.degrees(np.arccos(np.clip(mirror @ to_sun, -1.0, 1.0))), sun.get("angular_diameter_deg", 0.0) * 0.5


def metal_objects(scene):
    for index, entry in enumerate(scene["objects"]):
        material = entry.get("materials", {}).get("*", {})
        if material.get("metallic", 0) >= 0.5 and "base_color" in material:
            name = "%s %d (roughness %g)" % (entry["obj"].removesuffix(".obj"), index, material.get("roughness", 0))
            yield name, np.asarray(material["base_color"], float)


def main(arguments):
    if len(arguments) != 3:
        sys.exit(__doc__)
    scene = json.load(open(arguments[0]))
    frame = read_channels(arguments[1], ["direct.R", "direct.G", "direct.B"])
    albedo = read_channels(arguments[1], ["albedo.R", "albedo.G", "albedo.B", "metallic"])
    normal = np.stack(read_channels(arguments[1], ["normal.X", "normal.Y", "normal.Z"]), -1)
    reference = read_channels(arguments[2], ["direct.R", "direct.G", "direct.B"])
    height, width = frame[0].shape
    if reference[0].shape != frame[0].shape:
        sys.exit("the frame is %dx%d, the reference %dx%d" % (width, height, *reference[0].shape[::-1]))
    test, truth = luminance(frame), luminance(reference)
    angle, sun_radius = mirror_angle_degrees(scene, normal, width, height)
    regions = [("all", np.ones_like(angle, bool)), ("highlight", angle < 2 * sun_radius),
               ("shoulder", (angle >= 2 * sun_radius) & (angle <= 4 * sun_radius)),
               ("off highlight", angle > 4 * sun_radius)]
    print("%-28s %-13s %7s %11s %11s %8s %8s" % ("object", "region", "pixels", "frame", "reference", "mean", "median"))
    for name, colour in metal_objects(scene):
        # The decoded 8-bit sRGB albedo is within 0.5/255 of a code; pixels on the silhouette, whose
        # neighbours are not all the object, are left out (coverage and normals differ there).
        mask = (albedo[3] >= 0.5) & (np.max(np.abs(np.stack(albedo[:3], -1) - colour), -1) < 0.01)
        inner = mask.copy()
        inner[1:, :] &= mask[:-1, :]
        inner[:-1, :] &= mask[1:, :]
        inner[:, 1:] &= mask[:, :-1]
        inner[:, :-1] &= mask[:, 1:]
        for region, selected in regions:
            pixels = inner & selected
            count = int(pixels.sum())
            if count == 0:
                continue
            a, b = test[pixels], truth[pixels]
            positive = b > 0
            median = np.median(a[positive] / b[positive]) if positive.any() else float("nan")
            print("%-28s %-13s %7d %11.4g %11.4g %8.3f %8.3f" % (name, region, count, a.mean(), b.mean(),
                                                                  a.mean() / b.mean(), median))


if __name__ == "__main__":
    main(sys.argv[1:])
