#pragma once
#include "controller_if/loop/run_record.hpp"

namespace ambdrop {

/// Hands each event of a run to two recorders in turn (a record file and a live monitor);
/// either may be null. Real-time safe as far as both are.
class RecorderTee final : public RunRecorder {
 public:
  RecorderTee(RunRecorder* first, RunRecorder* second) : first_(first), second_(second) {}
  void OnStart(const RecordedStart& start) noexcept override {
    if (first_ != nullptr) first_->OnStart(start);
    if (second_ != nullptr) second_->OnStart(start);
  }
  void OnInput(const RecordedInput& input) noexcept override {
    if (first_ != nullptr) first_->OnInput(input);
    if (second_ != nullptr) second_->OnInput(input);
  }
  void OnPower(const RecordedPower& power) noexcept override {
    if (first_ != nullptr) first_->OnPower(power);
    if (second_ != nullptr) second_->OnPower(power);
  }
  void OnSensors(const RecordedSensors& sensors) noexcept override {
    if (first_ != nullptr) first_->OnSensors(sensors);
    if (second_ != nullptr) second_->OnSensors(sensors);
  }
  void OnState(const State& state, const Observation& observation) noexcept override {
    if (first_ != nullptr) first_->OnState(state, observation);
    if (second_ != nullptr) second_->OnState(state, observation);
  }

 private:
  RunRecorder* first_;
  RunRecorder* second_;
};

}  // namespace ambdrop
