#!/usr/bin/env bash
# Builds the scene of the demo and of the integration tests: renders the test
# scene (known poses) and reconstructs it with stock colmap 3.8 on the CPU.
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
mkdir -p "$out/logs" "$out/sparse"
touch "$out/$marker"
run() {  # run NAME COMMAND...: time a step, keep its log, show it on failure
  local name=$1
  shift
  local start=$SECONDS
  if ! "$@" > "$out/logs/$name.log" 2>&1; then
    cat "$out/logs/$name.log"
    echo "reconstruct_test_scene: step '$name' failed" >&2
    exit 1
  fi
  echo "[colmap_scene] $name: $((SECONDS - start)) s"
}

run render "$render" --out "$out/scene" --num_images 12
run feature_extractor colmap feature_extractor \
  --database_path "$out/database.db" --image_path "$out/scene/images" \
  --ImageReader.single_camera 1 --ImageReader.camera_model SIMPLE_RADIAL \
  --SiftExtraction.use_gpu 0 --SiftExtraction.max_num_features 2000 \
  --SiftExtraction.first_octave 0
run exhaustive_matcher colmap exhaustive_matcher \
  --database_path "$out/database.db" --SiftMatching.use_gpu 0
run mapper colmap mapper --database_path "$out/database.db" \
  --image_path "$out/scene/images" --output_path "$out/sparse"
test -f "$out/sparse/0/images.bin"
