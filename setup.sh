#!/usr/bin/env bash
# ssgi's one set-up script. On a fresh Debian 12 machine (as root, or with sudo) it installs the
# Debian packages that are missing, builds in Release, then:
#   ./setup.sh            renders the built-in default scene to default.png (with --stats)
#   ./setup.sh test       runs the whole test suite (ctest), first fetching the third-party scenes
#                         from ../shared/scenes where that mirror is beside the checkout
#   ./setup.sh build      only installs and builds
# BUILD_DIR (default: build) picks the build folder.
set -euo pipefail
cd "$(dirname "$0")"

# libtinygltf-dev reads glTF 2.0 files; assimp-testmodels holds the glTF 2.0 files the tests render
# or refuse (tests/cli/gltf_models_test.cpp). liblz4-dev and libturbojpeg0-dev are render-views'
# transfer encodings (LZ4, JPEG). libopenmpi-dev and openmpi-bin are Open MPI, which spreads
# render-views over processes and machines (mpirun); the build and the tests run without them
# (render-views then runs in one process, the MPI tests are left out). The last four are Mesa's
# OpenGL on the CPU, for the llvmpipe peer (bench/llvmpipe_bench.cpp) and the GLSL port the tests
# check against the oracle (tests/port/): EGL and OpenGL headers and libraries, Mesa's EGL, and
# Mesa's software drivers (llvmpipe). The build and the tests run without them (the peer is left
# out, the port's test skips). python3 runs data/scenes/fetch.sh.
packages=(cmake ninja-build g++ pkg-config libembree-dev libglm-dev libtinyobjloader-dev libtinygltf-dev
          libopenimageio-dev libbenchmark-dev catch2 libtbb-dev libhwy-dev libcli11-dev nlohmann-json3-dev python3
          assimp-testmodels liblz4-dev libturbojpeg0-dev libopenmpi-dev openmpi-bin
          libegl-dev libopengl-dev libegl-mesa0 libgl1-mesa-dri)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo=""
  [[ $(id -u) -eq 0 ]] || sudo="sudo"
  $sudo apt-get update -q
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
  echo "setup: packages installed in ${SECONDS} s"
fi

build="${BUILD_DIR:-build}"
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release
built_from=$SECONDS
cmake --build "$build" --parallel "$(nproc)"
echo "setup: built in $((SECONDS - built_from)) s"

case "${1:-render}" in
  render) "$build/cli/ssgi" render --stats ;;
  test)
    # The scene tests skip without the models; CI keeps a mirror beside the checkout.
    if [[ -d ../shared/scenes ]]; then data/scenes/fetch.sh --from ../shared/scenes --quiet; fi
    ctest --test-dir "$build" --output-on-failure --parallel "$(nproc)" ;;
  build) ;;
  *) echo "usage: $0 [render|test|build]" >&2; exit 2 ;;
esac
