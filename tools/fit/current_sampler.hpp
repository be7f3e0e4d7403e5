#pragma once
// The coil control currents a coil-current sensor reads at each sample of a run, from the run's
// recorded inputs and power events: shared by `ambdrop measure` (tools/fit/
// measured_record_maker.hpp), which samples a truth run as it goes, and by a run record read as
// a measurement (tools/fit/run_record_measurement.hpp), which feeds it the recorded events.
#include <array>
#include <cstdint>
#include <vector>

#include "controller_if/loop/run_record.hpp"
#include "rt_core/model_params.hpp"

namespace ambdrop {

/// Each sample's coil control currents: what the controller commanded while the axis has
/// power; after it loses power the current it had then, falling by the AMB's power-loss law
/// (rt_core/power_loss_drive.hpp, ReportedCoilCurrent: by default exp(-t/tau); gone at once
/// without flux decay), as a coil-current sensor would read it. A step's input reaches the
/// recorder after that step's observation, so a sample is filled only once the input after it
/// is known: it takes the last input applied from its step or earlier. Power events come
/// before the step's input, as PowerState applies them. A watchdog's zeroing input zeroes the
/// currents; its stop input changes nothing (the run ends there).
class CurrentSampler final : public RunRecorder {
 public:
  using Currents = std::array<std::array<double, 2>, kMaxAmbs>;

  CurrentSampler(const ModelParams& params, double step_s);
  /// Called for each sample in step order, before the inputs of a later step arrive.
  void AddSample(std::int64_t step);
  /// Fills the samples still open; the last input holds to the end.
  const std::vector<Currents>& Finish() noexcept;
  /// Each sample's commanded currents, after Finish: the last input applied from its step or
  /// earlier, what the controller (on its own supply) goes on commanding after power loss.
  const std::vector<Currents>& Commanded() const noexcept { return commanded_A_; }

  void OnStart(const RecordedStart& start) noexcept override;
  void OnInput(const RecordedInput& input) noexcept override;
  void OnPower(const RecordedPower& p) noexcept override;
  void OnSensors(const RecordedSensors&) noexcept override {}
  void OnState(const State&, const Observation&) noexcept override {}

 private:
  void FillBefore(std::int64_t step) noexcept;

  const ModelParams& params_;
  double step_s_;
  std::vector<std::int64_t> steps_;
  std::vector<Currents> current_A_;
  std::vector<Currents> commanded_A_;
  std::size_t filled_ = 0;
  Currents held_{};
  Currents frozen_{};
  std::array<std::array<std::int64_t, 2>, kMaxAmbs> lost_at_{};
};

}  // namespace ambdrop
