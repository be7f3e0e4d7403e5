#!/usr/bin/env bash
# `ambdrop measure` makes a measured-like record from a truth rig: the header names the fixed
# channels, the same options give the same bytes (another seed other noise), --channels and
# --from-s choose columns and rows, the [measurement] table it writes describes the columns and
# is accepted by the config loader, and bad options, bad configs and a diverging truth run exit
# 64, 2 and 3 with a clear error.
# Usage: measure.sh AMBDROP_BINARY SOURCE_DIR
set -euo pipefail
tool=$1
source_dir=$2
rig="$source_dir/configs/jarroux2019_industrial_pid.toml"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() {
  echo "FAIL: $*" >&2
  exit 1
}
cd "$work"

"$tool" measure "$rig" --set simulation.duration_s=0.3 --out x.csv --measurement-toml m.toml -q ||
  fail "measure exited $?"
expected="t,x_de,y_de,x_nde,y_nde,i_de_x,i_de_y,i_nde_x,i_nde_y,f_de,f_nde,w_de,w_nde,w_rotor"
[[ $(head -1 x.csv) == "$expected" ]] || fail "header: $(head -1 x.csv)"
# 20 kHz over 0.3 s, both ends: 6001 rows after the header.
[[ $(wc -l <x.csv) -eq 6002 ]] || fail "$(wc -l <x.csv) lines"

python3 - x.csv m.toml <<'PY'
import csv, sys, tomllib
rows = list(csv.reader(open(sys.argv[1])))
header, data = rows[0], [[float(v) for v in r] for r in rows[1:]]
m = tomllib.load(open(sys.argv[2], "rb"))["measurement"]
assert m["sample_rate_Hz"] == 20000.0, m
assert m["trigger_time_s"] == 0.2, m
assert [c["column"] for c in m["channel"]] == header[1:], (m["channel"], header)
keys = {"displacement": {"sensor", "axis"}, "current": {"amb", "axis"},
        "tdb_normal_force": {"tdb"}, "tdb_speed": {"tdb"}, "rotor_speed": set()}
for c in m["channel"]:
    assert set(c) - {"column", "quantity"} == keys[c["quantity"]], c
t = [r[0] for r in data]
assert t[0] == 0.0 and abs(t[1] - 5e-5) < 1e-15 and abs(t[-1] - 0.3) < 1e-12, (t[:2], t[-1])
col = {name: i for i, name in enumerate(header)}
# Levitated and spinning before the trigger, on the TDBs after it.
assert all(r[col["f_de"]] == 0.0 for r in data if r[0] < 0.2)
assert max(r[col["f_de"]] for r in data) > 1000.0
assert all(abs(r[col["w_rotor"]] - 680.6784082777885) < 1e-6 for r in data if r[0] < 0.2)
assert sum(r[col["y_de"]] for r in data if r[0] > 0.25) / len([1 for r in data if r[0] > 0.25]) < -2.2e-4
PY

# Same options, same bytes; another seed, other noise.
noise=(--current-noise-A 0.02 --force-noise-N 5 --speed-noise-rad-s 0.1)
"$tool" measure "$rig" --set simulation.duration_s=0.05 --out a.csv "${noise[@]}" --seed 3 -q
"$tool" measure "$rig" --set simulation.duration_s=0.05 --out b.csv "${noise[@]}" --seed 3 -q
"$tool" measure "$rig" --set simulation.duration_s=0.05 --out c.csv "${noise[@]}" --seed 4 -q
cmp a.csv b.csv || fail "the same seed gave different records"
if cmp -s a.csv c.csv; then fail "another seed gave the same record"; fi

# Groups come in their fixed order; rows before --from-s are left out, t stays run time.
"$tool" measure "$rig" --set simulation.duration_s=0.05 --out g.csv --channels rotor_speed,current \
  --rate-Hz 10000 --from-s 0.02 -q
[[ $(head -1 g.csv) == "t,i_de_x,i_de_y,i_nde_x,i_nde_y,w_rotor" ]] || fail "groups: $(head -1 g.csv)"
first_t=$(sed -n 2p g.csv | cut -d, -f1)
python3 -c "import sys; assert abs(float(sys.argv[1]) - 0.02) < 1e-12" "$first_t" ||
  fail "first row of --from-s 0.02 at t = $first_t"
[[ $(wc -l <g.csv) -eq 302 ]] || fail "--from-s 0.02 at 10 kHz to 0.05 s: $(wc -l <g.csv) lines"

# The table, appended to an analysed config of the same rig, must be accepted by the loader.
{
  echo "base = \"$rig\""
  cat m.toml
} >analysed.toml
rc=0
"$tool" sim analysed.toml --set simulation.duration_s=0.01 --out analysed -q 2>err.txt || rc=$?
# Only the loader's refusal of the whole table is a skip; an error inside it is a failure.
if [[ $rc -ne 0 ]] && grep -q "unknown key 'measurement'" err.txt; then
  echo "note: the loader does not take [measurement] yet; the table was not checked by it"
elif [[ $rc -ne 0 ]]; then
  fail "the analysed config with the table exited $rc: $(cat err.txt)"
fi

# Refusals, each saying why; a diverging truth run writes no record.
expect_exit() {
  local want=$1 pattern=$2
  shift 2
  local rc=0
  "$tool" measure "$rig" --out bad.csv -q "$@" 2>err.txt || rc=$?
  [[ $rc -eq $want ]] || fail "$* exited $rc, not $want: $(cat err.txt)"
  grep -q -- "$pattern" err.txt || fail "$*: unclear error: $(cat err.txt)"
}
expect_exit 64 "whole number of physics steps" --rate-Hz 30000
expect_exit 64 "no group 'speed'" --channels speed
expect_exit 2 "simulation.step_s" --set simulation.step_s=-1
expect_exit 3 "truth run failed" --set simulation.max_excursion_over_clearance=0.5
[[ ! -e bad.csv ]] || fail "a refused run wrote a record"
echo "measure: ok"
