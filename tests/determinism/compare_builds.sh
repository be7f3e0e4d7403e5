#!/usr/bin/env bash
# Runs the optimised and the -O0 builds of run_hash and compares their hashes of the same run.
# Usage: compare_builds.sh RUN_HASH RUN_HASH_DEBUG SOURCE_DIR
set -euo pipefail
for config in jarroux2019_industrial_pid.toml jarroux2019_industrial.toml; do
  release=$("$1" "$3" "$config")
  debug=$("$2" "$3" "$config")
  echo "$config: optimised $release"
  echo "$config: -O0 -g    $debug"
  [[ $release == "$debug" ]] || {
    echo "FAIL: $config: the -O0 build's results differ from the optimised build's"
    exit 1
  }
done
