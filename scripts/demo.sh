#!/usr/bin/env bash
# uwmetric's main job, end to end on the built-in synthetic survey, on the
# CPU:
#
#   1. uwsim: the default world (a rough seafloor) and survey (a lawnmower
#      pass with navigation, laser images and ground truth); stock colmap
#      3.8: features, matching, mapper
#   2. what uwmetric reads from colmap's files (database, model, a lossless
#      BIN round trip)
#   3. the laser images, added to a copy of colmap's database
#   4. the whole chain, stock colmap vs ours (scripts/compare_with_colmap.sh
#      --laser_database): stock colmap bundle_adjuster + model_aligner onto
#      the navigation against uwcolmap pose_prior_importer + bundle_adjuster
#      --Nav.strategy prior; then for both models uwcolmap dense_mesher,
#      laserscale detect / localize / estimate on that mesh, laserscale
#      apply (model and mesh in metres), each measured against the truth
#
# and ends with one summary: registered images, the scale with its 95 %
# interval and its error against the truth, the stock-vs-ours table (camera
# RMSE, surface RMS and doming sagitta against the truth), the dense mesh's
# accuracy and coverage, and the time of every stage (also in
# OUTPUT_DIR/timings.csv); then `uwcolmap survey_report` puts it all in
# OUTPUT_DIR/report/index.html. About 12 minutes on 2 cores.
#
#   bash scripts/demo.sh [OUTPUT_DIR] [flags]     # default: out/demo
#
# flags (for tests and quick looks; the defaults are the full demo):
#   --survey DIR          reuse a survey reconstructed by
#                         scripts/reconstruct_uwsim_survey.sh (copied)
#                         instead of stage 1
#   --laser_database DB   reuse the laser images' database of
#                         scripts/add_laser_images.sh (copied)
#   --max_image_size N    dense_mesher's depth maps (default 512)
#   --mc N                Monte Carlo samples of the scale (default 5000)
#   --no_setup            do not run scripts/setup.sh (already built)
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="${UW_BUILD_DIR:-$root/build}/bin"
out="$root/out/demo"
if [[ $# -gt 0 && $1 != --* ]]; then
  out=$1
  shift
fi
survey=""
laser_database=""
max_image_size=512
mc=5000
setup=1
while [[ $# -gt 0 ]]; do
  case $1 in
    --survey) survey=$2; shift 2 ;;
    --laser_database) laser_database=$2; shift 2 ;;
    --max_image_size) max_image_size=$2; shift 2 ;;
    --mc) mc=$2; shift 2 ;;
    --no_setup) setup=0; shift ;;
    *)
      sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//' >&2
      echo "demo: unknown flag $1" >&2
      exit 2
      ;;
  esac
done

if ((setup)); then
  # Only the programs the demo runs, not the tests and benchmarks.
  bash "$root/scripts/setup.sh" uwcolmap laserscale uwsim
fi
start=$SECONDS

stage_names=()
stage_seconds=()
stage() {  # stage NAME COMMAND...: run it and record its wall time
  local name=$1 t0=$SECONDS
  shift
  "$@"
  stage_names+=("$name")
  stage_seconds+=($((SECONDS - t0)))
}
fail() {
  echo "demo: $*" >&2
  exit 1
}

echo
echo "== 1. The default world and survey (uwsim), reconstructed by stock colmap"
if [[ -n "$survey" ]]; then
  for f in sim sparse/0 database.db; do
    [[ -e "$survey/$f" ]] || fail "--survey $survey has no $f"
  done
  marker=".uwmetric-uwsim-survey"
  if [[ -e "$out" && -n "$(ls -A "$out" 2>/dev/null)" && ! -f "$out/$marker" ]]; then
    fail "$out exists and was not made by this script; choose a new or empty folder"
  fi
  rm -rf "$out"
  mkdir -p "$out/logs"
  touch "$out/$marker"
  copy_survey() {
    cp -r "$survey/sim" "$survey/sparse" "$out/"
    # Through SQLite, so that a write-ahead log is included.
    sqlite3 "$survey/database.db" ".backup '$out/database.db'"
  }
  stage "copy the survey" copy_survey
  echo "reused $survey"
else
  stage "uwsim generate + stock colmap (features, matching, mapper)" \
    bash "$root/scripts/reconstruct_uwsim_survey.sh" "$bin/uwsim" "$out"
fi
sim="$out/sim"
registered=$("$bin/uwcolmap" model_analyzer --path "$out/sparse/0" |
  sed -n 's/^Registered images: //p')
total=$(find "$sim/images" -maxdepth 1 -type f | wc -l)
echo "registered images: $registered of $total"

echo
echo "== 2. What uwmetric reads from colmap's database and model"
"$bin/uwcolmap" database_analyzer --database_path "$out/database.db" \
  > "$out/logs/database_analyzer.log"
