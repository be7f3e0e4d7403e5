// Prints a hash of every bit of a run's outputs: the seed-000 PID rig (flexible rotor, AMB
// electromagnets with saturation, sensor noise, reference PID) levitated, dropped onto its
// contact-law TDBs and spinning down, observed at every step. Built twice, as this build type
// and with Debug's flags (-O0 -g, asserts on), so that ctest can check that the build types
// ambdrop ships give the same results bit for bit (tests/determinism/CMakeLists.txt).
// Usage: run_hash SOURCE_DIR [CONFIG]
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

#include "controller_if/loop/offline_run.hpp"
#include "io/config/config_loader.hpp"
#include "io/files/event_log.hpp"

namespace {

std::uint64_t Mix(std::uint64_t hash, const void* data, std::size_t size) {
  return ambdrop::Fnv1a64(
      std::span<const std::uint8_t>(static_cast<const std::uint8_t*>(data), size), hash);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: run_hash SOURCE_DIR [CONFIG]\n");
    return 64;
  }
  const std::string config =
      std::string(argv[1]) + "/configs/" + (argc > 2 ? argv[2] : "jarroux2019_industrial_pid.toml");
  const ambdrop::LoadedConfig loaded = ambdrop::LoadConfig(
      config,
      {"simulation.duration_s=0.15", "trigger.time_s=0.05", "simulation.output_interval_s=5e-6"});
  const ambdrop::Model model = ambdrop::BuildModel(loaded.params);
  std::uint64_t hash = ambdrop::kFnv1a64Basis;
  std::int64_t observations = 0;
  const ambdrop::OfflineRunResult result =
      ambdrop::RunOffline(model, [&](const ambdrop::Observation& o) {
        hash = Mix(hash, &o.time_s, sizeof o.time_s);
        hash = Mix(hash, &o.spin_speed_rad_s, sizeof o.spin_speed_rad_s);
        hash = Mix(hash, &o.spin_angle_rad, sizeof o.spin_angle_rad);
        hash = Mix(hash, &o.sensor_xy_m, sizeof o.sensor_xy_m);
        hash = Mix(hash, &o.tdb_journal_xy_m, sizeof o.tdb_journal_xy_m);
        for (const auto& t : o.tdb) {
          hash = Mix(hash, &t.normal_force_N, sizeof t.normal_force_N);
          hash = Mix(hash, &t.tangential_force_N, sizeof t.tangential_force_N);
          hash = Mix(hash, &t.tdb_spin_rad_s, sizeof t.tdb_spin_rad_s);
        }
        ++observations;
      });
  hash = Mix(hash, result.final_state.y.data(),
             sizeof(double) * static_cast<std::size_t>(result.final_state.y.size()));
  std::printf("%016llx %lld observations, status %d\n", static_cast<unsigned long long>(hash),
              static_cast<long long>(observations), static_cast<int>(result.status));
  return result.status == ambdrop::StepStatus::kOk ? 0 : 3;
}
