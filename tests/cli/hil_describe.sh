#!/usr/bin/env bash
# Issue 17: `ambdrop hil CONFIG --describe FILE` gives a controller designer the plant: index
# order and names, rates, and per AMB the static load, ki, ks and the electromagnet constants.
# Checked by physics, not by re-reading the code: the AMBs' static forces carry the rotor's
# weight; each static current makes its static force through ki; and ki, ks are the slopes of
# seed 003's force law F = k((I0+i)^2/(g0-u)^2 - (I0-i)^2/(g0+u)^2) at the centre, evaluated here
# by finite differences from the described k, I0, g0 alone. Usage: hil_describe.sh AMBDROP SRC
source "$(dirname "$0")/../support/cli_prelude.sh" "$@"
"$tool" hil "$source_dir/configs/jarroux2019_industrial_pid.toml" --describe plant.json ||
  fail "--describe exited $?"
[[ ! -e out ]] || fail "--describe ran the loop (it wrote out/)"
python3 - plant.json <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert d["schema_version"] == 1, d["schema_version"]
names = [a["name"] for a in d["ambs"]]
assert names == sorted(names) and [a["index"] for a in d["ambs"]] == list(range(len(names))), names
weight = d["rotor"]["mass_kg"] * d["rotor"]["gravity_m_s2"]
carried = sum(a["static_force_N"][1] for a in d["ambs"])
assert abs(carried / weight - 1) < 1e-9, (carried, weight)
for a in d["ambs"]:
    e = a["electromagnet"]
    k, i0, g0 = e["constant_k_N_m2_per_A2"], e["bias_current_A"], e["nominal_gap_m"]
    force = lambda i, u: k * ((i0 + i) ** 2 / (g0 - u) ** 2 - (i0 - i) ** 2 / (g0 + u) ** 2)
    h = 1e-6
    ki = (force(h, 0) - force(-h, 0)) / (2 * h)
    ks = (force(0, h * g0) - force(0, -h * g0)) / (2 * h * g0)
    assert abs(ki / a["current_gain_ki_N_per_A"] - 1) < 1e-6, (ki, a)
    assert abs(ks / a["position_gain_ks_N_per_m"] - 1) < 1e-6, (ks, a)
    fy, iy = a["static_force_N"][1], a["static_current_A"][1]
    assert abs(a["current_gain_ki_N_per_A"] * iy / fy - 1) < 1e-12, (fy, iy)
    assert abs(iy) <= a["control_current_limit_A"], a
pid = d["reference_controller"]
assert pid["kind"] == "pid" and pid["proportional_A_per_m"] > 0, pid
print(f"describe: {len(names)} AMBs carry {carried:.1f} N of {weight:.1f} N; ki, ks match the law")
PY
