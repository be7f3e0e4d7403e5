#!/usr/bin/env bash
# Every scenario in configs/scenarios/ runs with `ambdrop sim --scenario` and its expected
# outcome holds (exit 0, every check "pass" in summary.json); a scenario whose expectation is
# wrong exits 4 and says which check failed, in JUnit XML too (`--junit FILE`, read back with
# Python's XML parser); a rig config without [scenario] is refused, and so is --junit without
# --scenario.
# Usage: scenarios.sh AMBDROP_BINARY SOURCE_DIR
set -euo pipefail
tool=$1
source_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() {
  echo "FAIL: $*" >&2
  exit 1
}

count=0
for scenario in "$source_dir"/configs/scenarios/*.toml; do
  name=$(basename "$scenario" .toml)
  rc=0
  "$tool" sim --scenario "$scenario" --out "$work/$name" >"$work/$name.txt" 2>&1 || rc=$?
  [[ $rc -eq 0 ]] || fail "$name exited $rc: $(cat "$work/$name.txt")"
  python3 - "$work/$name/summary.json" "$name" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
checks = s["scenario"]["checks"]
assert checks, f"{sys.argv[2]}: the scenario states no expectation"
assert all(c["pass"] for c in checks), (sys.argv[2], checks)
assert s["scenario"]["pass"] is True
PY
  count=$((count + 1))
done
[[ $count -ge 9 ]] || fail "only $count scenarios found"

# A wrong expectation is caught.
cat >"$work/wrong.toml" <<TOML
base = "$source_dir/configs/scenarios/trigger_glitch.toml"
[scenario.expect]
contact = true
TOML
rc=0
"$tool" sim --scenario "$work/wrong.toml" --out "$work/wrong" --junit "$work/wrong.xml" \
  >"$work/wrong.txt" 2>&1 || rc=$?
[[ $rc -eq 4 ]] || fail "a failed expectation exited $rc"
grep -q "FAIL contact" "$work/wrong.txt" || fail "the failed check is not named: $(cat "$work/wrong.txt")"
"$tool" sim --scenario "$source_dir/configs/scenarios/trigger_glitch.toml" --out "$work/glitch" \
  --junit "$work/right.xml" --quiet || fail "the glitch scenario with --junit exited $?"
python3 - "$work/wrong.xml" "$work/right.xml" "$work/wrong/summary.json" <<'PY'
import json, sys
import xml.etree.ElementTree as ET

def suite(path):
    s = ET.parse(path).getroot().find("testsuite")
    cases = {(c.get("classname"), c.get("name")): c.find("failure") for c in s.findall("testcase")}
    assert int(s.get("tests")) == len(cases), s.attrib
    assert int(s.get("failures")) == sum(f is not None for f in cases.values()), s.attrib
    return cases

wrong, right = suite(sys.argv[1]), suite(sys.argv[2])
checks = json.load(open(sys.argv[3]))["scenario"]["checks"]
# One case per expectation, failed exactly where summary.json says, plus the run's own two.
assert len(wrong) == len(checks) + 2, (len(wrong), checks)
for c in checks:
    failure = wrong[("sim.scenario", c["check"])]
    assert (failure is None) == c["pass"], (c, failure)
assert wrong[("sim.scenario", "contact")] is not None
assert "expected" in wrong[("sim.scenario", "contact")].get("message")
assert wrong[("sim", "run_completed")] is None and wrong[("sim", "outputs_written")] is None
assert all(f is None for f in right.values()), right
PY
rc=0
"$tool" sim "$source_dir/configs/jarroux2019_industrial_pid.toml" --junit "$work/x.xml" \
  --out "$work/x" 2>"$work/nojunit.err" || rc=$?
[[ $rc -eq 64 && ! -e $work/x.xml ]] || fail "--junit without --scenario exited $rc, expected 64 (usage)"
grep -q "requires --scenario" "$work/nojunit.err" || fail "unclear error: $(cat "$work/nojunit.err")"

# A plain rig is not a scenario.
rc=0
"$tool" sim --scenario "$source_dir/configs/jarroux2019_industrial_pid.toml" --out "$work/x" \
  2>"$work/plain.err" || rc=$?
[[ $rc -eq 2 ]] || fail "a rig without [scenario] exited $rc"
grep -q "no \[scenario\] table" "$work/plain.err" || fail "unclear error: $(cat "$work/plain.err")"

# A scenario records and replays like any run.
"$tool" sim --scenario "$source_dir/configs/scenarios/power_dip_relevitation.toml" \
  --out "$work/dip" --record "$work/dip.lcm" --quiet
"$tool" replay "$work/dip.lcm" --out "$work/dip_replay" --quiet ||
  fail "the recorded scenario does not replay identically"
cmp "$work/dip/timeseries.csv" "$work/dip_replay/timeseries.csv" || fail "replay differs"
echo "scenarios: $count ok"
