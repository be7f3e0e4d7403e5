#!/usr/bin/env bash
# `ambdrop sim` end to end: the files it writes, their columns and metrics, and the exit code of
# a config error. Usage: sim_outputs.sh AMBDROP_BINARY SOURCE_DIR
set -euo pipefail

tool=$1
source_dir=$2
config=$source_dir/configs/jarroux2019_industrial.toml
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

fail() {
  echo "FAIL: $*" >&2
  exit 1
}

# --- command line basics ------------------------------------------------------------------
"$tool" --version | grep -q '[0-9]\.[0-9]' || fail "--version printed no version"
rc=0
"$tool" >/dev/null 2>&1 || rc=$?
[[ $rc -ne 0 ]] || fail "no subcommand exited 0"
rc=0
"$tool" frobnicate >/dev/null 2>&1 || rc=$?
[[ $rc -ne 0 ]] || fail "an unknown subcommand exited 0"

# --- a short drop -----------------------------------------------------------------------------
out=$work/out
rc=0
"$tool" sim "$config" --set simulation.duration_s=0.3 --out "$out" --quiet \
  >"$work/stdout" 2>"$work/stderr" || rc=$?
if [[ $rc -ne 0 ]]; then
  cat "$work/stderr" >&2
  fail "sim exited $rc"
fi
[[ ! -s $work/stdout ]] || fail "--quiet still printed to stdout: $(head -c 300 "$work/stdout")"
[[ -s $out/timeseries.csv ]] || fail "no timeseries.csv"
[[ -s $out/summary.json ]] || fail "no summary.json"

# Header columns (units in the names), sensors and TDBs named de and nde in the config.
header=$(head -n 1 "$out/timeseries.csv")
expected=(time_s spin_speed_rad_s)
for name in de nde; do
  expected+=("sensor_${name}_x_m" "sensor_${name}_y_m")
  for quantity in normal_force_N tangential_force_N penetration_m spin_speed_rad_s; do
    expected+=("tdb_${name}_${quantity}")
  done
done
for column in "${expected[@]}"; do
  [[ ",$header," == *",$column,"* ]] || fail "timeseries.csv header lacks $column: $header"
done

# The summary parses, has the per-TDB metrics, and agrees with the time series it came from.
python3 - "$out/timeseries.csv" "$out/summary.json" <<'PY' || fail "summary.json check"
import csv
import json
import sys

csv_path, json_path = sys.argv[1], sys.argv[2]
with open(json_path) as f:
    summary = json.load(f)
with open(csv_path, newline="") as f:
    rows = list(csv.reader(f))
header, data = rows[0], rows[1:]


def check(condition, message):
    if not condition:
        print(f"summary.json: {message}", file=sys.stderr)
        sys.exit(1)


check(len(data) >= 2, f"only {len(data)} rows in timeseries.csv")
check(all(len(row) == len(header) for row in data), "ragged rows in timeseries.csv")
for key in ("final_spin_speed_rad_s", "steps", "wall_time_s", "realtime_factor", "config",
            "status", "tdbs"):
    check(key in summary, f"no '{key}'")
check(summary["status"] == "ok", f"status {summary['status']!r}")
check(summary["steps"] > 0, "no steps")
trigger = summary.get("trigger_time_s")
check(trigger is not None and abs(trigger - 0.2) < 1e-12, f"trigger_time_s {trigger}, want 0.2")

times = [float(row[0]) for row in data]
interval = times[1] - times[0]
check(times[-1] <= 0.3 + 1e-9 and 0.3 - times[-1] < interval + 1e-9,
      f"time series ends at {times[-1]} s, the run lasts 0.3 s")

for name in ("de", "nde"):
    check(name in summary["tdbs"], f"no TDB '{name}'")
    tdb = summary["tdbs"][name]
    for key in ("peak_normal_force_N", "max_excursion_over_clearance", "first_contact_time_s",
                "spinup_time_s"):
        check(key in tdb, f"TDB '{name}' has no '{key}'")
    first = tdb["first_contact_time_s"]
    check(first is not None and first > trigger,
          f"TDB '{name}': first contact at {first}, not after the {trigger} s trigger")
    check(tdb["max_excursion_over_clearance"] > 1.0,
          f"TDB '{name}': contact but max excursion/clearance {tdb['max_excursion_over_clearance']}")
    # Both files print the same doubles with 17 digits, so they must agree exactly.
    force = [float(row[header.index(f"tdb_{name}_normal_force_N")]) for row in data]
    check(max(force) == tdb["peak_normal_force_N"],
          f"TDB '{name}': peak force {tdb['peak_normal_force_N']} but the CSV max is {max(force)}")
    first_csv = next(t for t, fn in zip(times, force) if fn > 0.0)
    check(first_csv == first, f"TDB '{name}': first contact {first} but the CSV says {first_csv}")
PY

# --- a misspelt --set key is a config error (exit 2) that names the key --------------------
rc=0
"$tool" sim "$config" --set tdb.de.clearence_m=1 --out "$work/bad" --quiet \
  >/dev/null 2>"$work/bad_stderr" || rc=$?
[[ $rc -eq 2 ]] || fail "a bad --set key exited $rc, want 2 (stderr: $(cat "$work/bad_stderr"))"
grep -q 'clearence_m' "$work/bad_stderr" ||
  fail "the error does not name the bad key: $(cat "$work/bad_stderr")"

# --- --amb-currents: the same rows, with every AMB's currents as the last columns -------------
"$tool" sim "$source_dir/configs/jarroux2019_industrial_pid.toml" --set simulation.duration_s=0.21 \
  --out "$work/currents" --quiet --amb-currents >/dev/null 2>"$work/currents_stderr" ||
  fail "sim --amb-currents: $(cat "$work/currents_stderr")"
"$tool" sim "$source_dir/configs/jarroux2019_industrial_pid.toml" --set simulation.duration_s=0.21 \
  --out "$work/plain" --quiet >/dev/null 2>&1 || fail "sim without --amb-currents"
python3 - "$work/currents/timeseries.csv" "$work/plain/timeseries.csv" <<'PY' || fail "--amb-currents"
import csv, sys
with_currents = list(csv.reader(open(sys.argv[1])))
plain = list(csv.reader(open(sys.argv[2])))
extra = [f"amb_{n}_{a}_{q}_A" for n in ("nde", "de") for q in ("command", "coil") for a in "xy"]
header = with_currents[0]
assert sorted(header[len(plain[0]):]) == sorted(extra), header
assert len(with_currents) == len(plain)
for a, b in zip(with_currents, plain):
    assert a[:len(b)] == b, "the other columns moved"
# Levitated: the y coil currents carry the weight; after the 0.2 s trigger they are gone (no
# flux decay in this config) while the command goes on.
rows = with_currents[1:]
t = [float(r[0]) for r in rows]
coil = [float(r[header.index("amb_de_y_coil_A")]) for r in rows]
command = [float(r[header.index("amb_de_y_command_A")]) for r in rows]
assert abs(coil[len(rows) // 2]) > 0.1, coil[len(rows) // 2]
assert all(c == 0.0 for tt, c in zip(t, coil) if tt > 0.2 + 1e-9)
assert any(c != 0.0 for tt, c in zip(t, command) if tt > 0.2 + 1e-9)
PY

echo "sim_outputs: ok"
