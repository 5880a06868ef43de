#!/usr/bin/env bash
# Installs every Debian 12 package the build, the tests and the benchmark scripts need.
# Idempotent: apt-get install skips what is present; safe to re-run.
#   tools/setup.sh [--viewers]   --viewers: also Debian's Blender (300 MB) and Xvfb, which only
#                                tools/study_export.sh's pictures of the exports in Blender and
#                                in MaterialX's renderer need (--blender: the same, its old name)
set -euo pipefail

packages=(
  # build
  build-essential meson ninja-build pkg-config clang-format
  # libraries (docs/architecture.md, "Conventions")
  libeigen3-dev libopencv-dev libmrcal-dev mrcal libmrgingham-dev mrgingham
  libusb-1.0-0-dev libaravis-dev aravis-tools aravis-tools-cli iproute2 libopenexr-dev libyaml-cpp-dev
  libsqlite3-dev libhdf5-dev libumockdev-dev umockdev catch2 nlohmann-json3-dev libssl-dev
  libcli11-dev
  # reference implementations, benchmarks and charts (Debian's /usr/bin/python3)
  python3 python3-numpy python3-h5py python3-matplotlib python3-mrcal python3-opencv
  # peak-memory measurement in benchmarks
  time
  # the renderer exports' tools (docs/export.md): a virtual environment for Mitsuba 3 and
  # MaterialX, the LLVM that Mitsuba 3.9's llvm variants need, node for the glTF validator
  python3-venv libllvm19
  # acqctl serve (the live view: docs/live-view.md) and its test in a real browser
  libcpp-httplib-dev chromium
)

for arg in "$@"; do
  case $arg in
    --viewers | --blender) packages+=(blender xvfb xauth) ;;
    *) echo "setup: unknown option '$arg' (the only one is --viewers)" >&2; exit 2 ;;
  esac
done

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# node and npm: Debian's, unless a node with npm is there already (e.g. from nodesource, whose
# nodejs package conflicts with Debian's npm).
command -v npm >/dev/null 2>&1 || missing+=(nodejs npm)
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages already installed"
else
  echo "setup: installing ${#missing[@]} packages: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
"$(dirname "$0")/setup-renderers.sh"
