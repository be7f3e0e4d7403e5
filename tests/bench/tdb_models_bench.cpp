// ns per step and real-time factor per TDB model on the seed-000 rig (12 modes, 5 us step),
// dropped at 6500 rpm and on its TDBs: #1 contact law, #2 4-DOF Kelvin-Voigt (linearised and
// Hertz bearing), #3 4-DOF Dahl. Run: build/tests/tdb_models_bench
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "rt_core/model.hpp"
#include "rt_core/simulator.hpp"
#include "test_configs.hpp"

namespace ambdrop {
namespace {

void RunDropped(benchmark::State& bench, const char* config,
                const std::vector<std::string>& overrides) {
  const Model model = BuildModel(testing::LoadTestConfig(config, overrides));
  Simulator sim(model);
  State s = sim.InitialState();
  const ControlInput input = ControlInput::PowerOff();
  // Start from a rotor already on its TDBs, spinning up the races.
  for (int i = 0; i < 20000; ++i) (void)sim.Step(&s, input);
  const State start = s;
  std::int64_t steps = 0;
  for (auto _ : bench) {
    if (sim.Step(&s, input) != StepStatus::kOk) s = start;
    ++steps;
  }
  bench.SetItemsProcessed(steps);
  // Simulated seconds per wall second: >1 is faster than real time.
  bench.counters["realtime_factor"] = benchmark::Counter(
      static_cast<double>(steps) * model.params.simulation.step_s, benchmark::Counter::kIsRate);
}

void BM_Model1ContactLaw(benchmark::State& s) {
  RunDropped(s, "jarroux2019_industrial.toml", {});
}
void BM_Model2FourDofKelvinVoigt(benchmark::State& s) {
  RunDropped(s, "jarroux2019_industrial_model2.toml", {});
}
void BM_Model2FourDofKelvinVoigtHertz(benchmark::State& s) {
  RunDropped(s, "jarroux2019_industrial_model2.toml",
             {"tdb.de.four_dof.bearing_law=\"hertz\"", "tdb.nde.four_dof.bearing_law=\"hertz\""});
}
void BM_Model3FourDofDahl(benchmark::State& s) {
  RunDropped(s, "jarroux2019_industrial_model3.toml", {});
}
BENCHMARK(BM_Model1ContactLaw);
BENCHMARK(BM_Model2FourDofKelvinVoigt);
BENCHMARK(BM_Model2FourDofKelvinVoigtHertz);
BENCHMARK(BM_Model3FourDofDahl);

}  // namespace
}  // namespace ambdrop

BENCHMARK_MAIN();
