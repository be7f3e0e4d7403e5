# Sourced by the client-kit tests, after cli_prelude.sh (tool, source_dir, work, fail): installs
# this build into $work/prefix with `cmake --install` and builds the kit's example project
# against it with find_package(ambdrop) into $work/ex (the CAN example on the PID rig's [can]
# table). Sets prefix and kit_args (the examples' controller flags, from the plant description
# of CONFIG, by names).
# Usage: kit_build CONFIG
kit_build() {
  local build_dir
  build_dir=$(cd "$(dirname "$tool")/.." && pwd)
  prefix=$work/prefix
  cmake --install "$build_dir" --prefix "$prefix" >install.log 2>&1 ||
    fail "cmake --install: $(tail -5 install.log)"
  cmake -S "$prefix/share/ambdrop/examples" -B ex -G Ninja -DCMAKE_PREFIX_PATH="$prefix" \
    -DAMBDROP_CAN_CONFIG="$source_dir/configs/jarroux2019_industrial_pid_can.toml" \
    >configure.log 2>&1 || fail "the examples do not configure: $(tail -20 configure.log)"
  cmake --build ex >build.log 2>&1 || fail "the examples do not build: $(tail -20 build.log)"
  [[ -x ex/lcm_pid && -x ex/can_pid && -s ex/ambdrop_can_frames.dbc ]] || fail "examples missing"
  "$prefix/bin/ambdrop" hil "$1" --describe plant.json || fail "--describe exited $?"
  # AMBs in the description's index order, each with the index of the sensor it is named to
  # read; the rates and gains of the reference controller.
  kit_args=$(python3 - plant.json <<'PY'
import json, sys
p = json.load(open(sys.argv[1]))
c = p["reference_controller"]
sensor = {s["name"]: s["index"] for s in p["sensors"]}
flags = [f"--kp {c['proportional_A_per_m']!r}", f"--ki {c['integral_A_per_m_s']!r}",
         f"--kd {c['derivative_A_s_per_m']!r}", f"--tf {c['derivative_filter_s']!r}",
         f"--limit-A {min(a['control_current_limit_A'] for a in p['ambs'])!r}"]
for a in sorted(p["ambs"], key=lambda a: a["index"]):
    x, y = a["static_current_A"]
    flags.append(f"--amb {sensor[a['sensor']]},{x!r},{y!r}")
print(" ".join(flags))
PY
)
}
