#!/usr/bin/env bash
# Runs every fuzz target for SECONDS each from a scratch copy of its corpus and prints the
# inputs executed and whether it crashed (a benchmark, not a test).
# Usage: bench_fuzz.sh BUILD_DIR [SECONDS]
set -uo pipefail
build=$1 seconds=${2:-60}
dir=$(cd "$(dirname "$0")" && pwd)
export ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1
printf '%-20s %12s %10s %s\n' target inputs per_s result
for target in "$build"/tests/fuzz/fuzz_*; do
  [[ -x $target && ! -d $target ]] || continue
  name=$(basename "$target")
  work=$(mktemp -d)
  cp -r "$dir/corpus/$name/." "$work/"
  log=$(mktemp)
  if "$target" -max_total_time="$seconds" -max_len=65536 -rss_limit_mb=4096 \
    -artifact_prefix="$work/" "$work" >"$log" 2>&1; then result=ok; else result=CRASH; fi
  runs=$(grep -o 'Done [0-9]* runs' "$log" | grep -o '[0-9]*' | tail -1)
  runs=${runs:-0}
  printf '%-20s %12s %10s %s\n' "$name" "$runs" "$((runs / seconds))" "$result"
  rm -rf "$work" "$log"
done
