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

# D4: a string length of 0 or INT32_MIN in the header or the footer, the integrity checks
# recomputed so that only the reader's own bounds can catch it. A bad header: refused, naming
# the event and its byte. A bad footer: the record is used without it.
python3 "$edit" run.lcm bad_header.lcm i32 AMBDROP_RECORD_HEADER 8 0 recheck
rc=0
"$tool" replay bad_header.lcm --out bad_header --quiet 2>bad_header.err || rc=$?
[[ $rc -eq 1 ]] || fail "a header string of length 0: exit $rc: $(cat bad_header.err)"
grep -q "not an ambdrop run record.*event 0 at byte 0: the header message does not decode" \
  bad_header.err || fail "unclear error for a bad header: $(cat bad_header.err)"
for length in 0 -2147483648; do
  python3 "$edit" run.lcm bad_footer.lcm i32 AMBDROP_RECORD_FOOTER 8 $length recheck
  rc=0
  "$tool" replay bad_footer.lcm --out bad_footer --quiet 2>bad_footer.err || rc=$?
  [[ $rc -eq 0 ]] || fail "a footer string of length $length: exit $rc: $(cat bad_footer.err)"
  grep -q "event [0-9]* at byte [0-9]*: the footer message does not decode" bad_footer.err ||
    fail "no warning of the bad footer: $(cat bad_footer.err)"
done

echo "hostile records: ok"
