#!/usr/bin/env bash
# One fuzz target under ctest. `replay`: every input of corpus/NAME and crashes/NAME once (the
# regression cases; a past crash that comes back fails). SECONDS: libFuzzer for that long from a
# scratch copy of the corpus (the checked-in one is not written to); a crash fails the test and
# leaves its input as crash-* in the build's fuzz_artifacts/NAME/ (add it to crashes/NAME once
# fixed). Usage: run_fuzz.sh TARGET SOURCE_DIR NAME replay|SECONDS
set -euo pipefail
target=$1 dir=$2 name=$3 mode=$4
corpus="$dir/corpus/$name" crashes="$dir/crashes/$name"
inputs=("$corpus")
[[ -d $crashes ]] && inputs+=("$crashes")
artifacts="$PWD/fuzz_artifacts/$name"
mkdir -p "$artifacts"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0 UBSAN_OPTIONS=print_stacktrace=1
if [[ $mode == replay ]]; then
  # Files as arguments run each once (libFuzzer's reproduce mode).
  mapfile -t files < <(find "${inputs[@]}" -type f | sort)
  [[ ${#files[@]} -gt 0 ]] || { echo "no corpus for $name"; exit 1; }
  exec "$target" -rss_limit_mb=4096 "${files[@]}"
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp -r "$corpus/." "$work/"
exec "$target" -max_total_time="$mode" -seed=1 -rss_limit_mb=4096 -max_len=65536 \
  -timeout=20 -artifact_prefix="$artifacts/" "$work"
