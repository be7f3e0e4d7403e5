#!/usr/bin/env bash
# The HIL command-line pair over real SocketCAN, inside the qemu VM (tests/hw/run_in_vm.sh):
# `ambdrop-controller --can vcan0` levitates the rotor through `ambdrop hil --controller can:vcan0
# --trigger can --record`, `cansend vcan0 080#01` (can-utils) drops it, and `ambdrop replay` of
# the record reproduces the live run bit for bit.
# Usage: hil_can_cli.sh AMBDROP_BINARY SOURCE_DIR   (exit 77: no VM here, skipped)
#
# The guest has no source tree: the config goes in flattened (the effective config of the CAN
# rig, `base =` resolved), inside the guest script itself. The VM emulates its CPU (TCG), about
# 70x slower than the host: the 20 kHz loop cannot keep real time there, so it runs on the
# virtual clock in lock step with the controller process (--virtual-clock --lockstep), which
# exchanges every sample over vcan0 as on a bench, only slower than real time.
set -euo pipefail
tool=$(realpath "$1")
source_dir=$2
controller=$(dirname "$tool")/ambdrop-controller
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

sets=(--set simulation.duration_s=0.6 --set trigger.enabled=false)
"$tool" sim "$source_dir/configs/jarroux2019_industrial_pid_can.toml" "${sets[@]}" \
  --set simulation.duration_s=1e-4 --out "$work/flat" --quiet
sed -i 's/^duration_s = .*/duration_s = 0.6/' "$work/flat/effective_config.toml"
grep -q '^duration_s = 0.6' "$work/flat/effective_config.toml" || {
  echo "hil_can_cli: cannot set the duration in the flattened config" >&2
  exit 1
}

guest=$work/hil_can_cli_guest
{
  echo '#!/bin/sh'
  echo 'cat > rig.toml <<"TOML"'
  cat "$work/flat/effective_config.toml"
  echo 'TOML'
  cat <<'GUEST'
fail() {
  echo "FAIL: $*"
  echo "--- controller.log"; cat controller.log
  echo "--- summary.json"; cat out/summary.json
  exit 1
}
ambdrop-controller rig.toml --can vcan0 --idle-exit-s 2 > controller.log 2>&1 &
# hil starts once the controller answers (its one line), not after a guessed sleep.
waited=0
until grep -q 'listening on' controller.log; do
  waited=$((waited + 1))
  [ $waited -le 600 ] || fail "the controller did not start within 60 s"
  sleep 0.1
done
candump -L vcan0,080:7FF > trigger.log &
candump_pid=$!
(sleep 1.3; cansend vcan0 080#01) &
ambdrop hil rig.toml --controller can:vcan0 --trigger can --virtual-clock --lockstep \
  --lockstep-timeout-s 5 --out out --record run.lcm \
  > hil.log 2>&1 || { cat hil.log; fail "ambdrop hil exited $?"; }
cat hil.log
kill $candump_pid
wait
grep -q '"status": "ok"' out/summary.json || fail "status: $(grep status out/summary.json)"
grep -q '"lockstep_timeouts": 0' out/summary.json || fail "the controller missed answers"
grep -q '"power_events": 1' out/summary.json || fail "the CAN trigger was not applied"
received=$(sed -n 's/.*"currents_received": \([0-9]*\).*/\1/p' out/summary.json)
[ "${received:-0}" -gt 100 ] || fail "only ${received:-0} current messages arrived over vcan0"
grep -q '080#01' trigger.log || fail "candump did not see the trigger frame"
grep -q '"first_contact_time_s": null' out/summary.json && fail "the rotor never touched down"
ambdrop replay run.lcm --out replay > replay.log 2>&1 || { cat replay.log; fail "replay differs"; }
cat replay.log
grep -q "identical, bit for bit" replay.log || fail "replay not identical"
cmp out/timeseries.csv replay/timeseries.csv || fail "replayed timeseries differs"
echo "hil over vcan0: currents and sensors exchanged, dropped on cansend 080#01, replay identical"
GUEST
} > "$guest"
chmod +x "$guest"
VMEXTRA="$tool $controller" VMTIMEOUT=400 bash "$source_dir/tests/hw/run_in_vm.sh" "$guest"
