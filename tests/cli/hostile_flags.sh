#!/usr/bin/env bash
# Number flags that are not finite, or absurd: a usage error (exit 64) naming the flag, before
# anything runs or is written.
# Usage: hostile_flags.sh AMBDROP_BINARY SOURCE_DIR
source "$(dirname "$0")/../support/cli_prelude.sh" "$@"
pid=$source_dir/configs/jarroux2019_industrial_pid.toml

# expect_usage FLAG VALUE COMMAND...: COMMAND with FLAG VALUE exits 64 naming FLAG, writes nothing.
expect_usage() {
  local flag=$1 value=$2
  shift 2
  local rc=0
  timeout 20 "$tool" "$@" "$flag" "$value" --out out >/dev/null 2>err.txt || rc=$?
  [[ $rc -eq 64 ]] || fail "$* $flag $value exited $rc, not 64: $(head -c 300 err.txt)"
  grep -q -- "$flag" err.txt || fail "$* $flag $value: the error does not name $flag: $(head -c 300 err.txt)"
  [[ ! -e out ]] || fail "$* $flag $value wrote outputs"
}

# D8: modes at a speed that is no speed.
for value in nan inf -inf 1e300; do
  expect_usage --speed-rpm "$value" modes "$pid"
done
# D9: the watchdog timeout (nan became -9223372036854775808 ns) and its neighbours.
for value in nan inf 1e300; do
  expect_usage --watchdog-s "$value" hil "$pid" --virtual-clock
  expect_usage --lockstep-timeout-s "$value" hil "$pid" --virtual-clock
done
expect_usage --spin-us nan hil "$pid" --virtual-clock
# The other number flags.
expect_usage --rate-Hz nan measure "$pid"
expect_usage --current-noise-A inf measure "$pid"
expect_usage --lead-s nan fit "$pid"
expect_usage --tolerance inf fit "$pid"
expect_usage --profile-from nan replay none.lcm --export-profile out.toml
expect_usage --profile-to inf replay none.lcm --export-profile out.toml

# D9: validate -q without its configs folder said nothing and exited 1.
rc=0
"$tool" validate -q --configs "$work/no_such_folder" --out out >/dev/null 2>err.txt || rc=$?
[[ $rc -eq 2 ]] || fail "validate without its configs folder exited $rc, not 2: $(cat err.txt)"
grep -q -- "--configs $work/no_such_folder: not a folder of seed rig configs" err.txt ||
  fail "validate -q without its configs folder: unclear error: $(cat err.txt)"

echo "hostile flags: ok"
