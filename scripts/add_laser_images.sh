#!/usr/bin/env bash
# Adds a uwsim survey's laser images to a copy of its colmap database, as a
# user adds laser images to theirs before `laserscale localize`: features
# with the survey's camera (--ImageReader.existing_camera_id, so that the
# model's refined intrinsics apply), then matching, which matches only the
# new pairs. The survey's database and model are not touched.
#
#   add_laser_images.sh SURVEY_DIR OUTPUT_DIR
#
# SURVEY_DIR: reconstruct_uwsim_survey.sh's output (sim/, database.db,
# mount_flags.txt). OUTPUT_DIR/database.db, OUTPUT_DIR/laser_list.txt,
# OUTPUT_DIR/logs/.
#
# Matching (environment), as reconstruct_uwsim_survey.sh's: MATCHER=
# exhaustive (default: every laser image with every image; hours on the
# scarp's 357) or MATCHER=spatial: every image's position from the
# navigation at its time (sim/image_times.csv, sim/laser_image_times.csv;
# uwcolmap pose_prior_importer, UWCOLMAP the binary), then colmap
# spatial_matcher with each image's LASER_NEIGHBORS (30) nearest in 3D.
set -euo pipefail
survey=$1
out=$2

case "${MATCHER:-exhaustive}" in
  exhaustive) ;;
  spatial)
    if [[ -z "${UWCOLMAP:-}" || ! -f "$survey/sim/laser_image_times.csv" ]]; then
      echo "add_laser_images: MATCHER=spatial needs UWCOLMAP (the uwcolmap" \
        "binary) and $survey/sim/laser_image_times.csv" >&2
      exit 2
    fi
    ;;
  *)
    echo "add_laser_images: MATCHER is exhaustive or spatial, not '$MATCHER'" >&2
    exit 2
    ;;
esac

marker=".uwmetric-laser-images"
if [[ -e "$out" && -n "$(ls -A "$out" 2>/dev/null)" && ! -f "$out/$marker" ]]; then
  echo "add_laser_images: $out exists and was not made by this script" >&2
  exit 1
fi
rm -rf "$out"
mkdir -p "$out/logs"
touch "$out/$marker"
images="$survey/sim/laser_images"
find "$images" -maxdepth 1 -type f ! -name '*_aux.*' -printf '%f\n' | sort \
  > "$out/laser_list.txt"
if [[ ! -s "$out/laser_list.txt" ]]; then
  echo "add_laser_images: no laser images in $images" >&2
  exit 1
fi
cp "$survey/database.db" "$out/database.db"
source "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/run_step.sh"
run_step "$out/logs" feature_extractor colmap feature_extractor \
  --database_path "$out/database.db" --image_path "$images" \
  --image_list_path "$out/laser_list.txt" --ImageReader.existing_camera_id 1 \
  --SiftExtraction.use_gpu 0 --SiftExtraction.max_num_features 2000 \
  --SiftExtraction.first_octave 0
case "${MATCHER:-exhaustive}" in
  exhaustive)
    run_step "$out/logs" exhaustive_matcher colmap exhaustive_matcher \
      --database_path "$out/database.db" --SiftMatching.use_gpu 0
    ;;
  spatial)
    # One times file for every image of the database, so that the laser
    # images get priors on the survey images' clock and frame.
    { cat "$survey/sim/image_times.csv"
      grep -v -e '^#' -e '^image_name,' "$survey/sim/laser_image_times.csv"
    } > "$out/image_times.csv"
    read -r -a mount < "$survey/mount_flags.txt"
    run_step "$out/logs" pose_prior_importer "$UWCOLMAP" pose_prior_importer \
      --database_path "$out/database.db" --nav "$survey/sim/nav.csv" \
      --image_times "$out/image_times.csv" "${mount[@]}"
    run_step "$out/logs" spatial_matcher colmap spatial_matcher \
      --database_path "$out/database.db" --SiftMatching.use_gpu 0 \
      --SpatialMatching.is_gps 0 --SpatialMatching.ignore_z 0 \
      --SpatialMatching.max_num_neighbors "${LASER_NEIGHBORS:-30}"
    ;;
esac
echo "[add_laser_images] $(wc -l < "$out/laser_list.txt") laser images added"
