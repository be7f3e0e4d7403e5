#!/usr/bin/env bash
# The same config run in two separate processes must give bit-identical time series: nothing
# may depend on addresses, uninitialised memory, thread timing or the environment.
# Usage: determinism_processes.sh AMBDROP_BINARY SOURCE_DIR
set -euo pipefail

tool=$1
source_dir=$2
config=$source_dir/configs/jarroux2019_industrial.toml
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

fail() {
  echo "FAIL: $*" >&2
  exit 1
}

# Run concurrently: independent processes, and half the wall time on two cores.
pids=()
for run in a b; do
  "$tool" sim "$config" --set simulation.duration_s=0.25 --out "$work/$run" --quiet \
    >/dev/null 2>"$work/$run.stderr" &
  pids+=($!)
done
for i in 0 1; do
  run=$([[ $i -eq 0 ]] && echo a || echo b)
  rc=0
  wait "${pids[$i]}" || rc=$?
  if [[ $rc -ne 0 ]]; then
    cat "$work/$run.stderr" >&2
    fail "run $run exited $rc"
  fi
done

# A header-only file would compare equal without proving anything.
rows=$(wc -l <"$work/a/timeseries.csv")
[[ $rows -gt 2 ]] || fail "run a wrote only $rows lines"

cmp "$work/a/timeseries.csv" "$work/b/timeseries.csv" ||
  fail "timeseries.csv differs between two processes"

# The summaries must match too, apart from the wall-clock figures.
python3 - "$work/a/summary.json" "$work/b/summary.json" <<'PY' || fail "summary.json differs"
import json
import sys

a, b = (json.load(open(path)) for path in sys.argv[1:3])
for summary in (a, b):
    for key in ("wall_time_s", "realtime_factor"):
        summary.pop(key, None)
if a != b:
    print(f"{a}\n!=\n{b}", file=sys.stderr)
    sys.exit(1)
PY

echo "determinism_processes: ok"
