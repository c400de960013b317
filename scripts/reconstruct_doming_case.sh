#!/usr/bin/env bash
# The doming case of issue 4 (docs/uwsim.md, "The doming case"): a single
# pass along the scarp, reconstructed by stock colmap 3.8 on the CPU with the
# intrinsics FIXED at a radial distortion slightly off the truth, as when a
# user's calibration is a little wrong. The strip then bends into a dome.
#
#   reconstruct_doming_case.sh UWSIM_BINARY OUTPUT_DIR CONFIG_JSON [K1_OFFSET]
#
# CONFIG_JSON is an uwsim generate configuration (tests/fixtures/
# doming_case.json: ~40 images; doming_case_full.json: 100 images);
# K1_OFFSET (default 0.005) is added to the true k1 of the SIMPLE_RADIAL
# camera (0: the true calibration, the reference without a dome).
#
# OUTPUT_DIR/sim/          uwsim's output (images/, nav.csv, truth/)
# OUTPUT_DIR/database.db   features and sequential matches
# OUTPUT_DIR/sparse/0      colmap's model (intrinsics as given, not refined)
# OUTPUT_DIR/camera_params.txt   the camera given to colmap: MODEL p1,p2,...
# OUTPUT_DIR/logs/         one log per step; times.txt: seconds per step
set -euo pipefail
uwsim=$1
out=$2
config=$3
k1_offset=${4:-0.005}

marker=".uwmetric-doming-case"
if [[ -e "$out" && -n "$(ls -A "$out" 2>/dev/null)" && ! -f "$out/$marker" ]]; then
  echo "reconstruct_doming_case: $out exists and was not made by this" \
    "script; choose a new or empty folder" >&2
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
    tail -n 50 "$out/logs/$name.log"
    echo "reconstruct_doming_case: step '$name' failed" >&2
    exit 1
  fi
  echo "$name $((SECONDS - start))" >> "$out/logs/times.txt"
  echo "[doming_case] $name: $((SECONDS - start)) s"
}

run generate "$uwsim" generate --config "$config" --out "$out/sim"
# truth/cameras.txt: "1 SIMPLE_RADIAL WIDTH HEIGHT f cx cy k1" after three
# comment lines.
read -r _ model _ _ f cx cy k1 rest < <(grep -v '^#' "$out/sim/truth/cameras.txt" | head -n 1)
if [[ "$model" != SIMPLE_RADIAL || -n "$rest" ]]; then
  echo "reconstruct_doming_case: expected one SIMPLE_RADIAL camera, got $model" >&2
  exit 1
fi
params="$f,$cx,$cy,$(awk -v k="$k1" -v d="$k1_offset" 'BEGIN { printf "%.6f", k + d }')"
echo "$model $params" > "$out/camera_params.txt"
echo "[doming_case] camera given to colmap: $model $params (true k1 $k1)"

# The scarp's images are dim and of low contrast: SIFT's default peak
# threshold (0.0067) finds only tens of features in them, 0.002 a few
# thousand. 2000 features per image keep matching and mapping within the
# default test suite's budget.
run feature_extractor colmap feature_extractor \
  --database_path "$out/database.db" --image_path "$out/sim/images" \
  --ImageReader.single_camera 1 --ImageReader.camera_model "$model" \
  --ImageReader.camera_params "$params" \
  --SiftExtraction.use_gpu 0 --SiftExtraction.num_threads 2 \
  --SiftExtraction.max_num_features 2000 --SiftExtraction.first_octave 0 \
  --SiftExtraction.peak_threshold 0.002
# At 75 % forward overlap an image overlaps the next three.
run sequential_matcher colmap sequential_matcher \
  --database_path "$out/database.db" --SiftMatching.use_gpu 0 \
  --SiftMatching.num_threads 2 --SequentialMatching.overlap 5
run mapper colmap mapper --database_path "$out/database.db" \
  --image_path "$out/sim/images" --output_path "$out/sparse" \
  --Mapper.num_threads 2 --Mapper.ba_refine_focal_length 0 \
  --Mapper.ba_refine_principal_point 0 --Mapper.ba_refine_extra_params 0
test -f "$out/sparse/0/images.bin"
