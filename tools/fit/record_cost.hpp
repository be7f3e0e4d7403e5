#pragma once
// The fit's cost: the residual of a model against the record as one vector, each compared
// sample of channel c divided by that channel's measured range and by sqrt(samples of c), so
// that its squared norm is the sum over channels of (rms_c / range_c)^2: channels in different
// units weigh alike, and the vector's length is the same for every model tried.
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "io/config_measurement.hpp"
#include "io/measured_csv.hpp"
#include "rt_core/model_params.hpp"
#include "tools/fit/simulate_on_record.hpp"

namespace ambdrop {

class RecordCost {
 public:
  /// `max_samples_per_channel` thins the compared rows evenly (the cost of the linear algebra,
  /// not of the simulation, grows with it).
  RecordCost(const ModelParams& declared, const MeasurementParams& measurement,
             const MeasuredRecord& record, const RecordRunOptions& run,
             std::size_t max_samples_per_channel = 3000);

  /// The residual vector of `params` (a copy of the declared ones with effects applied). A run
  /// that stops early scores every sample it did not reach as a full range off.
  Eigen::VectorXd Residual(const ModelParams& params) const;
  /// The same for the run already made.
  Eigen::VectorXd Residual(const SimulatedRecord& sim) const;
  SimulatedRecord Simulate(const ModelParams& params) const;

  /// The overall relative RMS a perfect model would leave: each channel's measurement noise
  /// (tools/fit/noise_floor.hpp, over the whole record) over its range, as in the cost.
  double NoiseFloor() const;

  std::size_t size() const { return index_.size(); }
  int channels() const { return channels_; }
  const ModelParams& declared() const { return declared_; }
  const MeasurementParams& measurement() const { return measurement_; }
  const MeasuredRecord& record() const { return record_; }
  const RecordRunOptions& run_options() const { return run_; }
  double trigger_time_s() const { return trigger_s_; }

 private:
  struct Sample {
    std::size_t channel;
    std::size_t row;
    double weight;  // 1 / (range * sqrt(n))
    double range;   // the channel's measured range
  };
  const ModelParams& declared_;
  const MeasurementParams& measurement_;
  const MeasuredRecord& record_;
  RecordRunOptions run_;
  double trigger_s_ = 0.0;
  int channels_ = 0;
  std::vector<Sample> index_;
  std::vector<int> column_;    // record column per measurement channel
  std::vector<double> range_;  // per measurement channel; 0 if not compared
};

}  // namespace ambdrop
