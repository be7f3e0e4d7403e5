#!/usr/bin/env bash
# The client kit's C SocketCAN controller (tools/client_kit/examples/can_pid.c, built here against
# the installed kit, its frame header generated from the CAN rig's [can] table) against `ambdrop
# hil --scenario` on real vcan0 inside the qemu VM (tests/hw/run_in_vm.sh), in lock step: the
# power-loss scenario passes (exit 0, JUnit without failures), and with its ends swapped the
# controller fails it (exit 4). Usage: client_kit_can.sh AMBDROP_BINARY SOURCE_DIR (77: skipped)
source "$(dirname "$0")/../support/cli_prelude.sh" "$(realpath "$1")" "$2"
source "$source_dir/tests/support/client_kit_build.sh"
rig=$source_dir/configs/jarroux2019_industrial_pid_can.toml
kit_build "$rig"
# The guest has no source tree: the CAN rig flattened, with the power-loss scenario appended.
"$tool" sim "$rig" --set simulation.duration_s=1e-4 --set trigger.enabled=false --out flat -q
sed -i 's/^duration_s = .*/duration_s = 0.25/' flat/effective_config.toml
grep -q '^duration_s = 0.25' flat/effective_config.toml || fail "cannot set the duration"
guest=$work/client_kit_can_guest
{
  echo '#!/bin/sh'
  echo 'cat > scenario.toml <<"TOML"'
  cat flat/effective_config.toml
  cat <<'TOML'

[scenario]
description = "full power loss at 0.05 s, over vcan0"

[[scenario.event]]
kind = "power_fail"
time_s = 0.05

[scenario.expect]
status = "ok"
power_events = 1
first_contact_after_s = 0.05
contact_at = ["de", "nde"]
TOML
  echo 'TOML'
  cat <<GUEST
run() {
  name=\$1; expected=\$2; shift 2
  can_pid --interface vcan0 $kit_args --idle-exit-s 3 "\$@" > \$name.pid.log 2>&1 &
  sleep 0.5
  rc=0
  ambdrop hil --scenario scenario.toml --controller can:vcan0 --virtual-clock --lockstep \\
    --lockstep-timeout-s 5 --out \$name --junit \$name.xml -q 2> \$name.err || rc=\$?
  wait
  echo "\$name: exit \$rc"; cat \$name.pid.log
  [ \$rc = \$expected ] || { cat \$name.err \$name.xml; echo "FAIL: \$name: exit \$rc, expected \$expected"; exit 1; }
}
run ok 0
grep -q 'failures="0"' ok.xml || { cat ok.xml; echo "FAIL: JUnit"; exit 1; }
grep -q '"lockstep_timeouts": 0' ok/summary.json || { echo "FAIL: answers missed"; exit 1; }
run swapped 4 --swap-ends
grep -q '<failure' swapped.xml || { echo "FAIL: no JUnit failure for the swapped ends"; exit 1; }
mkdir -p out && cp ok/summary.json out/ok_summary.json && cp ok.xml swapped.xml out/
echo "the kit's C SocketCAN controller on vcan0: scenario passed; swapped ends exit 4"
GUEST
} >"$guest"
chmod +x "$guest"
VMEXTRA="$tool $work/ex/can_pid" VMOUT=$work/vmout VMTIMEOUT=400 \
  bash "$source_dir/tests/hw/run_in_vm.sh" "$guest"
# The results came out of the guest (VMOUT): the run over vcan0 as the host reads it.
python3 - "$work/vmout/ok_summary.json" <<'PY' || fail "the guest's results"
import json, sys
s = json.load(open(sys.argv[1]))
assert s["status"] == "ok" and s["checks"]["passed"], s["status"]
assert s["can"]["exchanges_sent"] > 200 and s["checks"]["levitated_fraction"] < 0.05, s["checks"]
print(f"copied out of the guest: status {s['status']}, {s['can']['exchanges_sent']} exchanges, "
      f"levitated within {s['checks']['levitated_fraction']:.3g} of the clearance")
PY
grep -q '<failure' "$work/vmout/swapped.xml" || fail "swapped.xml not copied out"
