#!/usr/bin/env bash
# An output that cannot be written (timeseries.csv on a full disk: a link to /dev/full) fails
# every command that writes summary.json: exit 1, an error on stderr, and a summary.json whose
# status is not "ok" and which says what failed.
# Usage: hostile_outputs.sh AMBDROP_BINARY SOURCE_DIR
set -euo pipefail
tool=$1
source_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() {
  echo "FAIL: $*" >&2
  exit 1
}
[[ -w /dev/full ]] || {
  echo "skipped: no writable /dev/full to stand for a full disk"
  exit 77
}
cd "$work"
configs=$source_dir/configs
short=(--set simulation.duration_s=0.05)

"$tool" sim "$configs/jarroux2019_industrial_pid.toml" "${short[@]}" --set trigger.time_s=0.01 \
  --out record --record run.lcm -q || fail "the record for the replay case failed"

# Runs each command with its timeseries.csv on /dev/full; $1 names the case.
check() {
  local name=$1
  shift
  mkdir -p "$name"
  ln -s /dev/full "$name/timeseries.csv"
  local rc=0
  timeout 60 "$tool" "$@" --out "$name" -q >/dev/null 2>"$name.err" || rc=$?
  [[ $rc -eq 1 ]] || fail "$name: exit $rc with timeseries.csv on a full disk: $(cat "$name.err")"
  grep -q "error: cannot write '$name/timeseries.csv'" "$name.err" ||
    fail "$name: no error names timeseries.csv: $(cat "$name.err")"
  python3 - "$name/summary.json" <<'PY' || fail "$name: summary.json says ok: $(cat "$name/summary.json")"
import json, sys
s = json.load(open(sys.argv[1]))
assert s["status"] == "output_error", s["status"]
assert "timeseries.csv" in s["output_error"], s["output_error"]
PY
}

check sim sim "$configs/jarroux2019_industrial_pid.toml" "${short[@]}"
check scenario sim --scenario "$configs/scenarios/power_dip_relevitation.toml" "${short[@]}"
check replay replay run.lcm
check hil hil "$configs/jarroux2019_industrial_pid.toml" "${short[@]}" --virtual-clock

echo "hostile outputs: ok"
