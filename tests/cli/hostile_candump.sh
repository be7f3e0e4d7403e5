#!/usr/bin/env bash
# A candump -l log whose receive times are not finite, absurd, or go back: each such line is
# skipped, counted in summary.json and warned with its line number; the replay stays within the
# run and says the log was damaged.
# Usage: hostile_candump.sh AMBDROP_BINARY SOURCE_DIR
source "$(dirname "$0")/../support/cli_prelude.sh" "$@"

# 0x200: the emulator's sensors (time zero), 0x100: the controller's currents (1 A each).
cat >bus.log <<'LOG'
(1700000000.000000) vcan0 200#0000000000000000
(1700000000.000100) vcan0 100#E803E803E803E803
(nan) vcan0 100#E803E803E803E803
(inf) vcan0 100#E803E803E803E803
(1700000000.000050) vcan0 100#E803E803E803E803
(1700000000.001000) vcan0 200#0000000000000000
(170000000000001200) vcan0 100#E803E803E803E803
(1e300) vcan0 100#E803E803E803E803
LOG
rc=0
timeout 20 "$tool" replay bus.log --config "$source_dir/configs/jarroux2019_industrial_pid_can.toml" \
  --set simulation.duration_s=0.05 --out out --quiet 2>err.txt || rc=$?
[[ $rc -eq 0 ]] || fail "replay exited $rc: $(cat err.txt)"
for expected in "bus.log:3: the receive time is not a finite number" \
  "bus.log:4: the receive time is not a finite number" \
  "bus.log:5: the receive time 1700000000.000050 s is before the previous line's" \
  "bus.log:7: the frames from .* are beyond the run's 0.05 s"; do
  grep -q "$expected" err.txt || fail "no warning '$expected': $(cat err.txt)"
done
python3 - out/summary.json <<'PY' || fail "summary.json does not count the rejected lines"
import json, sys
s = json.load(open(sys.argv[1]))
c = s["candump"]
assert (c["malformed_lines"], c["out_of_order_lines"], c["frames_after_end"]) == (2, 1, 2), c
assert c["controller_frames"] == 1, c
assert s["damaged"] is True and len(s["warnings"]) == 4, s
assert 0 < s["steps"] <= 10000, s["steps"]
PY

echo "hostile candump: ok"
