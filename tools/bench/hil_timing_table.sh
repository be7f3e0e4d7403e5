#!/usr/bin/env bash
# Prints the README's HIL timing table (Markdown) from tests/bench/hil_timing_bench: the
# emulator's compute per period back to back, then at 20 kHz over the CAN double and over LCM
# udpm, under SCHED_OTHER and SCHED_FIFO, with the other CPU idle and loaded.
#
#   tools/bench/hil_timing_table.sh [BUILD_DIR=build] [SECONDS=60]
#
# Run it as root on an otherwise idle machine (nothing building): SCHED_FIFO, mlockall and the
# network namespace need root; without them the rows say what was refused. LCM runs inside a
# private network namespace (loopback only, multicast routed to lo), so no traffic leaves the
# host; where namespaces are refused it falls back to LCM's in-process memq:// bus and says so.
# Diagnostics (warnings, counts) go to stderr.
set -euo pipefail
build=${1:-build}
seconds=${2:-60}
bench=$build/tests/hil_timing_bench
if [[ ! -x $bench ]]; then
  echo "no $bench: configure with -DAMBDROP_BUILD_BENCHMARKS=ON and build hil_timing_bench" >&2
  exit 64
fi
bench=$(realpath "$bench")

load1=$(cut -d' ' -f1 /proc/loadavg)
if awk -v l="$load1" 'BEGIN { exit !(l > 0.5) }'; then
  echo "warning: load average $load1: the machine is not idle, the figures will show it" >&2
fi

lcm_in_netns=1
if ! unshare -n true 2>/dev/null; then
  lcm_in_netns=0
  echo "warning: no network namespace here (unshare -n refused): LCM rows use memq://" >&2
fi

run_lcm() {
  if ((lcm_in_netns)); then
    unshare -n bash -c 'ip link set lo up && ip route add 239.0.0.0/8 dev lo && exec "$@"' \
      lcm-netns "$bench" "$@"
  else
    "$bench" "$@" --lcm-url=memq://
  fi
}

echo "hil_timing_bench: ${seconds} s per row, $(nproc) CPUs, $(uname -r)," \
  "sched_rt_runtime_us $(cat /proc/sys/kernel/sched_rt_runtime_us), load average $load1"
echo
"$bench" "$seconds" --compute-only --header
for link in can lcm; do
  for sched in other fifo; do
    for load in "" --load; do
      args=("$seconds" "--link=$link" "--sched=$sched" $load)
      if [[ $link == lcm ]]; then
        run_lcm "${args[@]}"
      else
        "$bench" "${args[@]}"
      fi
    done
  done
done
echo
echo "Quantiles are histogram bucket upper edges (at most 6.25 % above the exact value); max is"
echo "exact. compute: the emulator's work per period (currents in, 10 RK4 steps of 5 us, sensor"
echo "emulation, sample out); lateness: wake-up minus deadline (the host); round trip: currents"
echo "sent by the controller stand-in until the sample computed with them arrives back; next"
echo "period: answers applied in the period right after the sample they answer. The CAN double"
echo "has no wire time (a real 1/8 Mbit/s FD bus adds ~56 us per 20-byte frame)."
