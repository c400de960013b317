#!/usr/bin/env bash
# Runs stock colmap 3.8 on the CPU over a folder of images: feature
# extraction (one shared camera), exhaustive matching, incremental mapping.
#
#   colmap_sparse.sh IMAGE_DIR OUTPUT_DIR [CAMERA_MODEL [CAMERA_PARAMS]]
#
# CAMERA_PARAMS (comma-separated, COLMAP order) are the calibration a user
# would give; without them colmap guesses the focal length. Writes
# OUTPUT_DIR/database.db, OUTPUT_DIR/sparse/N and OUTPUT_DIR/logs/*.log.
# OUTPUT_DIR must not hold a database or model already.
set -euo pipefail
images=$1
out=$2
model=${3:-SIMPLE_RADIAL}
params=${4:-}

if [[ -e "$out/database.db" || -e "$out/sparse" ]]; then
  echo "colmap_sparse: $out already holds a database or model" >&2
  exit 1
fi
mkdir -p "$out/logs" "$out/sparse"
source "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/run_step.sh"

camera=(--ImageReader.single_camera 1 --ImageReader.camera_model "$model")
if [[ -n "$params" ]]; then camera+=(--ImageReader.camera_params "$params"); fi
run_step "$out/logs" feature_extractor colmap feature_extractor \
  --database_path "$out/database.db" --image_path "$images" "${camera[@]}" \
  --SiftExtraction.use_gpu 0 --SiftExtraction.max_num_features 2000 \
  --SiftExtraction.first_octave 0
run_step "$out/logs" exhaustive_matcher colmap exhaustive_matcher \
  --database_path "$out/database.db" --SiftMatching.use_gpu 0
run_step "$out/logs" mapper colmap mapper --database_path "$out/database.db" \
  --image_path "$images" --output_path "$out/sparse"
test -f "$out/sparse/0/images.bin"
