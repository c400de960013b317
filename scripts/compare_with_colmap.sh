#!/usr/bin/env bash
# Runs one COLMAP model through stock colmap and through uwcolmap and prints
# one table of how far each result is from uwsim's truth (issue 4,
# acceptance 5):
#
#   colmap          colmap bundle_adjuster, then colmap model_aligner onto
#                   the navigation: the vehicle positions of nav.csv as
#                   they are (what a stock colmap user has), and, with a
#                   database, the camera centres (vehicle position + lever
#                   arm) that uwcolmap pose_prior_importer writes into a
#                   copy of it
#   ours, no priors uwcolmap bundle_adjuster without navigation, then
#                   uwcolmap model_aligner --nav (covariance-weighted)
#   ours, posterior uwcolmap bundle_adjuster --Nav.strategy posterior
#   ours, prior     uwcolmap bundle_adjuster --Nav.strategy prior, once per
#                   --Nav.weight in NAV_WEIGHTS (default: auto, lambda
#                   from the estimated noise levels)
#
# With --laser_database, the whole chain for stock colmap's model aligned to
# the navigation (camera centres, or vehicle positions without a database)
# and for ours (prior, the first weight): uwcolmap dense_mesher on the
# model, laserscale detect / localize / estimate on that mesh with SIM_DIR's
# laser images, laserscale apply; one more row per chain ("... +
# dense_mesher + laserscale apply", the scaled model against the truth) and
# OUT_DIR/chain.csv: the laser scale, its 95 % interval, the truth (the
# similarity of the unscaled model to the true cameras), its error, the
# dense mesh's accuracy and coverage against the true surface, each
# source's share of the scale's variance, and for the fused model the
# laser scale's z-score against the navigation's own scale. The laser
# scale's Monte Carlo re-samples each model from its covariance
# (--Covariance.samples N draws, 200).
#
# Columns: camera RMSE vs truth as the model stands (absolute: every result
# is in the navigation's frame) and after a least-squares similarity to the
# truth; scale error s - 1 with s the scale of that similarity
# (truth_from_model: + when the model is too small); after that similarity,
# the RMS distance of the model's points from the true surface and the
# sagitta of the dome fit along the track (negative: the middle stands out
# towards the cameras; uwcolmap model_comparer); wall time of the steps of
# that row (bundle adjustment + alignment). OUT_DIR/table.txt has the
# table, OUT_DIR/table.csv the same figures for spreadsheets and reports.
#
#   compare_with_colmap.sh SIM_DIR MODEL_DIR OUT_DIR [flags]
#
# SIM_DIR     uwsim output: nav.csv and truth/
# MODEL_DIR   the model to adjust (e.g. colmap mapper's sparse/0)
# OUT_DIR     new or empty folder: one model per row, logs/, table.txt
# flags       --BundleAdjustment.NAME VALUE: given to both bundle
#             adjusters; --database_path DB: the images' database
#             (default MODEL_DIR/../../database.db when it exists);
#             --laser_database DB: the database with SIM_DIR's laser images
#             (scripts/add_laser_images.sh) for the whole chain, with
#             --DenseMesher.max_image_size N (512), --mc N (5000) and
#             --Covariance.samples N (200); --Nav.use_attitude 1: the
#             log's roll, pitch and yaw as priors of the prior-strategy
#             rows (a single pass needs them: docs/uwcolmap.md); any
#             other flag describes the camera on the vehicle and goes to
#             uwcolmap (--mount, --lever_arm, --boresight, --time_offset,
#             --image_times)
#
# A step's WARNING lines (e.g. camera centres on one line) are repeated on
# stderr with the step's name.
#
# Environment: COLMAP, UWCOLMAP, LASERSCALE (programs; default colmap on
# PATH, build/bin/uwcolmap and build/bin/laserscale), NAV_WEIGHTS (e.g.
# "auto 0.5"). Every step's wall time goes to OUT_DIR/timings.csv.
#
# Example (the survey of scripts/reconstruct_uwsim_survey.sh):
#   bash scripts/compare_with_colmap.sh build/tests/uwsim_survey/sim \
#     build/tests/uwsim_survey/sparse/0 /tmp/compare --mount down \
#     --lever_arm 0.6,0,-0.3 --boresight 0.3,-0.5,0.8
set -euo pipefail
if [[ $# -lt 3 ]]; then
  sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'
  exit 2
fi
sim=$1
model=$2
out=$3
shift 3
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
colmap=${COLMAP:-colmap}
uwcolmap=${UWCOLMAP:-$root/build/bin/uwcolmap}
laserscale=${LASERSCALE:-$root/build/bin/laserscale}
read -r -a nav_weights <<< "${NAV_WEIGHTS:-auto}"

ba_flags=()
prior_flags=()
mount_flags=()
database=""
laser_database=""
max_image_size=512
mc=5000
model_draws=200
while [[ $# -gt 0 ]]; do
  if [[ $# -lt 2 ]]; then
    echo "compare_with_colmap: flag $1 has no value" >&2
    exit 2
  fi
  case $1 in
    --BundleAdjustment.*) ba_flags+=("$1" "$2") ;;
    --Nav.use_attitude) prior_flags+=("$1" "$2") ;;
    --database_path) database=$2 ;;
    --laser_database) laser_database=$2 ;;
    --DenseMesher.max_image_size) max_image_size=$2 ;;
    --mc) mc=$2 ;;
    --Covariance.samples) model_draws=$2 ;;
    *) mount_flags+=("$1" "$2") ;;
  esac
  shift 2
