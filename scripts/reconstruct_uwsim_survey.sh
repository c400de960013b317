#!/usr/bin/env bash
# Generates a uwsim survey and reconstructs it with stock colmap 3.8 on the
# CPU, giving colmap the true calibration as a user would.
#
#   reconstruct_uwsim_survey.sh UWSIM_BINARY OUTPUT_DIR [uwsim generate flags]
#
# OUTPUT_DIR/sim/      uwsim's output (images/, nav.csv, truth/)
# OUTPUT_DIR/database.db, OUTPUT_DIR/sparse/N, OUTPUT_DIR/logs/
# OUTPUT_DIR/mount_flags.txt  the camera on the vehicle as uwsim mounted it
#                      (truth/sim.json), as uwcolmap flags: --mount
#                      down|starboard --lever_arm X,Y,Z --boresight R,P,Y
#
# MATCHER=spatial (environment; default exhaustive) matches each image with
# its nearest ones by the navigation (scripts/colmap_sparse.sh; UWCOLMAP is
# the uwcolmap binary).
set -euo pipefail
uwsim=$1
out=$2
shift 2
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"

marker=".uwmetric-uwsim-survey"
if [[ -e "$out" && -n "$(ls -A "$out" 2>/dev/null)" && ! -f "$out/$marker" ]]; then
  echo "reconstruct_uwsim_survey: $out exists and was not made by this" \
    "script; choose a new or empty folder" >&2
  exit 1
fi
rm -rf "$out"
mkdir -p "$out"
touch "$out/$marker"

start=$SECONDS
"$uwsim" generate --out "$out/sim" "$@" | tail -n 1
echo "[uwsim] generate: $((SECONDS - start)) s"
python3 - "$out/sim/truth/sim.json" > "$out/mount_flags.txt" <<'PY'
import json, sys
sim = json.load(open(sys.argv[1]))
survey = sim["survey_options"]
triple = lambda key: ",".join("%.10g" % v for v in survey[key])
print("--mount %s --lever_arm %s --boresight %s"
      % (sim["truth"]["camera_mount"], triple("lever_arm_m"),
         triple("boresight_deg")))
PY
# truth/cameras.txt: "1 MODEL WIDTH HEIGHT PARAMS..." after three comments.
read -r _ model _ _ params < <(grep -v '^#' "$out/sim/truth/cameras.txt" | head -n 1)
NAV="$out/sim/nav.csv" NAV_FLAGS="$(cat "$out/mount_flags.txt")" \
  bash "$here/colmap_sparse.sh" "$out/sim/images" "$out" "$model" "${params// /,}"
