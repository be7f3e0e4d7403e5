#!/usr/bin/env bash
# `ambdrop fit` over several records of one rig: two drops of the PID rig whose rotor loses
# speed to a constant coast-down torque the declared rig lacks (300 and 600 N m), each fitted
# into its own directory (the torque found within 2 %), and shared.md / shared.json saying what
# both share; a record that cannot be read fails its own fit (exit 2) without losing the others.
# Usage: fit_several.sh AMBDROP_BINARY SOURCE_DIR
source "$(dirname "$0")/../support/cli_prelude.sh" "$@"
rig="$source_dir/configs/jarroux2019_industrial_pid.toml"
timing=(--set simulation.duration_s=0.25 --set trigger.time_s=0.1)
for torque in 300 600; do
  "$tool" measure "$rig" "${timing[@]}" --set simulation.step_s=2.5e-6 \
    --set rotor.coast_down.enabled=true --set rotor.coast_down.constant_torque_N_m=$torque \
    --seed "$torque" --out "drop_$torque.csv" --measurement-toml measurement.toml -q ||
    fail "measure exited $?"
done
{
  echo "base = \"$rig\""
  cat measurement.toml
} >declared.toml
"$tool" fit declared.toml "${timing[@]}" --measured drop_300.csv drop_600.csv --out fit \
  >fit.txt || fail "fit exited $?: $(cat fit.txt)"
python3 - fit <<'PY'
import json, os, sys
out = sys.argv[1]
shared = json.load(open(os.path.join(out, "shared.json")))
assert shared["failed_records"] == 0, shared
assert [os.path.basename(r["out"]) for r in shared["records"]] == ["01_drop_300", "02_drop_600"], shared
for r, torque in zip(shared["records"], (300.0, 600.0)):
    f = json.load(open(os.path.join(r["out"], "fit.json")))
    assert f["verdict"] == "explained", (r["record"], f["verdict"], f["reason"])
    chosen = f["chosen"]
    assert [c["effect"] for c in chosen] == ["rotor_coast_down_constant"], chosen
    value = chosen[0]["parameters"]["constant_torque_N_m"]["value"]
    assert abs(value / torque - 1) < 0.02, (torque, value)
    assert f["discrepancy"]["dominant"] is False, f["discrepancy"]
assert "every record chose rotor_coast_down_constant" in shared["shared"], shared["shared"]
print("fit several:", [r["verdict"] for r in shared["records"]])
PY
grep -q "What the records share" fit/shared.md || fail "shared.md has no shared section"
# A record that is not there fails alone: the other is still fitted and reported.
status=0
"$tool" fit declared.toml "${timing[@]}" --measured drop_300.csv missing.csv --out bad \
  >bad.txt 2>bad.err || status=$?
[[ $status -eq 2 ]] || fail "a missing record: exit $status, expected 2"
grep -q "missing.csv" bad.err || fail "the error does not name the record: $(cat bad.err)"
python3 -c "
import json; s = json.load(open('bad/shared.json'))
assert s['failed_records'] == 1 and len(s['records']) == 1, s
" || fail "shared.json of the run with a missing record"
echo "fit_several: ok"
