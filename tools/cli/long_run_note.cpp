#include "tools/cli/long_run_note.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <string>

#include "rt_core/simulator.hpp"

namespace ambdrop {
namespace {

// Shorter runs start without a word.
constexpr double kLongRunWall_s = 60.0;
// Below this many steps no model here takes a minute (the largest run ~10^5 steps/s).
constexpr std::int64_t kStepsWorthTiming = 1'000'000;

std::string Duration(double s) {
  if (s < 120.0) return fmt::format("{:.0f} s", s);
  if (s < 7200.0) return fmt::format("{:.0f} min", s / 60.0);
  if (s < 172800.0) return fmt::format("{:.1f} h", s / 3600.0);
  return fmt::format("{:.1f} days", s / 86400.0);
}

// Steps per second of wall time, from a burst of the model's first steps (powered, at rest:
// contact phases are slower, so this is a lower bound on the time).
double MeasuredStepRate(const Model& model) {
  Simulator sim(model);
  const ControlInput input = StaticLoadInput(model);
  State state = sim.InitialState(input);
  const auto start = std::chrono::steady_clock::now();
  std::int64_t steps = 0;
  double elapsed_s = 0.0;
  bool ok = true;
  while (ok && steps < 20000 && elapsed_s < 0.05) {
    for (int i = 0; ok && i < 100; ++i, ++steps) ok = sim.Step(&state, input) == StepStatus::kOk;
    elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return elapsed_s > 0.0 ? static_cast<double>(steps) / elapsed_s : 0.0;
}

}  // namespace

void NoteLongRun(const Model& model, bool real_time) {
  const double dt = model.params.simulation.step_s;
  const double simulated_s = static_cast<double>(model.total_steps) * dt;
  double wall_s = simulated_s;
  std::string how = "in real time";
  if (!real_time) {
    if (model.total_steps < kStepsWorthTiming) return;
    const double rate = MeasuredStepRate(model);
    if (!(rate > 0.0)) return;
    wall_s = static_cast<double>(model.total_steps) / rate;
    how = fmt::format("at about {:.3g} steps/s here", rate);
  }
  if (wall_s < kLongRunWall_s) return;
  fmt::print(stderr,
             "note: a long run: {} steps of {:.6g} s ({:.6g} s simulated) take roughly {} {} "
             "(simulation.max_steps = {})\n",
             model.total_steps, dt, simulated_s, Duration(wall_s), how,
             model.params.simulation.max_steps);
  std::fflush(stderr);
}

}  // namespace ambdrop
