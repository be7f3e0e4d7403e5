#!/usr/bin/env bash
# Every test of ambdrop, as CI runs them: the README's test command ends with this script, and
# .ci/run runs that command. The jobs (format, release, asan with the fuzz targets, tsan) run
# one after another (CI has 2 cores and 30 minutes for all of them); each prints "ok" or
# "FAILED" with its time, and the exit code is non-zero when any job failed, so a CI job can be
# built on it. Run one job alone with its name as argument:
#   tests/run_all.sh [format|release|asan|tsan|fuzz]...
set -uo pipefail
cd "$(dirname "$0")/.."
cores=$(nproc)
failed=()
declare -A took

run_job() {
  local name=$1
  shift
  local start=$SECONDS
  echo "=== $name"
  if "$@"; then
    took[$name]="ok, $((SECONDS - start)) s"
  else
    took[$name]="FAILED, $((SECONDS - start)) s"
    failed+=("$name")
  fi
  echo "=== $name: ${took[$name]}"
}

# The tree is clang-format-14 clean; another version formats a few constructs differently.
format_check() {
  find rt_core io controller_if tools tests \( -name '*.cpp' -o -name '*.hpp' \) -print0 |
    xargs -0 clang-format-14 --dry-run --Werror
}

# The build users get: Release, warnings as errors, every test (validation, golden hashes, the
# hw tests in the qemu VM) but no benchmarks.
release() {
  # The hw tests' VM cache (packages, Debian's kernel, gpio-sim) fills beside the build: its
  # downloads wait on the network, and in a test slot they left a core idle (the first hw test
  # took ~47 s longer than the others). The hw tests wait on its lock; its log is kept.
  mkdir -p build
  bash tests/hw/run_in_vm.sh --prepare >build/vm_prepare.log 2>&1 &
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DAMBDROP_WERROR=ON \
    -DAMBDROP_BUILD_BENCHMARKS=OFF &&
    cmake --build build &&
    ctest --test-dir build --output-on-failure -j "$cores"
}

# ASan+UBSan at -O1 with asserts on, line tables only (-g1: file and line in the reports, a
# third less compile time than -g) (tests/CMakeLists.txt lists what it runs): the command line
# and the listed test programs are built, nothing else (the truth generator and the stand-in
# controller are not run under ASan). Built by clang 14: the same build took 318 s where GCC 12
# took 438 s (rt_core/simulator.cpp alone 38 s against 65 s), and the 417 tests pass under both.
# No -Werror: GCC 12 warns falsely under the sanitizers, and the Release job holds the tree to
# GCC's warnings. The same tree builds the libFuzzer targets of every decoder and runs them (the
# corpus and past crashes replayed, then each target fuzzed for AMBDROP_FUZZ_SECONDS, 5 s, two
# at a time; tests/fuzz/README.md runs them longer): a tree of their own would compile rt_core, io
# and controller_if a third time (~190 s of CI).
asan() {
  cmake -S . -B build-asan -G Ninja -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=Debug \
    -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1" \
    -DAMBDROP_SANITIZE=ON -DAMBDROP_FUZZ=ON -DAMBDROP_BUILD_BENCHMARKS=OFF &&
    cmake --build build-asan --target ambdrop ambdrop_test_programs ambdrop_fuzz_targets &&
    ASAN_OPTIONS=detect_leaks=1:abort_on_error=0 UBSAN_OPTIONS=print_stacktrace=1 \
      ctest --test-dir build-asan --output-on-failure -j "$cores"
}

# The fuzz targets in a tree of their own, every library instrumented for coverage (not in the
# default list: the asan job runs them; this one is for fuzzing longer, tests/fuzz/README.md).
fuzz() {
  CXX=clang++-14 cmake -S . -B build-fuzz -G Ninja -DAMBDROP_FUZZ=ON -DCMAKE_BUILD_TYPE=Debug \
    -DCMAKE_CXX_FLAGS_DEBUG="-O1" -DAMBDROP_BUILD_BENCHMARKS=OFF &&
    cmake --build build-fuzz --target ambdrop_fuzz_targets &&
    ctest --test-dir build-fuzz -L fuzz --output-on-failure -j "$cores"
}

# TSan at -O1 on the threaded tests only; the tools are not built. Clang 14 too: 91 s to build
# where GCC 12 took about 113 s.
tsan() {
  cmake -S . -B build-tsan -G Ninja -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=Debug \
    -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1" \
    -DAMBDROP_TSAN=ON -DAMBDROP_BUILD_BENCHMARKS=OFF &&
    cmake --build build-tsan --target ambdrop_test_programs &&
    ctest --test-dir build-tsan --output-on-failure -j "$cores"
}

selected=("$@")
[[ ${#selected[@]} -gt 0 ]] || selected=(format release asan tsan)
for job in "${selected[@]}"; do
  case $job in
    format) run_job format format_check ;;
    release) run_job release release ;;
    asan) run_job asan asan ;;
    tsan) run_job tsan tsan ;;
    fuzz) run_job fuzz fuzz ;;
    *)
      echo "unknown job '$job' (expected format, release, asan, tsan or fuzz)" >&2
      exit 64
      ;;
  esac
done

echo "=== summary (${SECONDS} s in all)"
for job in "${selected[@]}"; do echo "  $job: ${took[$job]}"; done
if [[ ${#failed[@]} -gt 0 ]]; then
  echo "FAILED: ${failed[*]}"
  exit 1
fi
echo "all jobs ok"
