// measurement.trigger_state = "record" (issue 24): a magnet-biased rotor is unstable once its
// coils lose power (the magnet's negative stiffness stays), so where it goes depends on the
// levitated jitter at the trigger that its controller's answer to the sensors' noise set up,
// which no model predicts sample by sample. The fit then takes that state from a lead window
// of the record, and the current the coils held from the declared law's fit to the samples
// after the trigger.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "io/config/config_loader.hpp"
#include "rt_core/model_params.hpp"
#include "rt_core/power_loss_drive.hpp"
#include "test_configs.hpp"
#include "tools/fit/held_current.hpp"
#include "tools/fit/measured_record_maker.hpp"
#include "tools/fit/simulate_on_record.hpp"

namespace ambdrop::fit_trigger_state_test {
namespace {

constexpr const char* kRig = "jarroux2019_industrial_pid.toml";
constexpr double kTrigger_s = 0.1;

// The truth generator's magnet-biased flexible rig as ambdrop models it
// (tests/truth/flexible_pm_b.toml): a 49 kg rotor whose controller (PD, lead, notch) answers
// its sensors' 0.3 um of noise with a micrometre of jitter; after the power fails the coil
// currents ramp down and the magnets' pull stays. Its own record, shortened.
ModelParams MagnetRig() {
  return LoadConfig(std::string(AMBDROP_SOURCE_DIR) + "/tests/truth/flexible_pm_b.toml",
                    {"simulation.duration_s=0.115"})
      .params;
}

// RMS over the displacement channels of record - prediction from the trigger to 8 ms after.
double EarlyDropError(const MeasuredRecord& record, const MeasurementParams& m,
                      const SimulatedRecord& sim) {
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t c = 0; c < m.channels.size(); ++c) {
    if (m.channels[c].quantity != MeasuredQuantity::kDisplacement) continue;
    for (std::size_t j = 0; j < record.time_s.size(); ++j) {
      const double t = record.time_s[j];
      if (t < kTrigger_s || t > kTrigger_s + 8e-3) continue;
      const double e = record.values[c][j] - sim.values[c][j];
      sum += e * e;
      ++n;
    }
  }
  return std::sqrt(sum / static_cast<double>(n));
}

TEST(FitTriggerState, TheRecordsStateAtTheTriggerPredictsAMagnetRotorsDrop) {
  const ModelParams truth = MagnetRig();
  MeasureOptions options;
  options.rate_Hz = 20000.0;  // an acquisition at four times the controller rate
  options.current_noise_A = 0.005;
  const SyntheticMeasurement made = MakeMeasuredRecord(truth, options);
  // The declared model is the truth: only the start differs.
  MeasurementParams from_model = made.measurement;
  MeasurementParams from_record = made.measurement;
  from_record.trigger_state_from_record = true;
  const SimulatedRecord own = SimulateOnRecord(truth, from_model, made.record, {});
  const SimulatedRecord seated = SimulateOnRecord(truth, from_record, made.record, {});
  ASSERT_TRUE(own.closed_loop && seated.closed_loop);
  ASSERT_EQ(seated.failure, "");
  const double own_error = EarlyDropError(made.record, made.measurement, own);
  const double seated_error = EarlyDropError(made.record, made.measurement, seated);
  // How far the rotor went in those 8 ms, for scale.
  double travel = 0.0;
  for (std::size_t c = 0; c < made.measurement.channels.size(); ++c) {
    if (made.measurement.channels[c].quantity != MeasuredQuantity::kDisplacement) continue;
    for (std::size_t j = 0; j < made.record.time_s.size(); ++j) {
      const double t = made.record.time_s[j];
      if (t >= kTrigger_s && t <= kTrigger_s + 8e-3) {
        travel = std::max(travel, std::abs(made.record.values[c][j]));
      }
    }
  }
  std::printf(
      "early drop error: the model's own start %.3g m, the record's %.3g m (travel %.3g m)\n",
      own_error, seated_error, travel);
  EXPECT_GT(travel, 20e-6);
  EXPECT_LT(seated_error, 0.6 * own_error);
  EXPECT_LT(seated_error, 0.01 * travel);
  EXPECT_THAT(seated.lead_fit, ::testing::HasSubstr("displacement channels over the 6 ms"));
  EXPECT_EQ(own.lead_fit, "");

  // A record that starts 0.1 ms before the trigger has two samples per channel in the lead
  // window, too few to fit a state: the run keeps the model's own state, says so, and drives
  // the rotor by the record's currents only where the record has them.
  MeasuredRecord late = made.record;
  std::size_t first = 0;
  while (late.time_s[first] < kTrigger_s - 0.1e-3) ++first;
  const auto from_first = [first](auto& v) { v.erase(v.begin(), v.begin() + first); };
  from_first(late.time_s);
  for (std::vector<double>& column : late.values) from_first(column);
  const SimulatedRecord unfitted = SimulateOnRecord(truth, from_record, late, {});
  EXPECT_THAT(unfitted.lead_fit, ::testing::StartsWith("not fitted: "));
  EXPECT_THAT(unfitted.lead_fit, ::testing::HasSubstr("fewer than twice"));
  EXPECT_TRUE(unfitted.lead_uncertainty.empty());
  const SimulatedRecord late_own = SimulateOnRecord(truth, from_model, late, {});
  const double unfitted_error = EarlyDropError(late, made.measurement, unfitted);
  const double late_own_error = EarlyDropError(late, made.measurement, late_own);
  std::printf("late record: the model's own start %.3g m, unfitted lead %.3g m\n", late_own_error,
              unfitted_error);
  // Driven for its last 0.1 ms by the record's currents (which carry the record's jitter: 0.78 A
  // where the noise-free model holds 0.83 A), the model's own state still predicts the start
  // within a few percent of the travel: measured 2.3 % (the model's own alone 1.0 %). With the
  // amplifier stepped at the controller period, both were 1.6 %.
  EXPECT_LT(unfitted_error, 0.05 * travel);
}

// Refused without displacement channels (there is no state to read); taken with
// power_loss = "from_record", whose open-loop run then starts a lead window before the trigger.
TEST(FitTriggerState, NeedsDisplacements) {
  const std::string base = "base = \"" + testing::ConfigPath(kRig) + "\"\n";
  const std::string table =
      "[measurement]\nsample_rate_Hz = 20000.0\ntrigger_time_s = 0.2\n"
      "trigger_state = \"record\"\n";
  for (const char* state : {"record", "record_start"}) {
    try {
      LoadConfigFromString(base +
                               "[measurement]\nsample_rate_Hz = 20000.0\ntrigger_time_s = 0.2\n"
                               "trigger_state = \"" +
                               state +
                               "\"\n[[measurement.channel]]\ncolumn = \"w\"\nquantity = "
                               "\"rotor_speed\"\n",
                           "m.toml");
      ADD_FAILURE() << state << " loaded";
    } catch (const ConfigError& e) {
      EXPECT_THAT(e.what(), ::testing::HasSubstr("m.toml:5: key 'measurement.trigger_state': "
                                                 "expected \"model\", or a channel with quantity = "
                                                 "\"displacement\""));
    }
  }
  const LoadedConfig open = LoadConfigFromString(
      base + table + "power_loss = \"from_record\"\n" +
          "[[measurement.channel]]\ncolumn = \"i\"\nquantity = \"current\"\namb = \"nde\"\n"
          "axis = \"x\"\n[[measurement.channel]]\ncolumn = \"x\"\nquantity = "
          "\"displacement\"\nsensor = \"nde\"\naxis = \"x\"\n",
      "m.toml", {"amb.nde.flux_decay.enabled=true"});
  ASSERT_TRUE(open.measurement.has_value());
  EXPECT_TRUE(open.measurement->trigger_state_from_record);
  EXPECT_EQ(open.measurement->power_loss, PowerLossSource::kFromRecord);
}

// A current that falls by a declared law after the trigger, sampled at 20 kHz with 5 mA of
// noise. Two samples (the old reading) leave the held current about the noise off; the law's
// least-squares fit over its 2 ms window about the noise over the root of the samples.
TEST(FitTriggerState, TheLawsFitPinsTheHeldCurrent) {
  AmbParams amb;
  amb.law = AmbForceLaw::kElectromagnet;
  amb.bias_source = AmbBiasSource::kPermanentMagnet;
  amb.electromagnet.bias_current_A = 3.0;
  amb.current_limit_A = 3.0;
  amb.flux_decay.enabled = true;
  std::mt19937_64 engine(7);
  const auto normal = [&] {
    // Box-Muller on the engine's own bits: the same numbers with any standard library.
    const double u1 = (static_cast<double>(engine() >> 11) + 0.5) * 0x1p-53;
    const double u2 = static_cast<double>(engine() >> 11) * 0x1p-53;
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  };
  for (const PowerLossCurrentLaw law :
       {PowerLossCurrentLaw::kExponential, PowerLossCurrentLaw::kSlewLimitedRamp}) {
    amb.flux_decay.current_law = law;
    amb.flux_decay.time_constant_s = 5e-3;
    amb.flux_decay.slew_rate_A_per_s = 40.0;
    double by_law = 0.0, two_samples = 0.0;
    const int trials = 200;
    for (int trial = 0; trial < trials; ++trial) {
      const double held = 0.5 + 0.002 * trial;
      const double trigger = 0.01 + 1.3e-5 * (trial % 3);  // between samples, or on one
      MeasuredRecord r;
      r.columns = {"i"};
      r.values.resize(1);
      for (int j = 0; j < 600; ++j) {
        const double t = j * 5e-5;
        const double clean =
            t < trigger ? held : ReportedCoilCurrent(PowerLossDrive(amb, held, t - trigger));
        r.time_s.push_back(t);
        r.values[0].push_back(clean + 0.005 * normal());
      }
      by_law += std::pow(HeldCurrentByLaw(r, 0, trigger, amb) - held, 2);
      two_samples += std::pow(HeldCurrentAtTrigger(r, 0, trigger, true) - held, 2);
    }
    by_law = std::sqrt(by_law / trials);
    two_samples = std::sqrt(two_samples / trials);
    std::printf("held current error (law %d): fit %.3g A, two samples %.3g A\n",
                static_cast<int>(law), by_law, two_samples);
    EXPECT_LT(by_law, 0.005 / std::sqrt(10.0));  // within about 40 samples' worth
    EXPECT_LT(by_law, 0.3 * two_samples);
  }
}

}  // namespace
}  // namespace ambdrop::fit_trigger_state_test
