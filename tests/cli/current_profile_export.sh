#!/usr/bin/env bash
# Currents taken from a recording drive a run: `ambdrop replay --export-profile` turns a
# recorded PID drop into a profile-driven rig, and the drop it gives matches the recorded one
# (touch-down time, peak loads); a scenario on a profile-driven rig without faults is the same
# run as `ambdrop sim` of the rig, byte for byte, and records and replays like any run; a record
# whose AMBs take no currents, or a window outside the record, is refused with a clear error.
# Usage: current_profile_export.sh AMBDROP_BINARY SOURCE_DIR
source "$(dirname "$0")/../support/cli_prelude.sh" "$@"

# The recorded drop: power fails at 0.2 s.
"$tool" sim "$source_dir/configs/jarroux2019_industrial_pid.toml" --out live --record live.lcm -q

# The whole record: at most 1024 points per AMB, the failure as the rig's trigger.
"$tool" replay live.lcm --export-profile whole.toml >whole.txt || fail "export: $(cat whole.txt)"
grep -q "as 1024 profile points per AMB" whole.txt || fail "not decimated to 1024: $(cat whole.txt)"
# The window from 1 ms before the failure, timed from its start.
"$tool" replay live.lcm --export-profile window.toml --profile-from 0.199 --profile-to 0.26 -q
python3 - whole.toml window.toml <<'PY'
import sys, tomllib
for path, trigger_s, duration_s in ((sys.argv[1], 0.2, 1.0), (sys.argv[2], 0.001, 0.061)):
    c = tomllib.load(open(path, "rb"))
    assert c["controller"] == {"kind": "none"}, c["controller"]
    assert abs(c["trigger"]["time_s"] - trigger_s) < 1e-9, (path, c["trigger"])
    assert abs(c["simulation"]["duration_s"] - duration_s) < 1e-9, (path, c["simulation"])
    for name, amb in c["amb"].items():
        p = amb["current_profile"]
        assert 2 <= len(p) <= 1024, (path, name, len(p))
        assert p[0][0] == 0.0 and all(a[0] < b[0] for a, b in zip(p, p[1:])), (path, name)
        # The levitating currents carry the rotor's weight: the y current is the larger.
        assert abs(p[0][2]) > 0.5 and abs(p[0][1]) < 0.5, (path, name, p[0])
PY

# The drop on the exported currents matches the recorded drop.
"$tool" sim window.toml --out window_sim -q
python3 - live/summary.json window_sim/summary.json <<'PY'
import json, sys
live = json.load(open(sys.argv[1]))["tdbs"]
prof = json.load(open(sys.argv[2]))["tdbs"]
for name in ("de", "nde"):
    t_live = live[name]["first_contact_time_s"] - 0.199
    t_prof = prof[name]["first_contact_time_s"]
    assert abs(t_prof - t_live) < 0.5e-3, (name, "touch-down", t_live, t_prof)
    f_live = live[name]["peak_normal_force_N"]
    f_prof = prof[name]["peak_normal_force_N"]
    assert abs(f_prof / f_live - 1) < 0.25, (name, "peak load", f_live, f_prof)
    print(f"{name}: touch-down {t_live*1e3:.2f} ms recorded, {t_prof*1e3:.2f} ms from the profile;"
          f" peak {f_live:.0f} N recorded, {f_prof:.0f} N")
PY

# A scenario on the profile-driven rig without faults is `ambdrop sim` of that rig.
cat >scenario.toml <<TOML
base = "window.toml"
[scenario]
description = "the exported currents, as they are"
[scenario.expect]
contact_at = ["de", "nde"]
TOML
"$tool" sim --scenario scenario.toml --out scenario --record scenario.lcm -q ||
  fail "the scenario on the profile-driven rig failed"
cmp window_sim/timeseries.csv scenario/timeseries.csv ||
  fail "the scenario's run differs from ambdrop sim of the same rig"
"$tool" replay scenario.lcm --out scenario_replay -q || fail "the scenario's record does not replay"
cmp scenario/timeseries.csv scenario_replay/timeseries.csv || fail "replay differs"

# Refusals, each saying why.
"$tool" sim "$source_dir/configs/jarroux2019_industrial.toml" --set simulation.duration_s=0.01 \
  --out equivalent --record equivalent.lcm -q
rc=0
"$tool" replay equivalent.lcm --export-profile x.toml 2>err.txt || rc=$?
[[ $rc -eq 2 ]] || fail "an equivalent-law record exited $rc"
grep -q "takes no coil currents" err.txt || fail "unclear error: $(cat err.txt)"
rc=0
"$tool" replay live.lcm --export-profile x.toml --profile-from 2 2>err.txt || rc=$?
[[ $rc -eq 1 ]] || fail "a window outside the record exited $rc"
grep -q "not inside the record" err.txt || fail "unclear error: $(cat err.txt)"
rc=0
"$tool" replay live.lcm --profile-from 0.1 2>err.txt || rc=$?
[[ $rc -ne 0 ]] || fail "--profile-from without --export-profile was accepted"
echo "current profile export: ok"
