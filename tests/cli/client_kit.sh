#!/usr/bin/env bash
# The client kit from outside (issue 17): `cmake --install` of this build into a scratch prefix,
# the kit's example project configured and built against it with find_package(ambdrop) (the C
# LCM types compiled in, the CAN header generated from a [can] table at build time), and the C
# LCM controller, configured from `hil --describe` by names, run against `ambdrop hil
# --scenario` over LCM udpm in lock step inside a network namespace this test creates: the
# power-loss scenario passes (exit 0, JUnit without failures) and the drop is the in-process
# controller's; the same controller with its ends swapped, or silent, fails it (exit 4, JUnit
# failures). Usage: client_kit.sh AMBDROP_BINARY SOURCE_DIR; exit 77 = skipped (no namespace).
source "$(dirname "$0")/../support/cli_prelude.sh" "$@"
source "$source_dir/tests/support/client_kit_build.sh"
scenario=$source_dir/configs/scenarios/power_loss.toml
kit_build "$scenario"
echo "client kit: installed, examples built with find_package(ambdrop)"
ambdrop=$prefix/bin/ambdrop
period=$(python3 -c 'import json; print(repr(json.load(open("plant.json"))["rates"]["sensor_period_s"]))')
args="$kit_args --period-s $period"
if ! unshare -n true 2>/dev/null; then
  echo "SKIPPED: the kit built, but no network namespace here for the LCM run (unshare -n refused)"
  exit 77
fi
unshare -n bash -c "
  set -e
  ip link set lo up
  ip route add 239.0.0.0/8 dev lo
  run() {
    name=\$1; shift
    ex/lcm_pid $args --idle-exit-s 1 \"\$@\" > \$name.pid.log 2>&1 &
    sleep 0.3
    rc=0
    '$ambdrop' hil --scenario '$scenario' --controller lcm --virtual-clock \$mode \
      --out \$name --junit \$name.xml -q 2> \$name.err || rc=\$?
    echo \$rc > \$name.rc
    wait
  }
  mode=--lockstep run ok
  mode=--lockstep run swapped --swap-ends
  mode= run silent --silent
"
[[ $(cat ok.rc) == 0 ]] || fail "the C controller failed the scenario: $(cat ok.rc) $(cat ok.err)"
grep -q 'failures="0"' ok.xml || fail "JUnit: $(cat ok.xml)"
for broken in swapped silent; do
  [[ $(cat $broken.rc) == 4 ]] || fail "$broken controller: exit $(cat $broken.rc), expected 4"
  grep -q '<failure' $broken.xml || fail "$broken: no JUnit failure: $(cat $broken.xml)"
done
grep -q "before any power event" swapped.err || fail "swapped: $(cat swapped.err)"
grep -q "sent no currents message" silent.err || fail "silent: $(cat silent.err)"
# The same scenario with the in-process controller: the C controller's drop is the same.
"$ambdrop" sim --scenario "$scenario" --out internal -q || fail "sim --scenario exited $?"
python3 - ok/summary.json internal/summary.json <<'PY'
import json, sys
outside, inside = (json.load(open(f)) for f in sys.argv[1:])
assert outside["checks"]["levitated_fraction"] < 0.01, outside["checks"]
assert outside["checks"]["answers"] >= outside["checks"]["samples_sent"] - 1, outside["checks"]
for name, tdb in outside["tdbs"].items():
    a, b = tdb["first_contact_time_s"], inside["tdbs"][name]["first_contact_time_s"]
    assert abs(a - b) < 5e-4, (name, a, b)
    pa, pb = tdb["peak_normal_force_N"], inside["tdbs"][name]["peak_normal_force_N"]
    assert abs(pa - pb) < 0.1 * pb, (name, pa, pb)
print("C controller over LCM: scenario passed; first contacts",
      {n: t["first_contact_time_s"] for n, t in outside["tdbs"].items()},
      "as the in-process controller's", {n: t["first_contact_time_s"] for n, t in inside["tdbs"].items()})
PY
echo "client kit: ok (a working C controller passes, swapped and silent ones exit 4)"
