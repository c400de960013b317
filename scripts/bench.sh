#!/usr/bin/env bash
# Sets up (scripts/setup.sh) and runs the heavy tests and benchmarks: every
# CTest test labelled "heavy". Not part of scripts/test.sh or CI; results
# that compare us with a peer (stock COLMAP, Ceres, OMPL) go to bench/.
#
#   bash scripts/bench.sh [extra ctest arguments]
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${UW_BUILD_DIR:-$root/build}"

bash "$root/scripts/setup.sh"
cd "$build_dir"
# Six hours a test: each of the scarp's NEES tests (400 re-adjustments of
# 256 images) takes about two on 2 cores, more beside another heavy test.
ctest --output-on-failure --label-regex heavy --timeout 21600 "$@"
