#include "controller_if/loop/replay_run.hpp"

#include <algorithm>
#include <cmath>

#include "controller_if/loop/state_dump.hpp"
#include "controller_if/loop/step_driver.hpp"

namespace ambdrop {
namespace {

// A record's events around the step driver: its power events and inputs at their steps.
struct ReplayHooks : StepHooks {
  const Model& model;
  const RecordedRun& run;
  const std::function<void(const Observation&)>& on_output;
  const std::function<void(const RecordedSensors&)>& on_sensors;
  RunRecorder* observer;
  std::size_t next_input = 0;
  std::size_t next_power = 0;
  RecordedSensors sample;

  ReplayHooks(const Model& m, const RecordedRun& r,
              const std::function<void(const Observation&)>& out,
              const std::function<void(const RecordedSensors&)>& sensors, RunRecorder* obs)
      : model(m), run(r), on_output(out), on_sensors(sensors), observer(obs) {}

  void OnSensors(StepDriver& d, std::int64_t k) noexcept {
    sample.step = k;
    sample.time_s = d.observation().time_s;
    sample.readings = d.readings();
    if (on_sensors) on_sensors(sample);
    if (observer != nullptr) observer->OnSensors(sample);
  }
  void PowerEvents(StepDriver& d, std::int64_t k) noexcept {
    // Events recorded for steps already passed cannot come from a live run; skip them.
    while (next_power < run.power.size() && run.power[next_power].step < k) ++next_power;
    for (; next_power < run.power.size() && run.power[next_power].step == k; ++next_power) {
      d.ApplyPower(run.power[next_power].event);
    }
  }
  bool Command(StepDriver& d, std::int64_t k) noexcept {
    while (next_input < run.inputs.size() && run.inputs[next_input].step < k) ++next_input;
    for (; next_input < run.inputs.size() && run.inputs[next_input].step == k; ++next_input) {
      const RecordedInput& in = run.inputs[next_input];
      switch (in.kind) {
        case RecordedInputKind::kCurrents:
          for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
            d.command()[a] = in.current_A[a];
          }
          break;
        case RecordedInputKind::kWatchdogZero:
          for (std::size_t a = 0; a < model.params.ambs.size(); ++a) d.command()[a] = {0.0, 0.0};
          break;
        case RecordedInputKind::kWatchdogStop:
          return false;
      }
    }
    return true;
  }
  void OnOutput(StepDriver& d) noexcept { Output(d.state(), d.observation()); }
  void Output(const State& state, const Observation& o) noexcept {
    if (on_output) on_output(o);
    if (observer != nullptr) observer->OnState(state, o);
  }
};

}  // namespace

ReplayResult ReplayRun(const Model& model, const RecordedRun& run,
                       const std::function<void(const Observation&)>& on_output,
                       const std::function<void(const RecordedSensors&)>& on_sensors,
                       const std::function<void(double)>& on_progress, RunRecorder* observer) {
  StepDriver driver(model, std::max<std::int64_t>(0, run.sensor_every_steps));
  ControlInput input;
  for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
    input.amb[a].current_A = run.start.loop_current_A[a];
  }
  driver.SetInput(input);
  ReplayHooks hooks(model, run, on_output, on_sensors, observer);
  ReplayResult result;
  const State initial = driver.sim().InitialState(run.start.equilibrium_input);
  if (on_output || observer != nullptr) {
    Observation first;
    driver.sim().Observe(initial, &first);
    hooks.Output(initial, first);
  }
  driver.Start(initial);
  const std::int64_t end = run.end_step;
  const std::int64_t progress_every = std::max<std::int64_t>(1, end / 200);
  while (driver.state().step_index < end) {
    if (!driver.Step(hooks)) {
      if (driver.stopped()) {
        result.watchdog_stop = true;
      } else {
        result.status = driver.status();
        result.failure_message = DescribeFailure(model, driver.status(), driver.state());
      }
      break;
    }
    const std::int64_t k = driver.state().step_index;
    if (on_progress && k % progress_every == 0) {
      on_progress(static_cast<double>(k) / static_cast<double>(end));
    }
  }
  // The sample at the end step, as the live run took it.
  if (result.status == StepStatus::kOk && !result.watchdog_stop) driver.SampleNow(hooks);
  result.steps = driver.state().step_index;
  result.final_state = driver.state();
  return result;
}

}  // namespace ambdrop
