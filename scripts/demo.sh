#!/usr/bin/env bash
# uwmetric's main job, end to end on the built-in synthetic scene.
#
# Today (foundation): sets up and builds (scripts/setup.sh), renders the test
# scene with known camera poses, reconstructs it with stock colmap 3.8 on the
# CPU, and shows what uwmetric reads from colmap's files: the database's
# schema and contents, the model_analyzer figures, a lossless BIN -> BIN
# round trip, TXT output, and the model's camera positions against the truth
# after colmap's similarity alignment.
#
#   bash scripts/demo.sh [OUTPUT_DIR]      # default: out/demo
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${1:-$root/out/demo}"
bin="${UW_BUILD_DIR:-$root/build}/bin"

bash "$root/scripts/setup.sh"
start=$SECONDS

echo
echo "== 1. Render the test scene and reconstruct it with stock colmap"
bash "$root/scripts/reconstruct_test_scene.sh" "$bin/render_test_scene" "$out"

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
echo "== 4. Camera positions vs truth (colmap model_aligner, similarity)"
mkdir -p "$out/aligned"
if ! colmap model_aligner --input_path "$out/sparse/0" --output_path "$out/aligned" \
  --ref_images_path "$out/scene/truth/ref_images.txt" --ref_is_gps 0 \
  --robust_alignment_max_error 0.05 > "$out/logs/model_aligner.log" 2>&1; then
  cat "$out/logs/model_aligner.log" >&2
  exit 1
fi
grep -i "alignment error" "$out/logs/model_aligner.log"

echo
echo "Demo finished in $((SECONDS - start)) s; outputs in $out"
