#!/usr/bin/env bash
# uwmetric's main job, end to end on the built-in synthetic survey.
#
# Today: sets up and builds (scripts/setup.sh); generates the default uwsim
# world and survey (a rough seafloor, a lawnmower pass, navigation with
# USBL-like errors, ground truth); reconstructs it with stock colmap 3.8 on
# the CPU; and shows what uwmetric reads from colmap's files (database
# schema and contents, model_analyzer figures, a lossless BIN -> BIN round
# trip) and how far colmap's cameras are from the truth after colmap's own
# similarity alignment; then runs the same model through stock colmap's
# bundle_adjuster + model_aligner and through uwmetric's navigation-fused
# bundle adjuster and prints one comparison table against the truth; then
# measures the navigation-fused model's scale with the laser images
# (laserscale detect / localize / estimate) and ends with that scale, its
# 95 % interval, the truth and the report's path.
# Takes about 11 minutes on 2 cores.
#
#   bash scripts/demo.sh [OUTPUT_DIR]      # default: out/demo
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${1:-$root/out/demo}"
bin="${UW_BUILD_DIR:-$root/build}/bin"

bash "$root/scripts/setup.sh"
start=$SECONDS

echo
echo "== 1. Generate the default world and survey (uwsim), reconstruct it with stock colmap"
bash "$root/scripts/reconstruct_uwsim_survey.sh" "$bin/uwsim" "$out"

echo
echo "== 2. What uwmetric reads from colmap's database and model"
"$bin/uwcolmap" database_analyzer --database_path "$out/database.db"
echo
"$bin/uwcolmap" model_analyzer --path "$out/sparse/0"

echo
echo "== 3. Round trips through uwmetric's reader and writer"
"$bin/uwcolmap" model_converter --input_path "$out/sparse/0" \
  --output_path "$out/uw_bin" --output_type BIN
"$bin/uwcolmap" model_converter --input_path "$out/sparse/0" \
  --output_path "$out/uw_txt" --output_type TXT
for f in cameras images points3D; do
  if cmp -s "$out/sparse/0/$f.bin" "$out/uw_bin/$f.bin"; then
    echo "$f.bin: byte-identical after read + write ($(stat -c %s "$out/uw_bin/$f.bin") bytes)"
  else
    echo "$f.bin: DIFFERS after read + write" >&2
    exit 1
  fi
done
echo "text model written to $out/uw_txt"

echo
echo "== 4. colmap's cameras vs uwsim's truth (colmap model_aligner, similarity)"
mkdir -p "$out/aligned"
if ! colmap model_aligner --input_path "$out/sparse/0" --output_path "$out/aligned" \
  --ref_images_path "$out/sim/truth/ref_images.txt" --ref_is_gps 0 \
  --robust_alignment_max_error 0.1 > "$out/logs/model_aligner.log" 2>&1; then
  cat "$out/logs/model_aligner.log" >&2
  exit 1
fi
registered=$("$bin/uwcolmap" model_analyzer --path "$out/sparse/0" | sed -n 's/^Registered images: //p')
total=$(ls "$out/sim/images" | wc -l)
echo "registered images: $registered of $total"
grep -i "alignment error" "$out/logs/model_aligner.log" | sed 's/^=> //; s/$/ [m]/'

echo
echo "== 5. Navigation: stock colmap BA + model_aligner vs uwmetric's navigation-fused BA"
echo "(camera on the vehicle as uwsim places it; the navigation has uwsim's USBL-like"
echo " errors, ~1 m per image on this 6 m survey: see docs/uwcolmap.md#bundle_adjuster)"
rm -rf "$out/compare"
bash "$root/scripts/compare_with_colmap.sh" "$out/sim" "$out/sparse/0" \
  "$out/compare" --mount down --lever_arm 0.6,0,-0.3 --boresight 0.3,-0.5,0.8
echo "navigation-fused model (lambda from the noise levels): $out/compare/ours_prior_auto (ba_report.json)"

echo
echo "== 6. Laser scale of the navigation-fused model (laserscale)"
model="$out/compare/ours_prior_auto"
laser="$out/laser"
bash "$root/scripts/add_laser_images.sh" "$out" "$laser"
"$bin/laserscale" detect --images "$out/sim/laser_images" \
  --lasers "$out/sim/lasers.json" --input_path "$model" \
  --out "$laser/spots.json" --overlays "$laser/overlays" | tail -n 1
"$bin/laserscale" localize --database_path "$laser/database.db" \
  --input_path "$model" --image_list_path "$laser/laser_list.txt" \
  --out "$laser/poses.json" | tail -n 1
# No dense mesh yet: a heightfield of the sparse points (docs/laserscale.md).
"$bin/laserscale" sparse_surface --input_path "$model" \
  --output_path "$laser/surface.ply"
"$bin/laserscale" estimate --mesh "$laser/surface.ply" \
  --poses "$laser/poses.json" --spots "$laser/spots.json" \
  --lasers "$out/sim/lasers.json" --overlays "$laser/overlays" \
  --out "$laser/report" > "$laser/estimate.log"
summary=$(tail -n 1 "$laser/estimate.log")
true_scale=$(sed -n 's/^Alignment reference_from_model.*: scale \([^,]*\),.*/\1/p' \
  "$out/compare/logs/compare_ours_prior_auto_similarity.log" | head -n 1)

echo
echo "Demo finished in $((SECONDS - start)) s; outputs in $out"
echo "Scale of the navigation-fused model from the laser images:"
echo "  ${summary#\[estimate\] }"
echo "  truth (similarity of the model to uwsim's truth): s = $true_scale"
echo "  report: $laser/report/index.html"
