#!/usr/bin/env bash
# Runs every fuzz target from a scratch copy of its corpus and prints the inputs executed, the
# seconds taken and whether it crashed (a benchmark, not a test). Either for SECONDS each, or
# (runs=N) until each has executed N inputs, which is how issue 18's ">= 1e6 inputs per decoder"
# figure is measured.
# Usage: bench_fuzz.sh BUILD_DIR [SECONDS | runs=N] [TARGET...]
set -uo pipefail
build=$1 budget=${2:-60}
shift $(($# < 2 ? $# : 2))
dir=$(cd "$(dirname "$0")" && pwd)
if [[ $budget =~ ^runs=([0-9]+)$ ]]; then
  limit=(-runs="${BASH_REMATCH[1]}")
elif [[ $budget =~ ^[0-9]+$ && $budget -gt 0 ]]; then
  limit=(-max_total_time="$budget")
else
  echo "bench_fuzz.sh: expected SECONDS (a whole number > 0) or runs=N, got '$budget'" >&2
  exit 64
fi
export ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1
echo "bench_fuzz.sh $budget: $(nproc) CPUs, load average $(cut -d' ' -f1 /proc/loadavg)," \
  "$(date -u +%Y-%m-%dT%H:%MZ)"
printf '%-20s %12s %8s %10s %s\n' target inputs seconds per_s result
status=0
for target in "$build"/tests/fuzz/fuzz_*; do
  [[ -x $target && ! -d $target ]] || continue
  name=$(basename "$target")
  if (($# > 0)) && [[ " $* " != *" $name "* ]]; then continue; fi
  work=$(mktemp -d)
  cp -r "$dir/corpus/$name/." "$work/"
  log=$(mktemp)
  start=$(date +%s.%N)
  if "$target" "${limit[@]}" -max_len=65536 -rss_limit_mb=4096 -seed=1 \
    -artifact_prefix="$work/" "$work" >"$log" 2>&1; then
    result=ok
  else
    result=CRASH status=1
    cp "$log" "/tmp/bench_fuzz_$name.log" && result="CRASH (log: /tmp/bench_fuzz_$name.log)"
  fi
  seconds=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { print b - a }')
  runs=$(grep -o 'Done [0-9]* runs' "$log" | grep -o '[0-9]*' | tail -1)
  runs=${runs:-0}
  printf '%-20s %12s %8.0f %10.0f %s\n' "$name" "$runs" "$seconds" \
    "$(awk -v r="$runs" -v s="$seconds" 'BEGIN { print r / s }')" "$result"
  rm -rf "$work" "$log"
done
exit $status
