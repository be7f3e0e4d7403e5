#!/usr/bin/env bash
# Config values that cannot make a run: each is a config error (exit 2) that names the file (or
# --set) and line, the key, the range expected and the value found; a long run is announced on
# stderr before it starts.
# Usage: hostile_configs.sh AMBDROP_BINARY SOURCE_DIR
source "$(dirname "$0")/../support/cli_prelude.sh" "$@"
pid=$source_dir/configs/jarroux2019_industrial_pid.toml

# Runs `ambdrop sim` on $1 with the other arguments as --set overrides; expects exit $expected_rc
# and every pattern of "${expected[@]}" on stderr.
expect_error() {
  local config=$1
  shift
  local sets=()
  for s in "$@"; do sets+=(--set "$s"); done
  local rc=0
  timeout 20 "$tool" sim "$config" "${sets[@]}" --out out -q 2>err.txt >/dev/null || rc=$?
  [[ $rc -eq $expected_rc ]] || fail "sim $* exited $rc, not $expected_rc: $(cat err.txt)"
  for pattern in "${expected[@]}"; do
    grep -q -- "$pattern" err.txt || fail "sim $*: no '$pattern' in: $(cat err.txt)"
  done
}

# D6: a duration beyond simulation.max_steps (1e300 s overflowed the step count to 0 steps and
# exited 0), and a lowered ceiling.
expected_rc=2
expected=("--set simulation.duration_s=1e300: key 'simulation.duration_s': expected simulation.duration_s <= 5000 s: at most simulation.max_steps = 1000000000 steps" "found duration_s = 1e+300 s")
expect_error "$pid" simulation.duration_s=1e300
expected=("key 'simulation.duration_s'" "max_steps = 1000 steps")
expect_error "$pid" simulation.duration_s=0.05 simulation.max_steps=1000
expected=("key 'simulation.max_steps': expected an integer in \[1, ")
expect_error "$pid" simulation.max_steps=0
# A long run says so before it starts (stopped at once: only the note is wanted).
rc=0
timeout 5 "$tool" sim "$pid" --set simulation.duration_s=2000 --set simulation.output_interval_s=1 \
  --out long -q 2>long.err >/dev/null || rc=$?
[[ $rc -eq 124 ]] || fail "a 2000 s run ended within 5 s (exit $rc): $(cat long.err)"
grep -q "note: a long run: 400000000 steps of 5e-06 s (2000 s simulated) take roughly" long.err ||
  fail "no note before a long run: $(cat long.err)"

# D7: a sensor lag of 1e6 s (wrapped to "-1474836480 samples", exit 1, no file or key) or 1e300 s
# (silently no lag), from --set and from a file.
expected=("--set sensor.de.lag.delay_s=1e6: key 'sensor.de.lag.delay_s': expected at most 255 samples of the controller period (1/controller.rate_Hz) = 5e-05 s: a number in \[0, 0.01275\] (s), found 1000000")
expect_error "$pid" sensor.de.lag.enabled=true sensor.de.lag.delay_s=1e6
expected=("key 'sensor.de.lag.delay_s'" "found 1e+300")
expect_error "$pid" sensor.de.lag.enabled=true sensor.de.lag.delay_s=1e300
cp "$source_dir/configs/jarroux2019_industrial.toml" "$source_dir/configs/jarroux2019_industrial_pid.toml" .
printf '\n[sensor.de.lag]\nenabled = true\ndelay_s = 1e6\n' >>jarroux2019_industrial_pid.toml
line=$(grep -n '^delay_s = 1e6' jarroux2019_industrial_pid.toml | cut -d: -f1)
expected=("jarroux2019_industrial_pid.toml:$line: key 'sensor.de.lag.delay_s': expected at most 255 samples")
expect_error jarroux2019_industrial_pid.toml
# Without a controller, `sim` samples the sensors at every step: the bound is 255 steps.
expected=("key 'sensor.de.lag.delay_s': expected at most 255 samples of the step (simulation.step_s; \[controller\] kind = \"none\") = 5e-06 s: a number in \[0, 0.001275\] (s), found 0.005")
expect_error jarroux2019_industrial.toml sensor.de.lag.enabled=true sensor.de.lag.delay_s=0.005

# D9: a folder as the config (read as an empty file), a base that never ends (/dev/zero read
# until bad_alloc), a shaft of 100000 elements (a bare std::bad_alloc), and a controller rate that
# is not a whole number of steps (exit 1, no file or line, a 0.1 us step printed as 0.000000 s).
mkdir folder.toml
expected=("folder.toml: not a readable config file: .*folder.toml is not a regular file (a folder)")
expect_error folder.toml
printf 'base = "/dev/zero"\n' >zero.toml
expected=("zero.toml:1: key 'base': expected a readable config file, found \"/dev/zero\" (/dev/zero is not a regular file")
expect_error zero.toml
sed '0,/^elements = [0-9]*/s//elements = 100000/' "$source_dir/configs/jarroux2019_industrial.toml" >elements.toml
line=$(grep -n '^elements = 100000' elements.toml | cut -d: -f1)
expected=("elements.toml:$line: key 'rotor.sections\[0\].elements': expected an integer in \[1, 500\], found 100000")
expect_error elements.toml
expected=("--set controller.rate_Hz=30000: key 'controller.rate_Hz': expected a rate whose period is a whole number of steps of simulation.step_s = 5e-06 s (e.g. 28571.4 Hz), found 30000 Hz, a period of 6.66667 steps")
expect_error "$pid" controller.rate_Hz=30000
expected=("step_s = 1e-07 s")
expect_error "$pid" simulation.step_s=1e-7 controller.rate_Hz=30000
rc=0
"$tool" hil "$pid" --set controller.rate_Hz=30000 --virtual-clock --out hil -q 2>hil.err || rc=$?
[[ $rc -eq 2 ]] || fail "hil with a rate of 6.67 steps exited $rc, not 2: $(cat hil.err)"

# Numbers that become counts or durations through llround: a sensor's counts per metre and
# offset, a scenario's watchdog timeout (1e300 s overflowed to garbage nanoseconds).
expected=("key 'sensor.de.counts_per_m': expected a positive number of at most 1e12" "found 1e+300")
expect_error "$pid" sensor.de.output=counts sensor.de.counts_per_m=1e300
expected=("key 'sensor.de.counts_offset': expected a number in \[-1000000000000, 1000000000000\]")
expect_error "$pid" sensor.de.output=counts sensor.de.counts_per_m=1e6 sensor.de.counts_offset=1e300
expected=("key 'scenario.watchdog_timeout_s': expected a positive number of at most 1e6 (s), found 1e+300")
expect_error "$source_dir/configs/scenarios/power_loss.toml" scenario.watchdog_timeout_s=1e300

echo "hostile configs: ok"
