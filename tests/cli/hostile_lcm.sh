#!/usr/bin/env bash
# `ambdrop hil --controller lcm` fed malformed packets on its currents channel (over LCM udpm, in
# a network namespace this test creates: loopback only): it runs on, counts them in the "lcm"
# block of summary.json, and neither the status nor the exit code says ok.
# Usage: hostile_lcm.sh AMBDROP_BINARY SOURCE_DIR; exit 77 = skipped.
set -euo pipefail
tool=$1
source_dir=$2
config=$source_dir/configs/jarroux2019_industrial_pid.toml
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() {
  echo "FAIL: $*" >&2
  exit 1
}
if ! unshare -n true 2>/dev/null; then
  echo "SKIPPED: cannot create a network namespace here (unshare -n refused)"
  exit 77
fi

# LCM's short-message UDP packet: magic "LC02", a sequence number, the channel, NUL, the payload
# (here 5 bytes: not an amb_currents_t). 100 of them over about 1 s, from 0.3 s on: hil starts
# listening within that (a slow, e.g. sanitized, build may miss the first ones). The loop runs
# at 2 kHz: at 20 kHz its own sensor messages, looped back to its socket, filled the socket's
# buffer whenever a loaded host held its receive thread back, and the kernel dropped all but a
# few of these among them.
cat >"$work/send.py" <<'PY'
import socket, struct, time
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
s.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_TTL, 0)
for seq in range(100):
    s.sendto(struct.pack(">II", 0x4C433032, seq) + b"AMBDROP_CURRENTS\0" + b"\1\2\3\4\5",
             ("239.255.76.67", 7667))
    time.sleep(0.01)
PY
unshare -n bash -c "
  ip link set lo up
  ip route add 239.0.0.0/8 dev lo
  ( sleep 0.3; python3 '$work/send.py' ) &
  rc=0
  '$tool' hil '$config' --controller lcm --set controller.rate_Hz=2000 \
    --set simulation.duration_s=1.5 --set trigger.time_s=1.4 \
    --out '$work/out' --quiet 2>'$work/err.txt' || rc=\$?
  echo \$rc >'$work/rc'
  wait
"
rc=$(cat "$work/rc")
[[ $rc -eq 1 ]] || fail "hil with malformed controller packets exited $rc, not 1: $(cat "$work/err.txt")"
grep -q "error: [0-9]* controller messages were refused" "$work/err.txt" ||
  fail "no error names the refused messages: $(cat "$work/err.txt")"
python3 - "$work/out/summary.json" <<'PY' || fail "summary.json: $(cat "$work/out/summary.json")"
import json, sys
s = json.load(open(sys.argv[1]))
assert s["status"] == "controller_messages_rejected", s["status"]
assert 0 < s["lcm"]["malformed_decode"] <= 100, s["lcm"]
assert s["lcm"]["malformed_non_finite"] == s["lcm"]["malformed_current_bound"] == 0, s["lcm"]
PY
echo "hostile lcm: ok"
