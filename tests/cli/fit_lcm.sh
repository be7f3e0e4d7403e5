#!/usr/bin/env bash
# `ambdrop fit` on an ambdrop run record: a drop recorded by `ambdrop sim --record` from the PID
# rig with its DE TDB offset, fitted with the rig as declared and no [measurement] table (the
# record brings its own): fit.json names the DE misalignment with the recorded offset.
# Usage: fit_lcm.sh AMBDROP_BINARY SOURCE_DIR
source "$(dirname "$0")/../support/cli_prelude.sh" "$@"
rig="$source_dir/configs/jarroux2019_industrial_pid.toml"

"$tool" sim "$rig" --set simulation.duration_s=0.25 --set trigger.time_s=0.1 \
  --set tdb.de.misalignment.enabled=true --set tdb.de.misalignment.y_m=-4e-5 \
  --record r.lcm --out sim -q >sim.txt 2>&1 || fail "sim exited $?: $(cat sim.txt)"
cat >declared.toml <<TOML
base = "$rig"

[simulation]
duration_s = 0.25

[trigger]
time_s = 0.1
TOML
"$tool" fit declared.toml --measured r.lcm --out fit >fit.txt 2>&1 ||
  fail "fit exited $?: $(cat fit.txt)"
python3 - fit/fit.json <<'PY'
import json, sys
f = json.load(open(sys.argv[1]))
assert f["verdict"] == "explained", (f["verdict"], f["reason"])
chosen = f["chosen"]
assert chosen and chosen[0]["effect"] == "tdb_misalignment:de", chosen
p = chosen[0]["parameters"]
assert abs(p["y_m"]["value"] + 4e-5) < 0.2 * 4e-5, p
channels = set(f["rms_before"]["channels"])
assert {"x_de", "y_de", "i_de_y", "f_de", "w_rotor"} <= channels, channels
print(f"fit_lcm: {f['verdict']}, {chosen[0]['effect']}, x {p['x_m']['value']:.3g} m, "
      f"y {p['y_m']['value']:.3g} m, overall {f['rms_before']['overall']:.3g} -> "
      f"{f['rms_after']['overall']:.3g}")
PY
grep -q "warning" fit.txt && fail "a sound record gave warnings: $(cat fit.txt)"

# A record cut short is read up to the cut, with the reader's warnings (here the cut comes
# before the power failure, so there is no trigger to fit from).
head -c 200000 r.lcm >cut.lcm
rc=0
"$tool" fit declared.toml --measured cut.lcm --out cutfit >cut.txt 2>&1 || rc=$?
[[ $rc -eq 2 ]] && grep -q "warning: .*truncated" cut.txt && grep -q "no footer" cut.txt ||
  fail "cut record: $rc $(cat cut.txt)"
# A [measurement] table of the declared config must name the record's columns.
{
  cat declared.toml
  printf '\n[measurement]\nsample_rate_Hz = 20000.0\ntrigger_time_s = 0.1\n'
  printf '[[measurement.channel]]\ncolumn = "de_x"\nquantity = "displacement"\n'
  printf 'sensor = "de"\naxis = "x"\n'
} >wrong_column.toml
rc=0
"$tool" fit wrong_column.toml --measured r.lcm --out x >err.txt 2>&1 || rc=$?
[[ $rc -eq 2 ]] && grep -q "'de_x'" err.txt && grep -q "'x_de'" err.txt ||
  fail "missing column: $rc $(cat err.txt)"
echo "fit_lcm: ok"
