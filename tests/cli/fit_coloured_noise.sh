#!/usr/bin/env bash
# `ambdrop fit` on a record whose sensors' noise passed a 2 kHz bandwidth (docs/fit.md, "The
# sensors' noise, white or coloured"): the rigid truth rig's clean record of seed 901 (tools/truth,
# no code shared with ambdrop; acquisition.sensor_noise_bandwidth_Hz set on a copy of the rig)
# through its translation, raw. Before the fit read the colour, it named a derivative filter 1.6
# times the declared on it (`explained`, the levitated currents' spectrum 2.40 against 1.55).
# Held here: `no_effect_needed` with nothing chosen; fit.json `sensor_noise` with the bandwidth
# within 15 % of 2 kHz and sigma within 10 % of the rig's 0.3 um, second differences reading it
# below 0.7 of that; report.md saying the noise is coloured. The same seed on the rig as declared
# (white noise): bandwidth 0, and sigma that of second differences.
# Usage: fit_coloured_noise.sh AMBDROP_BINARY SOURCE_DIR [AMBDROP_TRUTH_BINARY]
source "$(dirname "$0")/../support/cli_prelude.sh" "$@"
find_truth_tool_or_skip "${3:-}"

rig=$source_dir/tools/truth/rigs/rigid_rotor_a.json
python3 - "$rig" coloured.json <<'PY'
import json, sys
rig = json.load(open(sys.argv[1]))
rig["acquisition"]["sensor_noise_bandwidth_Hz"] = 2000.0
json.dump(rig, open(sys.argv[2], "w"), indent=1)
PY
for kind in coloured white; do
  sheet=coloured.json
  [[ $kind == white ]] && sheet=$rig
  "$truth_tool" --rig "$sheet" --effect clean --seed 901 --out "rec_$kind" >/dev/null ||
    fail "ambdrop_truth ($kind) exited $?"
  "$tool" fit "$source_dir/tests/truth/rigid_rotor_a.toml" \
    --measured "rec_$kind/blind/record.csv" --out "fit_$kind" >"fit_$kind.txt" 2>&1 ||
    fail "fit ($kind) exited $?: $(tail -n 5 "fit_$kind.txt")"
done

python3 - <<'PY' || fail "the fits' outcomes (above)"
import json
ok = True
def check(cond, what):
    global ok
    if not cond:
        print("FAIL:", what)
        ok = False
c = json.load(open("fit_coloured/fit.json"))
n = c["sensor_noise"]
check(c["verdict"] == "no_effect_needed" and not c["chosen"], f"coloured: {c['verdict']}, {c['chosen']}")
check(abs(n["bandwidth_Hz"] / 2000.0 - 1.0) <= 0.15, f"coloured: bandwidth {n['bandwidth_Hz']} Hz")
check(abs(n["sigma_m"] / 3e-7 - 1.0) <= 0.10, f"coloured: sigma {n['sigma_m']} m")
check(n["second_difference_sigma_m"] < 0.7 * 3e-7, f"coloured: second differences {n['second_difference_sigma_m']} m")
check("noise is coloured" in open("fit_coloured/report.md").read(), "report.md says nothing of the colour")
w = json.load(open("fit_white/fit.json"))["sensor_noise"]
check(w["bandwidth_Hz"] == 0 and w["sigma_m"] == w["second_difference_sigma_m"], f"white: {w}")
print("coloured:", c["verdict"], n, "\nwhite:", w)
raise SystemExit(0 if ok else 1)
PY
echo "ok: fit_coloured_noise"
