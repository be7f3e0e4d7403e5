#!/usr/bin/env bash
# Issue 18 item 3: the HIL loop at the controller rate (20 kHz) with 10 % malformed currents
# messages, against the same link without them, one row each from tests/bench/hil_timing_bench:
# the CAN double (a frame of the currents id too short for its signals after every 10th answer)
# and LCM udpm in a private network namespace (a packet that is no amb_currents_t after every
# 10th answer). Each row says how many faults the stand-in sent and the emulator's link counted;
# the deadlines (lateness, overruns per minute) and the compute per period are the columns to
# compare between a row and its fault-free neighbour.
#
#   tools/bench/hil_fault_rate.sh [BUILD_DIR=build] [SECONDS=20]
#
# As root on an otherwise idle machine (SCHED_FIFO, mlockall and the namespace need root; rows
# say what was refused). Needs -DAMBDROP_BUILD_BENCHMARKS=ON.
set -euo pipefail
build=${1:-build}
seconds=${2:-20}
bench=$build/tests/hil_timing_bench
if [[ ! -x $bench ]]; then
  echo "no $bench: configure with -DAMBDROP_BUILD_BENCHMARKS=ON and build hil_timing_bench" >&2
  exit 64
fi
bench=$(realpath "$bench")
run_lcm() {
  if unshare -n true 2>/dev/null; then
    unshare -n bash -c 'ip link set lo up && ip route add 239.0.0.0/8 dev lo && exec "$@"' \
      lcm-netns "$bench" "$@"
  else
    echo "warning: no network namespace here: LCM on memq://" >&2
    "$bench" "$@" --lcm-url=memq://
  fi
}
echo "hil_timing_bench: ${seconds} s per row, $(nproc) CPUs, $(uname -r)," \
  "load average $(cut -d' ' -f1 /proc/loadavg)"
echo
first=--header
for link in can lcm; do
  for faults in "" --malformed-every=10; do
    args=("$seconds" "--link=$link" "--sched=fifo" $faults $first)
    first=
    if [[ $link == lcm ]]; then run_lcm "${args[@]}"; else "$bench" "${args[@]}"; fi
  done
done
