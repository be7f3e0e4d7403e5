#!/usr/bin/env bash
# `ambdrop sim --record` then `ambdrop replay`: the replay reproduces timeseries.csv byte for
# byte, says the sensor outputs are identical, and a second replay gives the same bytes again;
# a changed config replays with a difference report (exit 0; with --strict exit 4); a truncated
# record replays with a warning that says where; garbage is refused with a clear error.
# Usage: record_replay.sh AMBDROP_BINARY SOURCE_DIR
set -euo pipefail

tool=$1
source_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() {
  echo "FAIL: $*" >&2
  exit 1
}

for config in jarroux2019_industrial_pid.toml jarroux2019_industrial.toml; do
  name=${config%.toml}
  "$tool" sim "$source_dir/configs/$config" --set simulation.duration_s=0.3 --set trigger.time_s=0.05 \
    --out "$work/$name/sim" --record "$work/$name/run.lcm" --quiet ||
    fail "$config: sim --record failed"
  [[ -s $work/$name/run.lcm ]] || fail "$config: no record written"
  "$tool" replay "$work/$name/run.lcm" --out "$work/$name/replay" >"$work/$name/replay.txt" ||
    fail "$config: replay failed: $(cat "$work/$name/replay.txt")"
  cmp "$work/$name/sim/timeseries.csv" "$work/$name/replay/timeseries.csv" ||
    fail "$config: the replayed timeseries.csv differs from the recorded run's"
  "$tool" replay "$work/$name/run.lcm" --out "$work/$name/replay2" --quiet
  cmp "$work/$name/replay/timeseries.csv" "$work/$name/replay2/timeseries.csv" ||
    fail "$config: two replays differ"
  grep -q '"identical": true' "$work/$name/replay/summary.json" ||
    fail "$config: summary.json does not say identical"
done
grep -q "identical, bit for bit" "$work/jarroux2019_industrial_pid/replay.txt" ||
  fail "the PID replay did not report identical sensor outputs: $(cat "$work/jarroux2019_industrial_pid/replay.txt")"

# Live at 20 kHz on the wall clock (the in-process controller): nothing lost at full rate (the
# summary and the footer count no drop) and the replay is the live run, bit for bit, overruns
# and caught-up periods included.
# A build that cannot keep 20 kHz (ASan's) misses periods: the physics catches up without the
# controller, the rotor lands before the trigger, and `hil`'s checks fail it (exit 4). That run
# is still recorded whole, and its replay must still be it, bit for bit.
rc=0
"$tool" hil "$source_dir/configs/jarroux2019_industrial_pid.toml" --set simulation.duration_s=0.3 \
  --set trigger.time_s=0.1 --out "$work/live" --record "$work/live.lcm" --quiet 2>"$work/live.err" ||
  rc=$?
if [[ $rc == 4 ]]; then
  python3 - "$work/live/summary.json" <<'PY' ||
import json, sys
d = json.load(open(sys.argv[1]))
assert d["status"] == "check_failed" and d["missed_periods"] > 0, (d["status"], d["missed_periods"])
print("note: the live run missed", d["missed_periods"], "periods and failed its checks:",
      d["checks"]["failures"])
PY
    fail "live hil exited 4 without missing periods: $(cat "$work/live.err")"
elif [[ $rc != 0 ]]; then
  fail "live hil --record failed ($rc): $(cat "$work/live.err")"
fi
grep -q '"events_dropped": 0' "$work/live/summary.json" || fail "the live record dropped events"
"$tool" replay "$work/live.lcm" --out "$work/live_replay" >"$work/live_replay.txt" ||
  fail "the live record does not replay identically: $(cat "$work/live_replay.txt")"
cmp "$work/live/timeseries.csv" "$work/live_replay/timeseries.csv" ||
  fail "the live run's timeseries.csv differs from its replay"

# A changed config: a difference report, not an error.
pid=$work/jarroux2019_industrial_pid
"$tool" replay "$pid/run.lcm" --set tdb.de.friction.coefficient=0.3 --out "$work/changed" \
  >"$work/changed.txt" || fail "a replay with a changed config exited non-zero"
grep -q "first at step" "$work/changed.txt" || fail "no difference report: $(cat "$work/changed.txt")"
grep -q '"identical": false' "$work/changed/summary.json" || fail "summary.json says identical"
# The same with --strict: exit 4 and status replay_differs; a tolerance larger than every
# difference lets it pass by value; the recorded config passes strictly (0 tolerance).
rc=0
"$tool" replay "$pid/run.lcm" --set tdb.de.friction.coefficient=0.3 --strict --out "$work/strict" \
  --quiet 2>"$work/strict.err" || rc=$?
[[ $rc -eq 4 ]] || fail "--strict with differences exited $rc, expected 4"
grep -q '"status": "replay_differs"' "$work/strict/summary.json" || fail "strict status not replay_differs"
"$tool" replay "$pid/run.lcm" --set tdb.de.friction.coefficient=0.3 --strict --tolerance-m 1 \
  --out "$work/loose" --quiet || fail "--strict --tolerance-m 1 exited $?"
"$tool" replay "$pid/run.lcm" --strict --out "$work/exact" --quiet ||
  fail "the recorded config failed --strict"

# A truncated record: replays up to the cut, warns where.
size=$(stat -c %s "$pid/run.lcm")
head -c $((size / 2 + 5)) "$pid/run.lcm" >"$work/cut.lcm"
"$tool" replay "$work/cut.lcm" --out "$work/cut" --quiet 2>"$work/cut.err" ||
  fail "a truncated record did not replay: $(cat "$work/cut.err")"
grep -q "truncated.*byte" "$work/cut.err" || fail "no truncation warning: $(cat "$work/cut.err")"

# Not a record at all: seeded bytes (the same every run), once as they come and once beginning
# with '(' as a candump log's first line does.
for first in "" "("; do
  python3 -c "import random, sys; random.seed(5); sys.stdout.buffer.write(b'$first' + bytes(random.getrandbits(8) for _ in range(5000)))" >"$work/garbage.lcm"
  rc=0
  "$tool" replay "$work/garbage.lcm" --out "$work/garbage" 2>"$work/garbage.err" || rc=$?
  [[ $rc -eq 1 ]] || fail "garbage (first byte '$first') replayed with exit $rc: $(cat "$work/garbage.err")"
  grep -q "not an ambdrop run record" "$work/garbage.err" || fail "unclear error: $(cat "$work/garbage.err")"
done
echo "record/replay: ok"
