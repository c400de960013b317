# Sourced by the scripts that run stock colmap:
#   run_step LOG_DIR NAME COMMAND...
# runs one step with its output in LOG_DIR/NAME.log, prints how long it
# took, and on failure shows the log and exits.
run_step() {
  local logs=$1 name=$2
  shift 2
  local start=$SECONDS
  if ! "$@" > "$logs/$name.log" 2>&1; then
    cat "$logs/$name.log"
    echo "$(basename "$0"): step '$name' failed" >&2
    exit 1
  fi
  echo "[colmap] $name: $((SECONDS - start)) s"
}
