#!/usr/bin/env bash
# Runs stock colmap 3.8 on the CPU over a folder of images: feature
# extraction (one shared camera), matching, incremental mapping.
#
#   colmap_sparse.sh IMAGE_DIR OUTPUT_DIR [CAMERA_MODEL [CAMERA_PARAMS]]
#
# CAMERA_PARAMS (comma-separated, COLMAP order) are the calibration a user
# would give; without them colmap guesses the focal length. Writes
# OUTPUT_DIR/database.db, OUTPUT_DIR/sparse/N and OUTPUT_DIR/logs/*.log.
# OUTPUT_DIR must not hold a database or model already.
#
# Matching (environment): MATCHER=exhaustive (default: every pair, time
# grows as images^2) or MATCHER=spatial: the navigation's positions go into
# the database (uwcolmap pose_prior_importer --nav "$NAV" $NAV_FLAGS; UWCOLMAP
# is the binary) and colmap spatial_matcher pairs each image with its
# SPATIAL_NEIGHBORS (50) nearest in 3D, as a user with navigation would on a
# survey of hundreds of images.
set -euo pipefail
images=$1
out=$2
model=${3:-SIMPLE_RADIAL}
params=${4:-}

case "${MATCHER:-exhaustive}" in
  exhaustive) ;;
  spatial)
    if [[ -z "${NAV:-}" || -z "${UWCOLMAP:-}" ]]; then
      echo "colmap_sparse: MATCHER=spatial needs NAV (a navigation log) and" \
        "UWCOLMAP (the uwcolmap binary)" >&2
      exit 2
    fi
    ;;
  *)
    echo "colmap_sparse: MATCHER is exhaustive or spatial, not '$MATCHER'" >&2
    exit 2
    ;;
esac
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
case "${MATCHER:-exhaustive}" in
  exhaustive)
    run_step "$out/logs" exhaustive_matcher colmap exhaustive_matcher \
      --database_path "$out/database.db" --SiftMatching.use_gpu 0
    ;;
  spatial)
    # NAV_FLAGS is a list of flags, split on spaces on purpose.
    # shellcheck disable=SC2086
    run_step "$out/logs" pose_prior_importer "$UWCOLMAP" pose_prior_importer \
      --database_path "$out/database.db" --nav "$NAV" ${NAV_FLAGS:-}
    # ignore_z 0: on a wall (scarp, breakwater) the lines are stacked in z.
    run_step "$out/logs" spatial_matcher colmap spatial_matcher \
      --database_path "$out/database.db" --SiftMatching.use_gpu 0 \
      --SpatialMatching.is_gps 0 --SpatialMatching.ignore_z 0 \
      --SpatialMatching.max_num_neighbors "${SPATIAL_NEIGHBORS:-50}"
    ;;
esac
run_step "$out/logs" mapper colmap mapper --database_path "$out/database.db" \
  --image_path "$images" --output_path "$out/sparse"
test -f "$out/sparse/0/images.bin"
