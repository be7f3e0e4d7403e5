// ns per step and real-time factor of the seed-000 rig (12 modes, 5 us step, contact-law TDBs),
// levitated and after the drop. Run: build/tests/step_bench
#include <benchmark/benchmark.h>

#include "rt_core/model.hpp"
#include "rt_core/simulator.hpp"
#include "test_configs.hpp"

namespace ambdrop {
namespace {

void RunSteps(benchmark::State& bench, bool dropped) {
  const Model model = BuildModel(testing::LoadTestConfig("jarroux2019_industrial.toml"));
  Simulator sim(model);
  State s = sim.InitialState();
  const ControlInput input = dropped ? ControlInput::PowerOff() : ControlInput::Powered();
  if (dropped) {
    // Start from a rotor already on its TDBs, spinning up the races.
    for (int i = 0; i < 20000; ++i) (void)sim.Step(&s, input);
  }
  const State start = s;
  std::int64_t steps = 0;
  for (auto _ : bench) {
    if (sim.Step(&s, input) != StepStatus::kOk) s = start;
    ++steps;
  }
  bench.SetItemsProcessed(steps);
  const double step_s = model.params.simulation.step_s;
  // Simulated seconds per wall second: >1 is faster than real time.
  bench.counters["realtime_factor"] =
      benchmark::Counter(static_cast<double>(steps) * step_s, benchmark::Counter::kIsRate);
}

void BM_StepLevitated(benchmark::State& s) {
  RunSteps(s, false);
}
void BM_StepDropped(benchmark::State& s) {
  RunSteps(s, true);
}
BENCHMARK(BM_StepLevitated);
BENCHMARK(BM_StepDropped);

}  // namespace
}  // namespace ambdrop

BENCHMARK_MAIN();
