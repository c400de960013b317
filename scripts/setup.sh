#!/usr/bin/env bash
# Sets up a Debian 12 machine for uwmetric and builds it into build/.
#
# Installs the Debian packages uwmetric needs (only those missing; one
# `apt-get update` when something is missing; non-interactive), then
# configures with CMake + Ninja (+ ccache) and builds. Safe to run again:
# a second run installs nothing and rebuilds only what changed.
#
#   bash scripts/setup.sh            # everything: programs, tests, benchmarks
#   bash scripts/setup.sh uwcolmap laserscale uwsim   # only these targets
#   UW_BUILD_TYPE=Release bash scripts/setup.sh
#
# Targets named on the command line are built alone (scripts/demo.sh builds
# only the programs it runs); with none, everything is built.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${UW_BUILD_DIR:-$root/build}"

packages=(
  # toolchain
  cmake ninja-build ccache g++ pkg-config clang-format
  # stock COLMAP 3.8: the program our tests compare against
  colmap
  # libraries (DESIGN.md §3)
  libeigen3-dev libceres-dev libsqlite3-dev sqlite3 libcli11-dev
  libopencv-dev libgtest-dev libembree-dev libtbb-dev nlohmann-json3-dev
  libfmt-dev
  # GeographicLib: lat/lon, UTM and heading in navigation logs (LocalCartesian)
  libgeographiclib-dev
  # EXIF capture times (DateTimeOriginal, SubSec, OffsetTime) and the PNG
  # chunk CRC
  libexif-dev zlib1g-dev
  # Assimp: meshes in STL, glTF and other tools' formats
  libassimp-dev
  # mrcal 2.2: the C library uwcalib calibrates with, and its tools
  # (mrcal-calibrate-cameras, run by /usr/bin/python3) and chessboard finder
  # (mrgingham) that tests compare with
  libmrcal-dev mrcal python3-mrcal mrgingham
  # AprilTag 3: tags and Kalibr AprilGrids for uwcalib
  libapriltag-dev
  # headless browser: the survey report's render test (tests/report_render_test.cc)
  chromium
  # the reports' figures (scripts/uwplot.py, run by /usr/bin/python3)
  python3-matplotlib
)

missing=()
for package in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null |
      grep -q "install ok installed"; then
    missing+=("$package")
  fi
done

if ((${#missing[@]} > 0)); then
  as_root=(env DEBIAN_FRONTEND=noninteractive)
  if [[ $(id -u) -ne 0 ]]; then
    if ! command -v sudo > /dev/null; then
      echo "[setup] missing packages: ${missing[*]}" >&2
      echo "[setup] run this script as root (or install sudo) to install them" >&2
      exit 1
    fi
    as_root=(sudo env DEBIAN_FRONTEND=noninteractive)
  fi
  echo "[setup] installing ${#missing[@]} Debian packages: ${missing[*]}"
  "${as_root[@]}" apt-get update -qq
  "${as_root[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "[setup] all ${#packages[@]} Debian packages already installed"
fi

echo "[setup] configuring and building in $build_dir"
mkdir -p "$build_dir"
cmake -S "$root" -B "$build_dir" -G Ninja \
  -DCMAKE_BUILD_TYPE="${UW_BUILD_TYPE:-RelWithDebInfo}" > "$build_dir/configure.log" 2>&1 ||
  { cat "$build_dir/configure.log"; exit 1; }
targets=()
if (($# > 0)); then
  targets=(--target "$@")
  echo "[setup] building $*"
fi
cmake --build "$build_dir" -j"$(nproc)" "${targets[@]}"
echo "[setup] done: binaries in $build_dir/bin"
