// The fit's diagnosis reads the residual's signatures the way a rotordynamicist would: a rest
// position off by a constant points at misalignment or sensor offset, currents that fade after
// power loss where the model's vanish at once point at flux decay (with its time constant), a
// fall that comes later than the model's shows as a lag, synchronous content while levitated
// points at runout or unbalance; and the drop's features are read alike from record and model.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "test_configs.hpp"
#include "tools/fit/drop_features.hpp"

namespace ambdrop::drop_features_test {
namespace {

constexpr double kDt = 5e-5;  // 20 kHz
constexpr double kTrigger = 0.1;
constexpr double kEnd = 0.3;
constexpr double kClearance = 0.25e-3;

// A vertical channel that levitates at 0, falls under gravity from `fall_at`, bounces once and
// rests at -clearance (+ `rest_offset`).
double Drop(double t, double fall_at, double rest_offset) {
  if (t < fall_at) return 0.0;
  const double fall = std::min(0.5 * 9.81 * (t - fall_at) * (t - fall_at), kClearance);
  const double t_hit = fall_at + std::sqrt(2 * kClearance / 9.81);
  const double bounce =
      t > t_hit ? 1e-4 * std::exp(-(t - t_hit) / 0.01) * std::abs(std::sin(300.0 * (t - t_hit)))
                : 0.0;
  return -fall + bounce + (t > t_hit ? rest_offset * std::min(1.0, (t - t_hit) / 0.02) : 0.0);
}

struct Case {
  MeasuredRecord record;
  SimulatedRecord model;
  MeasurementParams measurement;
  ModelParams params;
};

// Record and model alike but for what the test adds.
Case Make(double measured_fall_delay, double rest_offset, double fade_tau, double runout_m) {
  Case c;
  c.params = testing::LoadTestConfig("jarroux2019_industrial_pid.toml");
  const double spin = c.params.simulation.spin_speed_rad_s;
  c.record.columns = {"y_de", "i_de_y"};
  c.measurement.sample_rate_Hz = 1 / kDt;
  c.measurement.trigger_time_s = kTrigger;
  MeasurementChannel y;
  y.column = "y_de";
  y.quantity = MeasuredQuantity::kDisplacement;
  y.index = 0;
  y.axis = 1;
  MeasurementChannel i = y;
  i.column = "i_de_y";
  i.quantity = MeasuredQuantity::kCurrent;
  c.measurement.channels = {y, i};
  c.record.values.assign(2, {});
  c.model.values.assign(2, {});
  c.model.trigger_time_s = kTrigger;
  c.model.closed_loop = true;
  for (double t = 0.0; t <= kEnd + 1e-12; t += kDt) {
    c.record.time_s.push_back(t);
    const double runout = runout_m * std::cos(spin * t + 0.3);
    c.record.values[0].push_back(Drop(t, kTrigger + measured_fall_delay, rest_offset) + runout);
    c.model.values[0].push_back(Drop(t, kTrigger, 0.0));
    const double levitating = 1.4;
    c.record.values[1].push_back(
        t < kTrigger ? levitating
                     : (fade_tau > 0 ? levitating * std::exp(-(t - kTrigger) / fade_tau) : 0.0));
    c.model.values[1].push_back(t < kTrigger ? levitating : 0.0);
  }
  c.model.rows = c.record.time_s.size();
  return c;
}

const Signature* Find(const std::vector<Signature>& s, const std::string& kind) {
  for (const Signature& x : s) {
    if (x.kind == kind) return &x;
  }
  return nullptr;
}

TEST(DropSignatures, RestOffsetPointsAtMisalignment) {
  const Case c = Make(0.0, 3e-5, 0.0, 0.0);
  const auto s = ResidualSignatures(c.params, c.measurement, c.record, c.model);
  const Signature* offset = Find(s, "offset");
  ASSERT_NE(offset, nullptr);
  EXPECT_NEAR(offset->value, 3e-5, 3e-6);
  EXPECT_NE(std::find(offset->points_to.begin(), offset->points_to.end(), "tdb_misalignment"),
            offset->points_to.end());
  EXPECT_EQ(Find(s, "decay"), nullptr);
  EXPECT_EQ(Find(s, "lag"), nullptr);
}

TEST(DropSignatures, FadingCurrentsGiveTheFluxDecayTimeConstant) {
  const Case c = Make(0.0, 0.0, 4e-3, 0.0);
  const auto s = ResidualSignatures(c.params, c.measurement, c.record, c.model);
  ASSERT_FALSE(s.empty());
  EXPECT_EQ(s.front().kind, "decay");
  EXPECT_NEAR(s.front().value, 4e-3, 0.1e-3);  // the integral of exp(-t/tau) over its start
  EXPECT_EQ(s.front().points_to, std::vector<std::string>{"amb_flux_decay"});
}

TEST(DropSignatures, ALaterFallShowsAsALag) {
  const Case c = Make(1.5e-3, 0.0, 0.0, 0.0);
  const auto s = ResidualSignatures(c.params, c.measurement, c.record, c.model);
  const Signature* lag = Find(s, "lag");
  ASSERT_NE(lag, nullptr);
  EXPECT_NEAR(lag->value, 1.5e-3, 2 * kDt);
}

TEST(DropSignatures, LevitatedRunoutShowsSynchronously) {
  const Case c = Make(0.0, 0.0, 0.0, 1e-5);
  const auto s = ResidualSignatures(c.params, c.measurement, c.record, c.model);
  const Signature* sync = Find(s, "synchronous_1x");
  ASSERT_NE(sync, nullptr);
  EXPECT_NEAR(sync->value, 1e-5, 0.05e-5);
  EXPECT_EQ(Find(s, "synchronous_2x"), nullptr);
}

TEST(DropFeatures, ReadAlikeFromRecordAndModel) {
  const double fall = std::sqrt(2 * kClearance / 9.81);
  const Case late = Make(1e-3, 0.0, 0.0, 0.0);
  bool contact = false;
  for (const FeatureComparison& x :
       CompareFeatures(late.params, late.measurement, late.record, late.model)) {
    if (x.feature != "first_contact_s") continue;
    contact = true;
    // 90 % of the way down: sqrt(0.9) of the free-fall time.
    EXPECT_NEAR(x.model, std::sqrt(0.9) * fall, 2 * kDt);
    EXPECT_NEAR(x.measured - x.model, 1e-3, 2 * kDt);
  }
  EXPECT_TRUE(contact);
  const Case offset = Make(0.0, 2e-5, 0.0, 0.0);
  bool rest = false;
  for (const FeatureComparison& x :
       CompareFeatures(offset.params, offset.measurement, offset.record, offset.model)) {
    if (x.feature != "rest_position_m") continue;
    rest = true;
    EXPECT_NEAR(x.measured - x.model, 2e-5, 1e-6);
  }
  EXPECT_TRUE(rest);
}

}  // namespace
}  // namespace ambdrop::drop_features_test
