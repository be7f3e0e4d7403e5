// `measurement.power_loss = "from_record"` (issue 24 item 2): the record's coil currents drive
// the AMBs through and after the trigger, so a power-loss law the declared model cannot express
// (or gets wrong) no longer stands between the record and the TDB physics.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "io/config/config_loader.hpp"
#include "rt_core/amb_force.hpp"
#include "rt_core/power_loss_drive.hpp"
#include "test_configs.hpp"
#include "tools/fit/fit_record.hpp"
#include "tools/fit/measured_record_maker.hpp"
#include "tools/fit/residuals.hpp"
#include "tools/fit/simulate_on_record.hpp"

namespace ambdrop::fit_from_record_test {
namespace {

constexpr const char* kRig = "jarroux2019_industrial_pid.toml";

AmbParams Electromagnet(AmbBiasSource bias, PowerLossCurrentLaw law) {
  AmbParams a;
  a.law = AmbForceLaw::kElectromagnet;
  a.bias_source = bias;
  a.current_limit_A = 12.0;
  a.electromagnet.constant_N_m2_per_A2 = 2.0e-4;
  a.electromagnet.nominal_gap_m = 6e-4;
  a.electromagnet.bias_current_A = 6.0;
  a.flux_decay.enabled = true;
  a.flux_decay.current_law = law;
  a.flux_decay.time_constant_s = 4e-3;
  a.flux_decay.hold_time_s = 1e-3;
  return a;
}

// The axis force a drive makes at displacement u (the step's law, rt_core/plane_derivative.hpp).
double Force(const AmbParams& a, const UnpoweredDrive& d, double u) {
  const ElectromagnetParams& e = a.electromagnet;
  return d.force_scale * ElectromagnetForce(ElectromagnetConstant(e), e.nominal_gap_m,
                                            e.bias_current_A * d.bias_scale, d.current_A, u);
}

// A record that follows the declared uniform law gives exactly the law's own force: the bias
// falls by the law, the recorded control current by the same fraction, F(s I0, s i) = s^2 F.
TEST(RecordedCurrentDrive, ARecordFollowingTheDeclaredLawGivesTheLawsForce) {
  for (const PowerLossCurrentLaw law :
       {PowerLossCurrentLaw::kExponential, PowerLossCurrentLaw::kHoldThenExponential}) {
    const AmbParams a = Electromagnet(AmbBiasSource::kElectromagnet, law);
    const double held_A = 2.5;
    for (const double t : {0.0, 5e-4, 2e-3, 7e-3}) {
      const UnpoweredDrive law_drive = PowerLossDrive(a, held_A, t);
      const double recorded_A = ReportedCoilCurrent(law_drive);
      const UnpoweredDrive from_record = RecordedCurrentDrive(a, held_A, recorded_A, t);
      for (const double u : {-2e-4, 0.0, 3e-4}) {
        const double expected = Force(a, law_drive, u);
        EXPECT_NEAR(Force(a, from_record, u), expected, 1e-12 * std::abs(expected) + 1e-12)
            << "law " << static_cast<int>(law) << " t " << t << " u " << u;
      }
    }
  }
}

// A magnet's bias stays: the force after power loss is the powered law at the recorded current,
// whatever the declared law says the current should be by then.
TEST(RecordedCurrentDrive, AMagnetBiasFollowsTheRecordedCurrentAlone) {
  const AmbParams a =
      Electromagnet(AmbBiasSource::kPermanentMagnet, PowerLossCurrentLaw::kSlewLimitedRamp);
  for (const double recorded_A : {-1.5, 0.0, 0.7, 3.0}) {
    const UnpoweredDrive d = RecordedCurrentDrive(a, 2.0, recorded_A, 3e-3);
    const double powered = ElectromagnetForce(a.electromagnet, recorded_A, 1e-4);
    EXPECT_DOUBLE_EQ(Force(a, d, 1e-4), powered) << recorded_A;
  }
}

// The truth's amplifiers hold the coil currents for 5 ms before they fade; the declared rig says
// they fade at once, as exp(-t/tau). With the declared law the prediction departs from
// the record after the trigger; driven by the record's own currents it follows the record at
// least 5x more closely (what is left comes from the open-loop start: the record's noise leaves
// the start state uncertain, and the magnet's negative stiffness amplifies that), the currents
// are inputs, not residuals, and the fit says that the power-loss law cannot be decided.
TEST(FitFromRecord, RecordedCurrentsStandInForALawTheModelGetsWrong) {
  const std::vector<std::string> timing = {"simulation.duration_s=0.16", "trigger.time_s=0.1"};
  std::vector<std::string> magnet = timing;
  for (const char* amb : {"de", "nde"}) {
    const std::string t = std::string("amb.") + amb + ".";
    magnet.push_back(t + "bias_source=permanent_magnet");
    magnet.push_back(t + "flux_decay.enabled=true");
  }
  std::vector<std::string> truth = magnet;
  truth.push_back("simulation.step_s=2.5e-6");
  const std::vector<std::string>& declared = magnet;
  for (const char* amb : {"de", "nde"}) {
    const std::string t = std::string("amb.") + amb + ".flux_decay.";
    truth.push_back(t + "current_law=hold_then_exponential");
    truth.push_back(t + "hold_time_s=5e-3");
  }
  MeasureOptions noise;
  noise.current_noise_A = 0.005;
  noise.force_noise_N = 2.0;
  noise.speed_noise_rad_s = 0.01;
  noise.seed = 11;
  const SyntheticMeasurement made = MakeMeasuredRecord(testing::LoadTestConfig(kRig, truth), noise);
  const ConfigVariants variants = testing::LoadTestVariants(kRig, declared);
  const ModelParams& params = variants.declared().params;

  MeasurementParams from_record = made.measurement;
  from_record.power_loss = PowerLossSource::kFromRecord;
  const RecordRunOptions run;
  // The displacements after the trigger: where the law shows.
  const auto displacement_rms = [&](const MeasurementParams& m) {
    const SimulatedRecord sim = SimulateOnRecord(params, m, made.record, run);
    EXPECT_EQ(sim.failure, "");
    EXPECT_EQ(sim.closed_loop, m.power_loss == PowerLossSource::kDeclared);
    double sum = 0.0;
    std::size_t n = 0;
    for (std::size_t c = 0; c < m.channels.size(); ++c) {
      const std::vector<double> e = ResidualSeries(m, made.record, sim, c);
      const bool input = m.Drives(m.channels[c]);
      for (std::size_t j = 0; j < e.size(); ++j) {
        // from_record's coil currents are inputs: never a residual.
        if (input) {
          EXPECT_TRUE(std::isnan(e[j]));
        }
        if (m.channels[c].quantity != MeasuredQuantity::kDisplacement || std::isnan(e[j]) ||
            made.record.time_s[j] < sim.trigger_time_s) {
          continue;
        }
        sum += e[j] * e[j];
        ++n;
      }
    }
    return std::sqrt(sum / static_cast<double>(n));
  };
  const double declared_rms = displacement_rms(made.measurement);
  const double recorded_rms = displacement_rms(from_record);
  std::printf("displacement rms after the trigger: declared law %.3g m, from_record %.3g m\n",
              declared_rms, recorded_rms);
  EXPECT_LT(recorded_rms, 0.2 * declared_rms);

  FitRecordOptions options;
  options.rules.threads = 2;
  const std::unique_ptr<FitResult> fit = FitRecord(variants, from_record, made.record, options);
  const Selection& s = fit->selection;
  std::printf("verdict %s: %s\n", s.verdict.c_str(), s.reason.c_str());
  int flux_decay_candidates = 0;
  for (const CandidateScore& c : s.candidates) {
    if (c.family != "amb_flux_decay") continue;
    ++flux_decay_candidates;
    EXPECT_FALSE(c.decidable) << c.name << ": a magnet-biased AMB driven by its recorded current "
                              << "does not depend on its power-loss law";
  }
  EXPECT_GT(flux_decay_candidates, 0);
  for (const ChannelResidual& c : fit->residual_before.channels) {
    const bool input = c.column.rfind("i_", 0) == 0;
    EXPECT_EQ(input, c.samples == 0) << c.column << ": the coil currents are inputs";
  }
}

}  // namespace
}  // namespace ambdrop::fit_from_record_test
