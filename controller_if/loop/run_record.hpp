#pragma once
// What a run hands its recorder, and what a replay is made of: every input the emulator applied
// (with the step it applied from), every power event, every sensor sample sent, and a periodic
// state. A run driven by these inputs at these steps is the same run, bit for bit: that is what
// `ambdrop replay` relies on. The encoding on disk (LCM event log) lives in tools/record/.
#include <array>
#include <cstdint>
#include <vector>

#include "controller_if/boundary/power_state.hpp"
#include "controller_if/boundary/sensor_emulator.hpp"
#include "rt_core/control_input.hpp"
#include "rt_core/simulator.hpp"
#include "rt_core/state.hpp"

namespace ambdrop {

/// How the run started: the input whose powered equilibrium is the initial rotor position, and
/// the currents applied until the first recorded input.
struct RecordedStart {
  ControlInput equilibrium_input;
  std::array<std::array<double, 2>, kMaxAmbs> loop_current_A{};
};

enum class RecordedInputKind : std::uint8_t {
  kCurrents = 0,      ///< the controller's currents, applied from `step`
  kWatchdogZero = 1,  ///< controller silence: currents zero from `step`
  kWatchdogStop = 2,  ///< controller silence: the run stopped at `step`
};

struct RecordedInput {
  std::int64_t step = 0;
  std::int64_t receive_ns = 0;  ///< clock time it arrived (sim: simulated time), ns
  std::uint64_t sequence = 0;
  RecordedInputKind kind = RecordedInputKind::kCurrents;
  std::array<std::array<double, 2>, kMaxAmbs> current_A{};
};

struct RecordedPower {
  std::int64_t step = 0;
  PowerEvent event;
};

struct RecordedSensors {
  std::int64_t step = 0;
  double time_s = 0.0;
  SensorReadings readings;
};

/// Receives a run's events on the real-time thread: noexcept, allocation-free, non-blocking
/// (except that an offline run may wait for room). Events of one kind arrive in step order.
class RunRecorder {
 public:
  virtual ~RunRecorder() = default;
  virtual void OnStart(const RecordedStart& start) noexcept = 0;
  virtual void OnInput(const RecordedInput& input) noexcept = 0;
  virtual void OnPower(const RecordedPower& power) noexcept = 0;
  virtual void OnSensors(const RecordedSensors& sensors) noexcept = 0;
  /// The periodic state (every output interval), with its observation.
  virtual void OnState(const State& state, const Observation& observation) noexcept = 0;
};

/// Everything a replay needs besides the config, in step order per kind.
struct RecordedRun {
  RecordedStart start;
  std::vector<RecordedInput> inputs;
  std::vector<RecordedPower> power;
  std::int64_t sensor_every_steps = 0;  ///< 0: the run sent no sensor samples
  std::int64_t end_step = 0;            ///< replay up to this step (exclusive of later events)
};

}  // namespace ambdrop
