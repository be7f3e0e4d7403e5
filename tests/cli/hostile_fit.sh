#!/usr/bin/env bash
# Measured records that hold nothing to fit: one in which nothing moves (every channel would be
# left out, and any model "already within 0 of the record"), and one with a single absurd cell
# (it would swamp its channel's noise and drop the channel without a word). Each is refused
# (exit 2) saying why, naming the channels left out or the cell. And a declared model that
# cannot run the record (a contact so stiff that the step cannot follow it stops the drop at
# its first impact): refused as a failed run (exit 3) with where and why it stopped, and no
# verdict written; it once came out "no_effect_needed", its agreement limit widened past its
# residual by sensitivities measured from runs as broken.
# Usage: hostile_fit.sh AMBDROP_BINARY SOURCE_DIR
source "$(dirname "$0")/../support/cli_prelude.sh" "$@"
rig="$source_dir/configs/jarroux2019_industrial_pid.toml"
timing=(--set simulation.duration_s=0.25 --set trigger.time_s=0.1)

"$tool" measure "$rig" "${timing[@]}" --set simulation.step_s=2.5e-6 --out drop.csv \
  --measurement-toml measurement.toml -q || fail "measure failed"
{
  echo "base = \"$rig\""
  cat measurement.toml
} >declared.toml

# edit_csv OUT PYTHON: drop.csv's rows (t first) through PYTHON, which changes `rows` in place.
edit_csv() {
  python3 - drop.csv "$1" "$2" <<'PY'
import sys
lines = open(sys.argv[1]).read().splitlines()
head = [l for l in lines if l.startswith("#") or l.startswith("t,")]
rows = [l.split(",") for l in lines if l and l not in head]
exec(sys.argv[3])
open(sys.argv[2], "w").write("\n".join(head + [",".join(r) for r in rows]) + "\n")
PY
}

# Nothing moves: every channel holds its first value.
edit_csv still.csv 'for r in rows: r[1:] = rows[0][1:]'
rc=0
timeout 60 "$tool" fit declared.toml "${timing[@]}" --measured still.csv --out still -q \
  >/dev/null 2>still.err || rc=$?
[[ $rc -eq 2 ]] || fail "a record in which nothing moves: exit $rc, not 2: $(cat still.err)"
grep -q "still.csv: no channel of the record moves beyond its noise" still.err ||
  fail "unclear error for a still record: $(cat still.err)"
grep -q "('x_de' (displacement de x), 'y_de' (displacement de y), " still.err ||
  fail "the channels left out are not named: $(cat still.err)"

# One cell of 1e300 in the first data column, at row 2000.
edit_csv absurd.csv 'rows[1999][1] = "1e300"'
rc=0
timeout 60 "$tool" fit declared.toml "${timing[@]}" --measured absurd.csv --out absurd -q \
  >/dev/null 2>absurd.err || rc=$?
[[ $rc -eq 2 ]] || fail "a record with a 1e300 cell: exit $rc, not 2: $(cat absurd.err)"
grep -q "absurd.csv: column '.*' (displacement) at t = .* s (data row 2000): expected |value| <= 1 m, found 1e+300" \
  absurd.err || fail "unclear error for a 1e300 cell: $(cat absurd.err)"

# A declared model that stops at the drop's first impact.
rc=0
timeout 120 "$tool" fit declared.toml "${timing[@]}" --measured drop.csv --out stops -q \
  --set tdb.de.contact_law.bearing_stiffness_N_per_m=1e13 \
  --set tdb.nde.contact_law.bearing_stiffness_N_per_m=1e13 >/dev/null 2>stops.err || rc=$?
[[ $rc -eq 3 ]] || fail "a declared model that stops early: exit $rc, not 3: $(cat stops.err)"
grep -q "drop.csv: the declared model does not run to the record's end" stops.err ||
  fail "unclear error for a declared model that stops early: $(cat stops.err)"
grep -q "state after the failing step" stops.err ||
  fail "no state dump for a declared model that stops early: $(cat stops.err)"
[[ ! -e stops/fit.json ]] || fail "a verdict was written for a model that cannot run the record"

echo "hostile fit: ok"
