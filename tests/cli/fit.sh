#!/usr/bin/env bash
# `ambdrop fit` from the command line: a record made by `ambdrop measure` from the PID rig with
# its DE TDB offset, fitted with the rig as declared (with the [measurement] table `measure`
# wrote): fit.json names the misalignment with its values and uncertainties, the residual
# falls, report.md and its plots are written; bad inputs are refused with a clear error.
# Usage: fit.sh AMBDROP_BINARY SOURCE_DIR
source "$(dirname "$0")/../support/cli_prelude.sh" "$@"
rig="$source_dir/configs/jarroux2019_industrial_pid.toml"
timing=(--set simulation.duration_s=0.25 --set trigger.time_s=0.1)

"$tool" measure "$rig" "${timing[@]}" --set simulation.step_s=2.5e-6 \
  --set tdb.de.misalignment.enabled=true --set tdb.de.misalignment.x_m=2e-5 \
  --set tdb.de.misalignment.y_m=-4e-5 --current-noise-A 0.005 --out drop.csv \
  --measurement-toml measurement.toml -q
{
  echo "base = \"$rig\""
  cat measurement.toml
} >declared.toml
"$tool" fit declared.toml "${timing[@]}" --measured drop.csv --out fit >fit.txt ||
  fail "fit exited $?: $(cat fit.txt)"
python3 - fit/fit.json <<'PY'
import json, sys
f = json.load(open(sys.argv[1]))
assert f["verdict"] == "explained", f["verdict"]
chosen = f["chosen"]
assert [c["effect"] for c in chosen] == ["tdb_misalignment:de"], chosen
p = chosen[0]["parameters"]
assert abs(p["x_m"]["value"] - 2e-5) < 4e-6 and abs(p["y_m"]["value"] + 4e-5) < 8e-6, p
assert p["y_m"]["sigma"] > 0, p
assert f["schema_version"] == 2, f.get("schema_version")
lines = chosen[0]["set"]
assert "tdb.de.misalignment.enabled=true" in lines, lines
open("set.txt", "w").write("\n".join(lines) + "\n")
before, after = f["rms_before"], f["rms_after"]
assert before["overall"] > 3 * after["overall"], (before["overall"], after["overall"])
assert set(before["channels"]) == set(after["channels"]) and "y_de" in before["channels"]
assert len(f["candidates"]) >= 10 and all("effect" in c for c in f["candidates"])
# Every decidable hand-made family is fitted; of the registry's screened keys only the best few
# and as many look-alikes of the chosen effect.
assert all(c["tried"] for c in f["candidates"] if c["decidable"] and not c["screened"]), f["candidates"]
screened = [c for c in f["candidates"] if c["screened"]]
assert len(screened) > 20 and sum(c["tried"] for c in screened) <= 12, len(screened)
assert all("screened_rms" in c for c in screened if c["decidable"]), screened
assert f["decidable_candidates"] == sum(c["decidable"] for c in f["candidates"]), f["decidable_candidates"]
# An offset TDB shows in the drop's start, which the verdict then judges (the whole record
# agrees within its limit too); the races' spin laws (drag, inertia, damping) do not show there,
# before the races have been spun up, and every other hand-made effect does.
assert f["judged_on"] == "early", f["judged_on"]
assert f["early"]["rms_after"] <= f["early"]["agreement_limit"], f["early"]
assert f["whole"]["rms_after"] <= f["whole"]["agreement_limit"], f["whole"]
assert all(u["why"] for u in f["undecidable"]), f["undecidable"]
hand_made = [u["effect"] for u in f["undecidable"] if "." not in u["effect"]]
assert all(e.startswith(("tdb_race_", "tdb_drag_torque")) for e in hand_made), hand_made
assert f["agreement_limit"] <= f["agreement_limit_after"], (f["agreement_limit"], f["agreement_limit_after"])
judged = f[f["judged_on"]]  # the top-level limits are the judged part's
assert judged["rms_after"] <= f["agreement_limit_after"] <= max(f["agreement_limit"], judged["rms_before"] / 3)
print(f"fit: {f['verdict']}, x {p['x_m']['value']:.3g} m, y {p['y_m']['value']:.3g} m, "
      f"overall {before['overall']:.3g} -> {after['overall']:.3g}")