done
# The fused rows' labels say when the attitude was fused too.
attitude_label=""
if [[ ${#prior_flags[@]} -gt 0 ]]; then
  attitude_label=" (${prior_flags[*]})"
fi
# With the whole chain, the fused model's covariance and joint draws of it,
# which the laser scale's Monte Carlo re-samples the model with.
covariance_flags=()
if [[ -n "$laser_database" ]]; then
  covariance_flags=(--BA.covariance 1 --Covariance.samples "$model_draws")
fi
if [[ -z "$database" && -f "$model/../../database.db" ]]; then
  database="$model/../../database.db"
fi
required=("$sim/nav.csv" "$sim/truth" "$model")
if [[ -n "$laser_database" ]]; then
  required+=("$laser_database" "$sim/laser_images" "$sim/lasers.json" "$sim/images")
fi
for path in "${required[@]}"; do
  if [[ ! -e "$path" ]]; then
    echo "compare_with_colmap: $path does not exist" >&2
    exit 1
  fi
done

marker=".uwmetric-compare-with-colmap"
if [[ -e "$out" && -n "$(ls -A "$out" 2>/dev/null)" && ! -f "$out/$marker" ]]; then
  echo "compare_with_colmap: $out exists and was not made by this script;" \
    "choose a new or empty folder" >&2
  exit 1
fi
rm -rf "$out"
mkdir -p "$out/logs"
touch "$out/$marker"

now() { date +%s.%N; }
seconds_since() { awk -v a="$1" -v b="$(now)" 'BEGIN { printf "%.2f", b - a }'; }
echo "step,seconds" > "$out/timings.csv"
run() {  # run NAME COMMAND...: keep the step's log and time, show it on failure
  local name=$1 step_start
  shift
  step_start=$(now)
  if ! "$@" > "$out/logs/$name.log" 2>&1; then
    tail -n 30 "$out/logs/$name.log"
    echo "compare_with_colmap: step '$name' failed (log: $out/logs/$name.log)" >&2
    exit 1
  fi
  echo "$name,$(seconds_since "$step_start")" >> "$out/timings.csv"
  grep '^WARNING:' "$out/logs/$name.log" | sed "s/^/$name: /" >&2 || true
}

# colmap's inlier threshold: 3 x the navigation's RMS 3D sigma
# sqrt(std_x^2 + std_y^2 + std_z^2), so that only gross outliers are set
# aside, as by uwcolmap model_aligner's automatic threshold (Mahalanobis
# distance 4.03: 99.9 % of the navigation's own errors).
nav_table() {  # nav.csv without its comment lines
  grep -v '^#' "$sim/nav.csv"
}
max_error=$(nav_table | awk -F, '
  NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
  { s += $col["std_x"]^2 + $col["std_y"]^2 + $col["std_z"]^2; ++n }
  END { printf "%.4g", n ? 3 * sqrt(s / n) : 0 }')
if ! awk -v e="$max_error" 'BEGIN { exit !(e > 0) }'; then
  echo "compare_with_colmap: $sim/nav.csv gives no position sigmas" >&2
  exit 1
fi

rows=()
csv_rows=()
add_row() {  # add_row LABEL MODEL_DIR SECONDS
  local label=$1 dir=$2 seconds=$3
  run "compare_$(basename "$dir")_none" "$uwcolmap" model_comparer \
    --input_path "$dir" --truth_dir "$sim" --alignment none
  run "compare_$(basename "$dir")_similarity" "$uwcolmap" model_comparer \
    --input_path "$dir" --truth_dir "$sim" --alignment similarity
  # "Camera centres: RMSE <m> m = <p> % of the <extent> m extent, ..." and
  # "Alignment reference_from_model (similarity, ...): scale <s>, ...".
  local abs="" sim_rmse="" extent="" scale="" surface_rms="" sagitta=""
  read -r abs _ < <(sed -n 's/^Camera centres: RMSE \([^ ]*\) m.*/\1/p' \
    "$out/logs/compare_$(basename "$dir")_none.log") || true
  read -r sim_rmse extent < <(sed -n \
    's/^Camera centres: RMSE \([^ ]*\) m = .* of the \([^ ]*\) m extent.*/\1 \2/p' \
    "$out/logs/compare_$(basename "$dir")_similarity.log") || true
  read -r scale < <(sed -n 's/^Alignment reference_from_model.*: scale \([^,]*\),.*/\1/p' \
    "$out/logs/compare_$(basename "$dir")_similarity.log") || true
  # "Surface <mesh>: ... RMS <m> m, ..." and "Dome fit ...: sagitta <m> m ...".
  read -r surface_rms < <(sed -n 's/^Surface .* RMS \([^ ]*\) m,.*/\1/p' \
    "$out/logs/compare_$(basename "$dir")_similarity.log") || true
  read -r sagitta < <(sed -n 's/^Dome fit.*: sagitta \([^ ]*\) m .*/\1/p' \
    "$out/logs/compare_$(basename "$dir")_similarity.log") || true
  if [[ -z "$abs" || -z "$sim_rmse" || -z "$scale" || -z "$surface_rms" ]]; then
    echo "compare_with_colmap: no camera RMSE or scale in the model_comparer" \
      "logs of $dir" >&2
    exit 1
  fi
  truth_extent=$extent
  # No dome fit (too few binned points): "nan".
  sagitta=${sagitta:-nan}
  rows+=("$(awk -v l="$label" -v a="$abs" -v s="$sim_rmse" -v e="$extent" \
    -v k="$scale" -v m="$surface_rms" -v d="$sagitta" -v t="$seconds" 'BEGIN {
      printf "%-60s %10.4f %12.6f %10.4f %+11.4f %10.5f %+10.5f %8.2f", l, a, s,
        100 * s / e, 100 * (k - 1), m, d, t }')")
  csv_rows+=("\"$label\",$abs,$sim_rmse,$(awk -v s="$sim_rmse" -v e="$extent" \
    'BEGIN { printf "%.6g", 100 * s / e }'),$(awk -v k="$scale" \
    'BEGIN { printf "%.6g", 100 * (k - 1) }'),$surface_rms,$sagitta,$seconds")
}

echo "[compare] model $model, navigation $sim/nav.csv," \
  "camera on the vehicle: ${mount_flags[*]:-uwcolmap defaults (mount down, no lever arm)}"
echo "[compare] bundle adjustment flags: ${ba_flags[*]:-the defaults of colmap 3.8}"

# Stock colmap: bundle adjustment, then alignment to the navigation.
start=$(now)
mkdir -p "$out/colmap_ba"
run colmap_bundle_adjuster "$colmap" bundle_adjuster --input_path "$model" \
  --output_path "$out/colmap_ba" "${ba_flags[@]}"
colmap_ba_s=$(seconds_since "$start")
colmap_aligner() {  # colmap_aligner OUT_NAME REFERENCE_FLAGS...
  local name=$1
  shift
  mkdir -p "$out/$name"
  run "$name" "$colmap" model_aligner --input_path "$out/colmap_ba" \
    --output_path "$out/$name" "$@" --ref_is_gps 0 --alignment_type custom \
    --robust_alignment_max_error "$max_error"
}
# The vehicle positions of nav.csv by image name (rows without one: none).
nav_table | awk -F, '
  NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
  col["image_name"] { print $col["image_name"], $col["x"], $col["y"], $col["z"] }
' > "$out/vehicle_positions.txt"
if [[ -s "$out/vehicle_positions.txt" ]]; then
  start=$(now)
  colmap_aligner colmap_vehicle --ref_images_path "$out/vehicle_positions.txt"
  add_row "colmap BA + model_aligner (vehicle positions)" "$out/colmap_vehicle" \
    "$(awk -v a="$colmap_ba_s" -v b="$(seconds_since "$start")" 'BEGIN { printf "%.2f", a + b }')"
fi
if [[ -n "$database" ]]; then
  cp "$database" "$out/database_priors.db"
  run pose_prior_importer "$uwcolmap" pose_prior_importer \
    --database_path "$out/database_priors.db" --nav "$sim/nav.csv" "${mount_flags[@]}"
  start=$(now)
  colmap_aligner colmap_camera --database_path "$out/database_priors.db"
  add_row "colmap BA + model_aligner (camera centres)" "$out/colmap_camera" \
    "$(awk -v a="$colmap_ba_s" -v b="$(seconds_since "$start")" 'BEGIN { printf "%.2f", a + b }')"
fi

# Ours without priors, then aligned to the navigation: the same two steps.
start=$(now)
run ours_bundle_adjuster "$uwcolmap" bundle_adjuster --input_path "$model" \
  --output_path "$out/ours_ba" "${ba_flags[@]}"
ours_ba_s=$(seconds_since "$start")
run ours_model_aligner "$uwcolmap" model_aligner --input_path "$out/ours_ba" \
  --output_path "$out/ours_no_priors" --nav "$sim/nav.csv" "${mount_flags[@]}"
add_row "ours BA (no priors) + model_aligner --nav" "$out/ours_no_priors" \
  "$(seconds_since "$start")"

start=$(now)
run ours_posterior "$uwcolmap" bundle_adjuster --input_path "$model" \
  --output_path "$out/ours_posterior" --nav "$sim/nav.csv" "${mount_flags[@]}" \
  --Nav.strategy posterior "${ba_flags[@]}"
add_row "ours --Nav.strategy posterior" "$out/ours_posterior" "$(seconds_since "$start")"

for weight in "${nav_weights[@]}"; do
  # Only the first weight's model goes into the chain: it alone needs the
  # covariance.
  weight_covariance=()
  if [[ "$weight" == "${nav_weights[0]}" ]]; then
    weight_covariance=("${covariance_flags[@]}")
  fi
  start=$(now)
  run "ours_prior_$weight" "$uwcolmap" bundle_adjuster --input_path "$model" \
    --output_path "$out/ours_prior_$weight" --nav "$sim/nav.csv" \
    "${mount_flags[@]}" --Nav.strategy prior --Nav.weight "$weight" \
    "${prior_flags[@]}" "${ba_flags[@]}" "${weight_covariance[@]}"
  seconds=$(seconds_since "$start")
  # The weight used: the noise-level estimate, or the L-curve's choice.
  chosen=$(sed -n 's/.*lambda = \([^ ]*\) px\/m.*/ = \1 px\/m/p' \
    "$out/logs/ours_prior_$weight.log" | tail -n 1)
  add_row "ours --Nav.strategy prior --Nav.weight $weight$chosen$attitude_label" \
    "$out/ours_prior_$weight" "$seconds"
done

# The whole chain: dense mesh, laser scale on it, the model in metres. The
# laser scale's Monte Carlo re-samples the model from its covariance: the
# navigation-fused model's own (bundle_adjuster --BA.covariance 1, gauge
# priors), colmap's under held coordinates as colmap fixes them.
chain_rows=()
chain() {  # chain LABEL MODEL_DIR
  local label=$1 dir=$2 name work start dense_s laser_s covariance
  name=$(basename "$dir")
  work="$out/chain/$name"
  mkdir -p "$work"
  covariance="$dir/covariance"
  if [[ ! -f "$covariance/samples.bin" ]]; then
    covariance="$work/covariance"
    run "covariance_$name" "$uwcolmap" covariance_estimator --input_path "$dir" \
      --output_path "$covariance" --Covariance.gauge held \
      --Covariance.samples "$model_draws" "${ba_flags[@]}"
  fi
  start=$(now)
  run "dense_mesher_$name" "$uwcolmap" dense_mesher --input_path "$dir" \
    --image_path "$sim/images" --output_path "$work/mesh.ply" \
    --DenseMesher.max_image_size "$max_image_size"
  dense_s=$(seconds_since "$start")
  run "compare_${name}_dense" "$uwcolmap" model_comparer --input_path "$dir" \
    --truth_dir "$sim" --dense_mesh_path "$work/mesh.ply" \
    --output_path "$work/compare.json"
  start=$(now)
  run "laserscale_detect_$name" "$laserscale" detect \
    --images "$sim/laser_images" --lasers "$sim/lasers.json" \
    --input_path "$dir" --out "$work/spots.json" --overlays "$work/overlays"
  run "laserscale_localize_$name" "$laserscale" localize \
    --database_path "$laser_database" --input_path "$dir" \
    --image_list_path "$out/laser_list.txt" --out "$work/poses.json"
  run "laserscale_estimate_$name" "$laserscale" estimate --mesh "$work/mesh.ply" \
    --poses "$work/poses.json" --spots "$work/spots.json" \
    --lasers "$sim/lasers.json" --overlays "$work/overlays" --mc "$mc" \
    --covariance "$covariance" --input_path "$dir" --out "$work/report"
  run "laserscale_apply_$name" "$laserscale" apply --input_path "$dir" \
    --scale "$work/report/scale.json" --output_path "$out/${name}_laser" \
    --input_mesh "$work/mesh.ply" --output_mesh "$out/${name}_laser/mesh.ply"
  laser_s=$(seconds_since "$start")
  add_row "$label + dense_mesher + laserscale apply" "$out/${name}_laser" \
    "$(awk -v a="$dense_s" -v b="$laser_s" 'BEGIN { printf "%.2f", a + b }')"
  chain_rows+=("$(python3 - "$label" "$work" "$dense_s" "$laser_s" <<'PY'
import json, sys
label, work, dense_s, laser_s = sys.argv[1:]
scale = json.load(open(work + "/report/scale.json"))
compare = json.load(open(work + "/compare.json"))
truth = compare["alignment"]["reference_from_model"]["scale"]
dense = compare["dense_surface"]
s, (low, high) = scale["scale"], scale["ci95"]
shares = scale.get("variance_by_source", {})
share = lambda source: 100 * shares.get(source, {}).get("share", 0.0)
z = scale.get("navigation", {}).get("z")
print('"%s",%.6f,%.6f,%.6f,%.6f,%+.4f,%d,%d,%d,%.6f,%.4f,%.2f,%s,%s,%d,%.1f,%.1f,%.1f,%.1f,%s' % (
    label, s, low, high, truth, 100 * (s / truth - 1), low <= truth <= high,
    scale["num_accepted"], scale["num_images"], dense["median_distance"],
    100 * dense["median_over_camera_scene_distance"], 100 * dense["coverage"],
    dense_s, laser_s, scale["model_draws"]["count"], share("features"),
    share("spots"), share("calibration"), share("model"),
    "" if z is None else "%.3f" % z))
PY
)")
}
if [[ -n "$laser_database" ]]; then
  find "$sim/laser_images" -maxdepth 1 -type f ! -name '*_aux.*' -printf '%f\n' |
    sort > "$out/laser_list.txt"
  if [[ -n "$database" ]]; then
    chain "colmap BA + model_aligner (camera centres)" "$out/colmap_camera"
  else
    chain "colmap BA + model_aligner (vehicle positions)" "$out/colmap_vehicle"
  fi
  chain "ours --Nav.strategy prior --Nav.weight ${nav_weights[0]}$attitude_label" \
    "$out/ours_prior_${nav_weights[0]}"
  {
    echo "method,laser_scale,ci95_low,ci95_high,true_scale,scale_error_percent,truth_in_ci95,accepted_images,laser_images,mesh_median_m,mesh_median_percent_of_range,mesh_coverage_percent,dense_s,laser_s,model_draws,features_share_percent,spots_share_percent,calibration_share_percent,model_share_percent,navigation_z"
    printf '%s\n' "${chain_rows[@]}"
  } > "$out/chain.csv"
fi

{
  echo "Truth: $sim/truth, camera extent $truth_extent m." \
    "colmap model_aligner inlier threshold $max_error m."
  echo "Bundle adjustment alone: colmap $colmap_ba_s s, ours (no priors)" \
    "$ours_ba_s s, ratio $(awk -v a="$ours_ba_s" -v b="$colmap_ba_s" \
      'BEGIN { printf "%.2f", a / b }') (one run; bench/results/ba_speed.json has medians)."
  printf "%-60s %10s %12s %10s %11s %10s %10s %8s\n" "method" "abs_rmse_m" \
    "sim_rmse_m" "sim_%ext" "scale_err_%" "surf_rms_m" "sagitta_m" "time_s"
  printf '%s\n' "${rows[@]}"
} | tee "$out/table.txt"
{
  echo "method,abs_rmse_m,sim_rmse_m,sim_percent_of_extent,scale_error_percent,surface_rms_m,sagitta_m,time_s"
  printf '%s\n' "${csv_rows[@]}"
} > "$out/table.csv"
if [[ -n "$laser_database" ]]; then
  echo "Whole chain (dense_mesher at $max_image_size px, laser scale with $mc Monte Carlo samples; $out/chain.csv):"
  awk -F, 'NR > 1 { gsub(/"/, "", $1)
    printf "  %s: s = %.5f [%.5f, %.5f], truth %.5f, error %+.3f %% (%s), %d of %d laser images; mesh median %.2f mm = %.3f %% of the range, coverage %.1f %%; variance: features %.0f %%, spots %.0f %%, calibration %.0f %%, model %.0f %%%s\n",
      $1, $2, $3, $4, $5, $6, $7 ? "inside its 95 % interval" : "OUTSIDE its 95 % interval",
      $8, $9, 1000 * $10, $11, $12, $16, $17, $18, $19,
      $20 == "" ? "" : sprintf("; against the navigation z = %+.2f", $20) }' "$out/chain.csv"
fi
