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
#
# Flags of your own for each colmap step (environment, split on spaces as
# NAV_FLAGS is): EXTRACTOR_FLAGS (feature_extractor), MATCHER_FLAGS (the
# matcher), MAPPER_FLAGS (mapper). A flag given there replaces the script's
# default of the same name (colmap refuses a flag given twice); the camera
# model and its parameters are the arguments above. For 27 MP
# frames, say:
#   EXTRACTOR_FLAGS="--SiftExtraction.max_image_size 2400 --SiftExtraction.max_num_features 8000" \
#     bash scripts/colmap_sparse.sh images out OPENCV
# SINGLE_CAMERA=0 gives every image its own camera (default 1: one camera
# for all, as one camera and lens took them).
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

# with_user_flags USER_FLAGS NAME VALUE [NAME VALUE ...] sets the array
# `flags` to the NAME VALUE defaults that USER_FLAGS does not name (as
# "NAME VALUE" or "NAME=VALUE"), then USER_FLAGS split on spaces.
with_user_flags() {
  # Split on blanks and line breaks on purpose, but never glob (a value may
  # hold a *).
  local -
  set -f
  local user
  # shellcheck disable=SC2206
  user=($1)
  shift
  flags=()
  local word named
  while (($# >= 2)); do
    named=0
    for word in "${user[@]}"; do
      if [[ "$word" == "$1" || "$word" == "$1="* ]]; then named=1; fi
    done
    if ((!named)); then flags+=("$1" "$2"); fi
    shift 2
  done
  flags+=("${user[@]}")
}

camera=(--ImageReader.camera_model "$model")
if [[ -n "$params" ]]; then camera+=(--ImageReader.camera_params "$params"); fi
with_user_flags "${EXTRACTOR_FLAGS:-}" \
  --ImageReader.single_camera "${SINGLE_CAMERA:-1}" \
  --SiftExtraction.use_gpu 0 --SiftExtraction.max_num_features 2000 \
  --SiftExtraction.first_octave 0
run_step "$out/logs" feature_extractor colmap feature_extractor \
  --database_path "$out/database.db" --image_path "$images" "${camera[@]}" \
  "${flags[@]}"
case "${MATCHER:-exhaustive}" in
  exhaustive)
    with_user_flags "${MATCHER_FLAGS:-}" --SiftMatching.use_gpu 0
    run_step "$out/logs" exhaustive_matcher colmap exhaustive_matcher \
      --database_path "$out/database.db" "${flags[@]}"
    ;;
  spatial)
    # NAV_FLAGS is a list of flags, split on spaces on purpose.
    # shellcheck disable=SC2086
    run_step "$out/logs" pose_prior_importer "$UWCOLMAP" pose_prior_importer \
      --database_path "$out/database.db" --nav "$NAV" ${NAV_FLAGS:-}
    # ignore_z 0: on a wall (scarp, breakwater) the lines are stacked in z.
    with_user_flags "${MATCHER_FLAGS:-}" --SiftMatching.use_gpu 0 \
      --SpatialMatching.is_gps 0 --SpatialMatching.ignore_z 0 \
      --SpatialMatching.max_num_neighbors "${SPATIAL_NEIGHBORS:-50}"
    run_step "$out/logs" spatial_matcher colmap spatial_matcher \
      --database_path "$out/database.db" "${flags[@]}"
    ;;
esac
with_user_flags "${MAPPER_FLAGS:-}"
run_step "$out/logs" mapper colmap mapper --database_path "$out/database.db" \
  --image_path "$images" --output_path "$out/sparse" "${flags[@]}"
test -f "$out/sparse/0/images.bin"