head -n 12 "$out/logs/database_analyzer.log"
echo "... (all of it: $out/logs/database_analyzer.log)"
"$bin/uwcolmap" model_analyzer --path "$out/sparse/0"
"$bin/uwcolmap" model_converter --input_path "$out/sparse/0" \
  --output_path "$out/uw_bin" --output_type BIN > /dev/null
for f in cameras images points3D; do
  cmp -s "$out/sparse/0/$f.bin" "$out/uw_bin/$f.bin" ||
    fail "$f.bin differs after uwmetric's read + write"
done
echo "cameras.bin, images.bin, points3D.bin: byte-identical after uwmetric's read + write"
# Stock colmap's model, aligned to the truth by a similarity: the best a
# stock colmap user could do with perfect ground control.
"$bin/uwcolmap" model_comparer --input_path "$out/sparse/0" --truth_dir "$sim" \
  > "$out/logs/compare_colmap_mapper_similarity.log"

echo
echo "== 3. The laser images, added to a copy of colmap's database"
laser="$out/laser"
if [[ -n "$laser_database" ]]; then
  [[ -f "$laser_database" ]] || fail "--laser_database $laser_database does not exist"
  mkdir -p "$laser/logs"
  stage "laser images: copy the database" \
    sqlite3 "$laser_database" ".backup '$laser/database.db'"
else
  stage "laser images: colmap features + matching" \
    bash "$root/scripts/add_laser_images.sh" "$out" "$laser"
fi

echo
echo "== 4. The whole chain, stock colmap vs ours (scripts/compare_with_colmap.sh):"
echo "   stock colmap bundle_adjuster + model_aligner onto the navigation, against"
echo "   uwcolmap pose_prior_importer + bundle_adjuster --Nav.strategy prior; then"
echo "   for both: uwcolmap dense_mesher (CPU), laserscale detect / localize /"
echo "   estimate on that mesh, laserscale apply (model and mesh in metres)"
echo "(camera on the vehicle as uwsim places it; the navigation has uwsim's USBL-like"
echo " errors, ~1 m per image on this 6 m survey: see docs/uwcolmap.md#bundle_adjuster)"
compare_start=$SECONDS
bash "$root/scripts/compare_with_colmap.sh" "$sim" "$out/sparse/0" \
  "$out/compare" --mount down --lever_arm 0.6,0,-0.3 --boresight 0.3,-0.5,0.8 \
  --laser_database "$laser/database.db" \
  --DenseMesher.max_image_size "$max_image_size" --mc "$mc"
# Its steps (compare/timings.csv), grouped into the stages of the chain.
while IFS=, read -r name seconds; do
  stage_names+=("$name")
  stage_seconds+=("$seconds")
done < <(awk -F, 'NR > 1 {
    if ($1 ~ /^(colmap_|pose_prior)/) g = "stock colmap bundle_adjuster + model_aligner (+ pose_prior_importer)"
    else if ($1 ~ /^ours_/) g = "uwcolmap bundle_adjuster (no priors + model_aligner; posterior; prior)"
    else if ($1 ~ /^dense_mesher_/) g = "uwcolmap dense_mesher (stock colmap'"'"'s model and ours)"
    else if ($1 ~ /^laserscale_(detect|localize|estimate)/) g = "laserscale detect + localize + estimate (both models)"
    else if ($1 ~ /^laserscale_apply/) g = "laserscale apply (both models)"
    else g = "uwcolmap model_comparer against the truth"
    if (!(g in t)) order[n++] = g
    t[g] += $2 }
  END { for (k = 0; k < n; ++k) printf "%s,%d\n", order[k], t[order[k]] + 0.5 }' \
  "$out/compare/timings.csv")
model="$out/compare/ours_prior_auto"
chain="$out/compare/chain/ours_prior_auto"
metric="$out/compare/ours_prior_auto_laser"
echo "navigation-fused model (lambda from the noise levels): $model (ba_report.json)"
echo "its dense mesh: $chain/mesh.ply; in metres: $metric (model and mesh.ply)"
echo "(the chain took $((SECONDS - compare_start)) s)"

# ---------------------------------------------------------------- summary
total_s=$((SECONDS - start))
{
  echo "stage,seconds"
  for i in "${!stage_names[@]}"; do
    echo "\"${stage_names[$i]}\",${stage_seconds[$i]}"
  done
  echo "\"total\",$total_s"
} > "$out/timings.csv"

