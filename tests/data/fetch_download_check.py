#!/usr/bin/env python3
"""Checks data/scenes/fetch.py's download path without the network: the teapot's files zipped as the
upstream archive lays them out (one wrapping folder, a __MACOSX entry), served from a file:// URL in
place of GitHub's. Usage: fetch_download_check.py FETCH_PY TEAPOT_FOLDER SCRATCH

Prints one line per check and exits 1 at the first that fails."""

import dataclasses
import hashlib
import importlib.util
import os
import pathlib
import sys
import zipfile


def load(path):
    spec = importlib.util.spec_from_file_location("fetch", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def check(condition, what):
    print(("ok: " if condition else "FAILED: ") + what)
    if not condition:
        sys.exit(1)


def make_zip(path, teapot, files, change=None):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as out:
        out.writestr("teapot/", b"")
        out.writestr("__MACOSX/teapot/._teapot.obj", b"resource fork")
        for name in sorted(files):
            data = pathlib.Path(teapot, name).read_bytes()
            if name == change:
                data = data[:-1] + bytes([data[-1] ^ 1])
            out.writestr("teapot/" + name, data)
    return hashlib.sha256(pathlib.Path(path).read_bytes()).hexdigest()


def leftovers(dest):
    return sorted(os.listdir(dest)) if os.path.isdir(dest) else []


def main(fetch_py, teapot, scratch):
    fetch = load(fetch_py)
    sponza = next(s for s in fetch.SCENES if s.name == "sponza")
    check(fetch.zip_url(sponza) == "https://raw.githubusercontent.com/jvm-graphics-labs/awesome-3d-meshes/"
          "14b5a498c84d1df97cc65fba173b372dea7fe34f/McGuire/Dabrovic%20Sponza/sponza.zip",
          "the zip's URL names the repository, the commit and the quoted path")

    recorded = next(s for s in fetch.SCENES if s.name == "teapot")
    files = fetch.read_manifest()[recorded.folder]
    upstream = pathlib.Path(scratch, "upstream")
    base_url = upstream.as_uri()
    archive = os.path.join(upstream, recorded.commit, recorded.zip_path)

    def fetch_into(scene, dest):
        stage = lambda folder, work: fetch.stage_from_upstream(scene, files, folder, work, base_url, quiet=True)
        try:
            fetch.install(scene, files, dest, stage)
            return ""
        except fetch.FetchError as error:
            return str(error)

    # The zip here is not upstream's, so its hash is not the recorded one: refused before it is opened.
    make_zip(archive, teapot, files)
    dest = os.path.join(scratch, "refused")
    error = fetch_into(recorded, dest)
    check("does not match" in error and recorded.zip_sha256 in error and "teapot.zip" in error,
          "a zip whose SHA-256 is not the recorded one is refused: " + error)
    check(leftovers(dest) == [], "and nothing is left in the destination")

    # With its own hash recorded, the same zip installs the listed files and nothing else.
    scene = dataclasses.replace(recorded, zip_sha256=make_zip(archive, teapot, files))
    dest = os.path.join(scratch, "installed")
    error = fetch_into(scene, dest)
    check(error == "", "the zip installs: " + (error or "no error"))
    check(leftovers(dest) == [recorded.folder], "as the one folder " + recorded.folder)
    installed = os.path.join(dest, recorded.folder)
    check(sorted(os.listdir(installed)) == sorted(files), "holding exactly the listed files")
    check(fetch.verified(installed, files), "each with its listed SHA-256")

    # A zip with the right hash but a changed file (a wrong manifest, say) fails naming the file.
    scene = dataclasses.replace(recorded, zip_sha256=make_zip(archive, teapot, files, change="teapot.obj"))
    dest = os.path.join(scratch, "changed")
    error = fetch_into(scene, dest)
    check("teapot/teapot.obj" in error and "does not match" in error, "a changed file is named: " + error)
    check(leftovers(dest) == [], "and nothing is left in the destination")


if __name__ == "__main__":
    main(*sys.argv[1:4])
