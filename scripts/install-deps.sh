#!/usr/bin/env bash
# Installs the Debian 12 packages fibertwin needs, only those missing.
# Idempotent: a second run installs nothing and makes no network request.
set -euo pipefail

packages=(
  # toolchain
  g++ cmake ninja-build pkg-config python3
  clang libclang-rt-14-dev          # libFuzzer + sanitizer runtimes for the fuzz target
  # libraries
  libglm-dev libtbb-dev libfmt-dev nlohmann-json3-dev libcli11-dev libstb-dev
  libgtest-dev libbenchmark-dev
  libeigen3-dev                    # least squares of the AO cubic fit
  libembree-dev libopenexr-dev     # the ray-traced ground truth; float images
  libopenmpi-dev openmpi-bin       # `fibertwin bake` across MPI ranks (docs/bakes.md); optional at build time
  # headless OpenGL: libepoxy, EGL (surfaceless / device), Mesa llvmpipe, OSMesa
  libepoxy-dev libegl-dev libegl-mesa0 libgl1-mesa-dri libosmesa6-dev
  # shader checks in the tests
  glslang-tools
  # the report page check in headless Chromium (tests/report_page_test.py)
  chromium
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: run as root or install sudo" >&2; exit 1; }
  sudo=sudo
fi
$sudo apt-get update -q
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