# comparer_figures LOG: "camera_rmse_m surface_rms_m sagitta_m scale" of a
# model_comparer log (similarity alignment).
comparer_figures() {
  awk '
    /^Alignment reference_from_model/ { s = $0; sub(/.*: scale /, "", s); sub(/,.*/, "", s) }
    /^Camera centres: RMSE/ { r = $4 }
    /^Surface .*signed distance/ { m = $0; sub(/.*RMS /, "", m); sub(/ m,.*/, "", m) }
    /^Dome fit/ { d = $0; sub(/.*sagitta /, "", d); sub(/ m .*/, "", d) }
    END { printf "%s %s %s %s\n", r, m, d, s }' "$1"
}
row() {  # row LABEL LOG SCALE_MEANING
  local rmse surf sag scale
  read -r rmse surf sag scale < <(comparer_figures "$2")
  [[ -n "$rmse" && -n "$scale" ]] || fail "no figures in $2"
  awk -v l="$1" -v r="$rmse" -v m="$surf" -v d="$sag" -v s="$scale" -v k="$3" 'BEGIN {
    e = (k == "metric") ? sprintf("%+.3f %%", 100 * (s - 1)) : "(arbitrary)"
    printf "  %-50s %12.5f %12.5f %+12.5f %12s\n", l, r, m, d, e }'
}

read -r s low high < <(python3 -c '
import json, sys
j = json.load(open(sys.argv[1]))
print(j["scale"], j["ci95"][0], j["ci95"][1])' "$chain/report/scale.json")
# The truth: the scale of the similarity that takes the navigation-fused
# model onto uwsim's true cameras.
true_scale=$(python3 -c '
import json, sys
print(json.load(open(sys.argv[1]))["alignment"]["reference_from_model"]["scale"])' \
  "$chain/compare.json")
read -r accuracy < <(python3 -c '
import json, sys
d = json.load(open(sys.argv[1]))["dense_surface"]
print("median %.2f mm = %.3f %% of the %.2f m camera-scene distance, coverage %.1f %% of %.1f m^2" % (
    1000 * d["median_distance"], 100 * d["median_over_camera_scene_distance"],
    d["camera_scene_distance"], 100 * d["coverage"], d["observed_area"]))' \
  "$chain/compare.json")

echo
echo "================================ Summary ================================"
echo "Outputs in $out"
echo "Registered images: $registered of $total (stock colmap mapper)"
awk -v s="$s" -v a="$low" -v b="$high" -v t="$true_scale" 'BEGIN {
  e = s / t - 1
  inside = (a <= t && t <= b) ? "inside" : "OUTSIDE"
  printf "Laser scale of the navigation-fused model: s = %.5f, 95 %% interval [%.5f, %.5f]\n", s, a, b
  printf "  truth %.5f: error %+.3f %% (the truth is %s the interval)\n", t, 100 * e, inside }'
echo "Dense mesh of the navigation-fused model vs the true surface: $accuracy"
echo "Against uwsim's truth, each model aligned by a similarity (a camera-centre fit):"
printf "  %-50s %12s %12s %12s %12s\n" "model" "camera_rmse_m" "surf_rms_m" \
  "sagitta_m" "scale_error"
row "stock colmap mapper" "$out/logs/compare_colmap_mapper_similarity.log" arbitrary
row "stock colmap BA + model_aligner (camera centres)" \
  "$out/compare/logs/compare_colmap_camera_similarity.log" metric
row "  + dense_mesher + laserscale apply" \
  "$out/compare/logs/compare_colmap_camera_laser_similarity.log" metric
row "ours: bundle_adjuster --Nav.strategy prior" \
  "$out/compare/logs/compare_ours_prior_auto_similarity.log" metric
row "  + dense_mesher + laserscale apply" \
  "$out/compare/logs/compare_ours_prior_auto_laser_similarity.log" metric
echo "  (scale_error: s_similarity - 1 of a model meant to be in metres;"
echo "   sagitta < 0: a dome; absolute errors and every row: $out/compare/table.txt)"
echo "Time per stage (s):"
for i in "${!stage_names[@]}"; do
  printf "  %-78s %5d\n" "${stage_names[$i]}" "${stage_seconds[$i]}"
done
printf "  %-78s %5d\n" "total (after setup)" "$total_s"

# The survey report: everything above in one self-contained folder.
"$bin/uwcolmap" survey_report --input_path "$model" \
  --ba_report "$model/ba_report.json" --nav "$sim/nav.csv" \
  --laser_report "$chain/report" --compare_table "$out/compare/table.csv" \
  --dense_comparison "$chain/compare.json" --mesh "$chain/mesh.ply" \
  --timings "$out/timings.csv" --truth_dir "$sim" \
  --covariance "$model/covariance" --output_path "$out/report" \
  > "$out/logs/survey_report.log" 2>&1 ||
  { cat "$out/logs/survey_report.log"; fail "survey_report failed"; }
echo "Survey report: $out/report/index.html"
echo "Laser report: $chain/report/index.html"
