#!/usr/bin/env bash
# Adds a uwsim survey's laser images to a copy of its colmap database, as a
# user adds laser images to theirs before `laserscale localize`: features
# with the survey's camera (--ImageReader.existing_camera_id, so that the
# model's refined intrinsics apply), then exhaustive matching, which matches
# only the new pairs. The survey's database and model are not touched.
#
#   add_laser_images.sh SURVEY_DIR OUTPUT_DIR
#
# SURVEY_DIR: reconstruct_uwsim_survey.sh's output (sim/, database.db).
# OUTPUT_DIR/database.db, OUTPUT_DIR/laser_list.txt, OUTPUT_DIR/logs/.
set -euo pipefail
survey=$1
out=$2

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
run_step "$out/logs" exhaustive_matcher colmap exhaustive_matcher \
  --database_path "$out/database.db" --SiftMatching.use_gpu 0
echo "[add_laser_images] $(wc -l < "$out/laser_list.txt") laser images added"