PY
grep -q "Verdict: explained" fit/report.md || fail "report.md has no verdict"
python3 -c 'import json, sys; assert json.load(open(sys.argv[1]))["windows"]["trigger_detected"] is False' \
  fit/fit.json || fail "fit.json: the given trigger reported as detected"

# The same record with the trigger left to the record (its currents cut at once): found within
# half a sample, and fit.json and report.md say it was found, not given.
grep -q '^trigger_time_s = ' declared.toml || fail "measure wrote no trigger_time_s"
sed 's/^trigger_time_s = .*/trigger = "detect"/' declared.toml >detect.toml
"$tool" fit detect.toml "${timing[@]}" --measured drop.csv --out fit_detect >fit_detect.txt ||
  fail "fit with trigger = detect exited $?: $(cat fit_detect.txt)"
python3 - fit_detect/fit.json <<'PY'
import json, sys
w = json.load(open(sys.argv[1]))["windows"]
assert w["trigger_detected"] is True, w
assert abs(w["trigger_s"] - 0.1) <= 0.5 / 20000 + 1e-12, w
PY
grep -q "The trigger was found in the record at" fit_detect/report.md ||
  fail "report.md does not say the trigger was found in the record"
# The fitted effect's --set lines, as the report prints them, are what the config takes: read
# back through `ambdrop keys`, the offsets are the fitted values to the last bit.
set_args=()
while read -r line; do set_args+=(--set "$line"); done <set.txt
grep -qF -- "--set $(head -n1 set.txt)" fit/report.md || fail "report.md does not print the --set lines"
"$tool" keys declared.toml "${timing[@]}" "${set_args[@]}" --json >keys.json ||
  fail "the fitted --set lines do not load: $(cat keys.json)"
python3 - fit/fit.json keys.json <<'PY'
import json, sys
p = json.load(open(sys.argv[1]))["chosen"][0]["parameters"]
keys = {k["path"]: k for k in json.load(open(sys.argv[2]))["keys"]}
for axis in ("x_m", "y_m"):
    read = keys["tdb.de.misalignment." + axis]
    assert read["value"] == p[axis]["value"], (axis, read["value"], p[axis]["value"])
    assert read["location"].startswith("--set "), read
PY
for plot in channel_y_de.svg residual_y_de.svg orbit_de.svg; do
  grep -q "<svg" "fit/$plot" || fail "no plot $plot"
  grep -q "$plot" fit/report.md || fail "report.md does not show $plot"
done

# Refusals, each saying what is wrong.
rc=0
"$tool" fit "$rig" --measured drop.csv --out x 2>err.txt || rc=$?
[[ $rc -eq 2 ]] && grep -q "no \[measurement\] table" err.txt || fail "no [measurement]: $rc $(cat err.txt)"
python3 - <<'PY'
import csv
rows = list(csv.reader(open("drop.csv")))
keep = [i for i, name in enumerate(rows[0]) if name != "y_nde"]
with open("short.csv", "w", newline="") as f:
    csv.writer(f).writerows([[r[i] for i in keep] for r in rows])
with open("slow.csv", "w", newline="") as f:
    csv.writer(f).writerows([rows[0]] + rows[1::2])
PY
rc=0
"$tool" fit declared.toml --measured short.csv --out x 2>err.txt || rc=$?
[[ $rc -eq 2 ]] && grep -q "'y_nde'" err.txt || fail "missing column: $rc $(cat err.txt)"
rc=0
"$tool" fit declared.toml --measured slow.csv --out x 2>err.txt || rc=$?
[[ $rc -eq 2 ]] && grep -q "sample_rate_Hz" err.txt || fail "wrong rate: $rc $(cat err.txt)"
echo "fit: ok"
