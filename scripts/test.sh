#!/usr/bin/env bash
# Sets up (scripts/setup.sh) and runs uwmetric's default test suite: every
# CTest test not labelled "heavy" (scripts/bench.sh runs those). Prints
# CTest's summary and exits non-zero if any test fails.
#
#   bash scripts/test.sh                 # all default tests
#   bash scripts/test.sh -R model_io     # extra arguments go to ctest
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${UW_BUILD_DIR:-$root/build}"

bash "$root/scripts/setup.sh"
cd "$build_dir"
ctest --output-on-failure --label-exclude heavy -j"$(nproc)" --timeout 900 "$@"
