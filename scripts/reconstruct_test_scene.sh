#!/usr/bin/env bash
# Builds the scene of the colmap I/O integration tests: renders the small
# OpenCV test scene (known poses) and reconstructs it with stock colmap 3.8
# on the CPU (scripts/colmap_sparse.sh).
#
#   reconstruct_test_scene.sh RENDER_TEST_SCENE_BINARY OUTPUT_DIR
#
# OUTPUT_DIR/scene/{images,truth}  rendered images and the true model
# OUTPUT_DIR/database.db           colmap's features and matches
# OUTPUT_DIR/sparse/0              colmap's model
# OUTPUT_DIR/logs/                 what each colmap step printed
set -euo pipefail
render=$1
out=$2
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"

# Only a folder this script made earlier (it holds the marker) is replaced;
# anything else that is not empty is refused, so a mistyped path never
# deletes a user's data.
marker=".uwmetric-test-scene"
if [[ -e "$out" && -n "$(ls -A "$out" 2>/dev/null)" && ! -f "$out/$marker" ]]; then
  echo "reconstruct_test_scene: $out exists and was not made by this script;" \
    "choose a new or empty folder" >&2
  exit 1
fi
rm -rf "$out"
mkdir -p "$out"
touch "$out/$marker"

start=$SECONDS
"$render" --out "$out/scene" --num_images 12 > /dev/null
echo "[test scene] render: $((SECONDS - start)) s"
bash "$here/colmap_sparse.sh" "$out/scene/images" "$out" SIMPLE_RADIAL
