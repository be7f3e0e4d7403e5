#!/usr/bin/env bash
# Run records edited the way a broken or hostile writer would leave them (tests/cli/
# record_edit.py): each is refused or used up to the damage, with a warning that says where, and
# never drives the replay beyond the run it records.
# Usage: hostile_records.sh AMBDROP_BINARY SOURCE_DIR
set -euo pipefail
tool=$1
source_dir=$2
edit=$source_dir/tests/cli/record_edit.py
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() {
  echo "FAIL: $*" >&2
  exit 1
}
cd "$work"

# 0.05 s at 5 us: 10000 steps.
"$tool" sim "$source_dir/configs/jarroux2019_industrial_pid.toml" --set simulation.duration_s=0.05 \
  --set trigger.time_s=0.01 --out sim --record run.lcm -q || fail "sim --record failed"
total_steps=10000

# D1: cut before the footer, the last (unchecked) state event at step 1e12. The replay ends
# within the run (a bound by a timeout: without one it writes gigabytes), and so does an
# exported profile.
python3 "$edit" run.lcm huge_step.lcm cut-after AMBDROP_STATE i64 AMBDROP_STATE 16 1e12
rc=0
timeout 20 "$tool" replay huge_step.lcm --out huge --quiet 2>huge.err || rc=$?
[[ $rc -eq 0 ]] || fail "replay of a record with a huge unchecked step exited $rc: $(cat huge.err)"
grep -q "step 1000000000000 is beyond the run's configured $total_steps steps" huge.err ||
  fail "no warning names the step beyond the run: $(cat huge.err)"
python3 - huge/summary.json $total_steps <<'PY' || fail "the replay ran beyond the record"
import json, sys
s = json.load(open(sys.argv[1]))
assert 0 < s["steps"] <= int(sys.argv[2]), s["steps"]
assert s["damaged"] is True, s
PY
"$tool" replay huge_step.lcm --export-profile huge.toml -q 2>/dev/null ||
  fail "export of the cut record failed"
python3 - huge.toml <<'PY' || fail "the exported profile lasts beyond the record"
import sys, tomllib
d = tomllib.load(open(sys.argv[1], "rb"))["simulation"]["duration_s"]
assert 0 < d <= 0.05, d
PY

echo "hostile records: ok"
