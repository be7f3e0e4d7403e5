// `trigger = "detect"`: the power failure found in a record's coil currents lies within half a
// sample of the truth's, whether the truth's trigger falls on a sample or between two.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "test_configs.hpp"
#include "tools/fit/measured_record_maker.hpp"
#include "tools/fit/simulate_on_record.hpp"

namespace ambdrop::record_trigger_detect_test {
namespace {

double DetectedTrigger(double truth_trigger_s, double* sample_s) {
  const ModelParams truth = testing::LoadTestConfig(
      "jarroux2019_industrial_pid.toml",
      {"simulation.duration_s=0.15", "trigger.time_s=" + std::to_string(truth_trigger_s)});
  MeasureOptions noise;
  noise.current_noise_A = 0.005;
  noise.seed = 3;
  SyntheticMeasurement made = MakeMeasuredRecord(truth, noise);
  made.measurement.trigger_time_s.reset();
  made.measurement.detect_trigger = true;
  *sample_s = 1.0 / made.measurement.sample_rate_Hz;
  return RecordTriggerTime(made.measurement, made.record);
}

TEST(RecordTriggerDetect, WithinHalfASampleOnASample) {
  double sample_s = 0.0;
  const double detected = DetectedTrigger(0.1, &sample_s);
  EXPECT_LE(std::abs(detected - 0.1), 0.5 * sample_s + 1e-12) << detected;
}

TEST(RecordTriggerDetect, WithinHalfASampleBetweenSamples) {
  double sample_s = 0.0;
  // 0.3 of the way from one 20 kHz sample to the next.
  const double truth_s = 0.1 + 15e-6;
  const double detected = DetectedTrigger(truth_s, &sample_s);
  EXPECT_LE(std::abs(detected - truth_s), 0.5 * sample_s + 1e-12) << detected;
}

}  // namespace
}  // namespace ambdrop::record_trigger_detect_test
