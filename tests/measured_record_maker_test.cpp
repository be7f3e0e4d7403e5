// Measured-like records from a truth rig (tools/fit/measured_record_maker): each channel is the
// truth run's quantity as a logger on the rig would see it, the added noise is seeded and has
// the spread asked for, the same inputs give the same record bit for bit, and the [measurement]
// table written for it reads back through the config loader.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "controller_if/loop/offline_run.hpp"
#include "controller_if/loop/run_record.hpp"
#include "io/config/config_loader.hpp"
#include "rt_core/model.hpp"
#include "test_configs.hpp"
#include "tools/fit/measured_record_maker.hpp"

namespace ambdrop::measured_record_maker_test {
namespace {

constexpr const char* kRig = "jarroux2019_industrial_pid.toml";
constexpr double kTriggerS = 0.2;  // the rig's trigger.time_s

/// The PID rig for 0.3 s. With `ideal`, sensors without noise or quantisation: a reading is then
/// the rotor's displacement itself.
ModelParams Rig(bool ideal, std::vector<std::string> more = {}) {
  std::vector<std::string> overrides = {"simulation.duration_s=0.3"};
  if (ideal) {
    for (const char* sensor : {"nde", "de"}) {
      overrides.push_back(std::string("sensor.") + sensor + ".noise.enabled=false");
      overrides.push_back(std::string("sensor.") + sensor + ".quantisation_m=0.0");
    }
  }
  overrides.insert(overrides.end(), more.begin(), more.end());
  return testing::LoadTestConfig(kRig, overrides);
}

const std::vector<double>& Column(const SyntheticMeasurement& m, const std::string& name) {
  const int c = m.record.Column(name);
  if (c < 0) throw std::runtime_error("no column " + name);
  return m.record.values[static_cast<std::size_t>(c)];
}

/// The ideal rig's record and the truth run's own observations at the same instants.
struct IdealRun {
  ModelParams params;
  SyntheticMeasurement made;
  std::vector<Observation> truth;
};

const IdealRun& Ideal() {
  static const IdealRun run = [] {
    IdealRun r;
    r.params = Rig(true);
    r.made = MakeMeasuredRecord(r.params, {});
    // The rig's output interval is already the controller period (20 kHz).
    const Model model = BuildModel(r.params);
    const OfflineRunResult result =
        RunOffline(model, [&r](const Observation& o) { r.truth.push_back(o); });
    if (result.status != StepStatus::kOk) throw std::runtime_error(result.failure_message);
    return r;
  }();
  return run;
}

/// Records with noise on every added channel, by seed (and from_s).
SyntheticMeasurement Noisy(std::uint64_t seed, double from_s = 0.0, double current_noise_A = 0.05) {
  MeasureOptions o;
  o.current_noise_A = current_noise_A;
  o.force_noise_N = 20.0;
  o.speed_noise_rad_s = 0.5;
  o.seed = seed;
  o.from_s = from_s;
  return MakeMeasuredRecord(Rig(false), o);
}

bool BitIdentical(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

TEST(MeasuredRecordMaker, ColumnsSampleTimesAndTable) {
  const IdealRun& run = Ideal();
  const MeasuredRecord& r = run.made.record;
  std::vector<std::string> expected;
  for (const SensorParams& s : run.params.sensors) {
    expected.push_back("x_" + s.name);
    expected.push_back("y_" + s.name);
  }
  for (const AmbParams& a : run.params.ambs) {
    expected.push_back("i_" + a.name + "_x");
    expected.push_back("i_" + a.name + "_y");
  }
  for (const TdbParams& t : run.params.tdbs) expected.push_back("f_" + t.name);
  for (const TdbParams& t : run.params.tdbs) expected.push_back("w_" + t.name);
  expected.push_back("w_rotor");
  EXPECT_EQ(r.columns, expected);
  ASSERT_EQ(r.values.size(), expected.size());
  // 20 kHz over 0.3 s, both ends included; t is the run's step time.
  ASSERT_EQ(r.time_s.size(), 6001u);
  for (const std::vector<double>& v : r.values) EXPECT_EQ(v.size(), r.time_s.size());
  for (std::size_t n = 0; n < r.time_s.size(); n += 1000) {
    EXPECT_EQ(r.time_s[n], static_cast<double>(n * 10) * run.params.simulation.step_s);
  }
  EXPECT_EQ(run.made.measurement.sample_rate_Hz, 20000.0);
  ASSERT_TRUE(run.made.measurement.trigger_time_s.has_value());
  EXPECT_EQ(*run.made.measurement.trigger_time_s, kTriggerS);
  ASSERT_EQ(run.made.measurement.channels.size(), expected.size());
  for (std::size_t c = 0; c < expected.size(); ++c) {
    EXPECT_EQ(run.made.measurement.channels[c].column, expected[c]);
  }
}

TEST(MeasuredRecordMaker, BeforeTheTriggerReadingsAreTheTruthRunsSensorPositions) {
  const IdealRun& run = Ideal();
  const MeasuredRecord& r = run.made.record;
  ASSERT_EQ(run.truth.size(), r.time_s.size());
  int compared = 0;
  for (std::size_t i = 0; i < run.params.sensors.size(); ++i) {
    const std::string& name = run.params.sensors[i].name;
    const std::vector<double>& x = Column(run.made, "x_" + name);
    const std::vector<double>& y = Column(run.made, "y_" + name);
    for (std::size_t n = 0; r.time_s[n] < kTriggerS; ++n) {
      ASSERT_EQ(run.truth[n].time_s, r.time_s[n]);
      // A unit-gain, unfiltered sensor: the low-pass update y + 1 (x - y) may round by an ulp.
      ASSERT_NEAR(x[n], run.truth[n].sensor_xy_m[i][0], 1e-18) << name << " x at row " << n;
      ASSERT_NEAR(y[n], run.truth[n].sensor_xy_m[i][1], 1e-18) << name << " y at row " << n;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 2 * 4000);
}

/// Keeps the sensor samples the internal controller read and the currents it commanded.
class ControllerLog final : public RunRecorder {
 public:
  std::vector<RecordedSensors> samples;
  std::vector<RecordedInput> inputs;
  void OnStart(const RecordedStart&) noexcept override {}
  void OnInput(const RecordedInput& in) noexcept override { inputs.push_back(in); }
  void OnPower(const RecordedPower&) noexcept override {}
  void OnSensors(const RecordedSensors& s) noexcept override { samples.push_back(s); }
  void OnState(const State&, const Observation&) noexcept override {}
};

TEST(MeasuredRecordMaker, AtTheControllerRateChannelsAreWhatTheControllerReadAndCommanded) {
  // The rig's own sensors, noise and quantisation on: the record's emulator is a second
  // instance with the same parameters and seeds, sampling the same states.
  const ModelParams rig = Rig(false, {"simulation.duration_s=0.05"});
  const SyntheticMeasurement made = MakeMeasuredRecord(rig, {});
  const Model model = BuildModel(rig);
  ControllerLog log;
  ASSERT_EQ(RunOffline(model, {}, {}, &log).status, StepStatus::kOk);
  ASSERT_EQ(log.samples.size() + 1, made.record.time_s.size());  // the record ends with the run
  for (std::size_t i = 0; i < rig.sensors.size(); ++i) {
    const std::vector<double>& x = Column(made, "x_" + rig.sensors[i].name);
    const std::vector<double>& y = Column(made, "y_" + rig.sensors[i].name);
    for (std::size_t n = 0; n < log.samples.size(); ++n) {
      ASSERT_EQ(log.samples[n].time_s, made.record.time_s[n]);
      ASSERT_EQ(x[n], log.samples[n].readings.reading_m[i][0]) << "row " << n;
      ASSERT_EQ(y[n], log.samples[n].readings.reading_m[i][1]) << "row " << n;
    }
  }
  // A command holds from its step until the next one (inputs are logged only when they change).
  const double dt = rig.simulation.step_s;
  for (std::size_t a = 0; a < rig.ambs.size(); ++a) {
    for (int axis = 0; axis < 2; ++axis) {
      const std::vector<double>& i =
          Column(made, "i_" + rig.ambs[a].name + (axis == 0 ? "_x" : "_y"));
      std::size_t in = 0;
      for (std::size_t n = 0; n < i.size(); ++n) {
        const auto step = std::llround(made.record.time_s[n] / dt);
        while (in + 1 < log.inputs.size() && log.inputs[in + 1].step <= step) ++in;
        ASSERT_EQ(i[n], log.inputs[in].current_A[a][axis]) << rig.ambs[a].name << " row " << n;
      }
    }
  }
}

TEST(MeasuredRecordMaker, RotorSpinsAtTheConfiguredSpeedUntilTheTrigger) {
  const IdealRun& run = Ideal();
  const std::vector<double>& w = Column(run.made, "w_rotor");
  const double spin = run.params.simulation.spin_speed_rad_s;
  for (std::size_t n = 0; run.made.record.time_s[n] < kTriggerS; ++n) {
    ASSERT_NEAR(w[n], spin, 1e-9 * spin) << "row " << n;
  }
  // Coasting on the TDBs afterwards, slowed by contact friction.
  EXPECT_LT(w.back(), spin);
}

TEST(MeasuredRecordMaker, DroppedRotorReadsAboutMinusTheClearance) {
  const IdealRun& run = Ideal();
  const MeasuredRecord& r = run.made.record;
  const double clearance = run.params.tdbs.front().clearance_m;
  for (const SensorParams& s : run.params.sensors) {
    const std::vector<double>& y = Column(run.made, "y_" + s.name);
    // Levitated on the magnetic centre just before the trigger.
    double before = 0.0, after = 0.0;
    int count_before = 0, count_after = 0;
    for (std::size_t n = 0; n < r.time_s.size(); ++n) {
      if (r.time_s[n] > 0.15 && r.time_s[n] < kTriggerS) {
        before += y[n];
        ++count_before;
      }
      // The last 50 ms, well after the landing: the rotor rests or rocks at the bottom.
      if (r.time_s[n] >= 0.25) {
        after += y[n];
        ++count_after;
      }
    }
    EXPECT_NEAR(before / count_before, 0.0, 0.1 * clearance) << s.name;
    // Beyond the clearance by the contact law's compliance (about half a clearance under this
    // rotor's weight), never far beyond.
    const double mean = after / count_after;
    EXPECT_LT(mean, -0.9 * clearance) << s.name;
    EXPECT_GT(mean, -1.6 * clearance) << s.name;
  }
}

TEST(MeasuredRecordMaker, TdbForceIsZeroBeforeContactAndExceedsTheWeightShareAtImpact) {
  const IdealRun& run = Ideal();
  const MeasuredRecord& r = run.made.record;
  // The static load the AMBs carry is the rotor's weight; the lever rule shares it between the
  // TDBs.
  const Model model = BuildModel(run.params);
  double weight = 0.0, moment = 0.0;
  for (std::size_t a = 0; a < run.params.ambs.size(); ++a) {
    weight += model.amb_bias_force_N[a][1];
    moment += model.amb_bias_force_N[a][1] * run.params.ambs[a].position_m;
  }
  const double centre_m = moment / weight;
  ASSERT_EQ(run.params.tdbs.size(), 2u);
  const double z0 = run.params.tdbs[0].position_m, z1 = run.params.tdbs[1].position_m;
  const double share[2] = {weight * (z1 - centre_m) / (z1 - z0),
                           weight * (centre_m - z0) / (z1 - z0)};
  for (std::size_t t = 0; t < 2; ++t) {
    const std::string& name = run.params.tdbs[t].name;
    EXPECT_GT(share[t], 0.0) << name;
    const std::vector<double>& f = Column(run.made, "f_" + name);
    std::size_t n = 0;
    while (n < f.size() && f[n] == 0.0) ++n;
    ASSERT_LT(n, f.size()) << name << " never touched";
    EXPECT_GT(r.time_s[n], kTriggerS) << name << " touched before the trigger";
    // The first impact: from first contact until the journal leaves the race (or 5 ms).
    const double contact_s = r.time_s[n];
    double peak = 0.0;
    for (; n < f.size() && f[n] > 0.0 && r.time_s[n] < contact_s + 5e-3; ++n) {
      peak = std::max(peak, f[n]);
    }
    EXPECT_GT(peak, share[t]) << name;
  }
}

TEST(MeasuredRecordMaker, LevitatingCurrentsCarryTheLoad) {
  const IdealRun& run = Ideal();
  const MeasuredRecord& r = run.made.record;
  for (const AmbParams& a : run.params.ambs) {
    const std::vector<double>& iy = Column(run.made, "i_" + a.name + "_y");
    // Levitated: the y coils pull the rotor's weight up, so the mean control current is well
    // above zero.
    double sum = 0.0;
    int count = 0;
    for (std::size_t n = 0; r.time_s[n] < kTriggerS; ++n) {
      if (r.time_s[n] < 0.1) continue;
      sum += iy[n];
      ++count;
    }
    EXPECT_GT(sum / count, 0.5) << a.name;
  }
}

TEST(MeasuredRecordMaker, AfterPowerLossTheCoilCurrentFadesWithTheFlux) {
  // What a coil-current sensor reads: the amplifier is off, so the current it had at the
  // trigger fades as exp(-t/tau) (the force, quadratic in it, as exp(-2t/tau)); without flux
  // decay it is gone at once, whatever the controller still commands.
  for (const double tau : {0.0, 4e-3}) {
    std::vector<std::string> more = {"simulation.duration_s=0.25"};
    for (const char* amb : {"de", "nde"}) {
      more.push_back(fmt::format("amb.{}.flux_decay.enabled={}", amb, tau > 0 ? "true" : "false"));
      if (tau > 0) more.push_back(fmt::format("amb.{}.flux_decay.time_constant_s={}", amb, tau));
    }
    const SyntheticMeasurement made = MakeMeasuredRecord(Rig(true, more), {});
    const MeasuredRecord& r = made.record;
    const std::vector<double>& iy = Column(made, "i_de_y");
    std::size_t at = 0;
    while (r.time_s[at] < kTriggerS - 1e-9) ++at;
    // The command of the last period before the trigger is what flows when power fails.
    const double frozen = iy[at - 1];
    EXPECT_GT(frozen, 0.5) << "levitating current at the trigger";
    for (std::size_t n = at; n < r.time_s.size(); ++n) {
      const double t = r.time_s[n] - r.time_s[at];
      const double expected = tau > 0 ? frozen * std::exp(-t / tau) : 0.0;
      ASSERT_NEAR(iy[n], expected, 1e-12 + 1e-9 * frozen) << "tau " << tau << " at t " << t;
    }
  }
}

TEST(MeasuredRecordMaker, SameSeedSameBitsOtherSeedOtherNoise) {
  const SyntheticMeasurement a = Noisy(7);
  const SyntheticMeasurement b = Noisy(7);
  const SyntheticMeasurement c = Noisy(8);
  ASSERT_EQ(a.record.columns, b.record.columns);
  EXPECT_TRUE(BitIdentical(a.record.time_s, b.record.time_s));
  for (std::size_t k = 0; k < a.record.values.size(); ++k) {
    EXPECT_TRUE(BitIdentical(a.record.values[k], b.record.values[k])) << a.record.columns[k];
    // The seed is the added noise's; the sensors keep the config's seeds.
    const bool displacement = a.measurement.channels[k].quantity == MeasuredQuantity::kDisplacement;
    EXPECT_EQ(BitIdentical(a.record.values[k], c.record.values[k]), displacement)
        << a.record.columns[k];
  }
}

TEST(MeasuredRecordMaker, AddedCurrentNoiseHasTheAskedSpread) {
  const double sigma = 0.05;
  const SyntheticMeasurement noisy = Noisy(3, 0.0, sigma);
  const SyntheticMeasurement clean = MakeMeasuredRecord(Rig(false), {});
  const MeasuredRecord& r = noisy.record;
  for (const char* column : {"i_de_x", "i_de_y", "i_nde_x", "i_nde_y"}) {
    const std::vector<double>& with = Column(noisy, column);
    const std::vector<double>& without = Column(clean, column);
    // A quiet window: levitated, settled, before the trigger. The physics is the same run, so
    // the difference is the added noise alone.
    double sum = 0.0, sum2 = 0.0;
    int count = 0;
    for (std::size_t n = 0; r.time_s[n] < kTriggerS; ++n) {
      if (r.time_s[n] < 0.1) continue;
      const double d = with[n] - without[n];
      sum += d;
      sum2 += d * d;
      ++count;
    }
    const double mean = sum / count;
    const double std_dev = std::sqrt(sum2 / count - mean * mean);
    EXPECT_NEAR(std_dev, sigma, 0.1 * sigma) << column;
    EXPECT_NEAR(mean, 0.0, 5.0 * sigma / std::sqrt(count)) << column;
  }
}

TEST(MeasuredRecordMaker, FromSecondsDropsEarlierRowsOfTheSameRecord) {
  const SyntheticMeasurement whole = Noisy(5);
  const SyntheticMeasurement tail = Noisy(5, 0.25);
  const MeasuredRecord& w = whole.record;
  const MeasuredRecord& t = tail.record;
  ASSERT_EQ(t.time_s.size(), 1001u);
  EXPECT_NEAR(t.time_s.front(), 0.25, 1e-12);  // run time, not restarted at 0
  const std::size_t skip = w.time_s.size() - t.time_s.size();
  for (std::size_t k = 0; k < w.values.size(); ++k) {
    const std::vector<double> expected(w.values[k].begin() + static_cast<std::ptrdiff_t>(skip),
                                       w.values[k].end());
    EXPECT_TRUE(BitIdentical(expected, t.values[k])) << w.columns[k];
  }
}

TEST(MeasuredRecordMaker, ChannelGroupsAndSampleRate) {
  MeasureOptions o;
  o.channels = {false, false, false, false, true};
  o.rate_Hz = 10000.0;
  o.speed_noise_rad_s = 0.5;
  const SyntheticMeasurement speed_only = MakeMeasuredRecord(Rig(true), o);
  EXPECT_EQ(speed_only.record.columns, std::vector<std::string>{"w_rotor"});
  EXPECT_EQ(speed_only.record.time_s.size(), 3001u);
  EXPECT_EQ(speed_only.record.time_s[1], 1e-4);
  EXPECT_EQ(speed_only.measurement.sample_rate_Hz, 10000.0);

  o.rate_Hz = 30000.0;  // 6.67 steps of 5 us
  EXPECT_THROW(MakeMeasuredRecord(Rig(true), o), std::invalid_argument);
  o.rate_Hz = 0.0;
  o.from_s = 0.5;  // after the end
  EXPECT_THROW(MakeMeasuredRecord(Rig(true), o), std::invalid_argument);
}

TEST(MeasuredRecordMaker, DivergingTruthRunThrows) {
  // The journal leaves the stated bound as soon as it lands.
  const ModelParams rig = Rig(true, {"simulation.max_excursion_over_clearance=0.5"});
  try {
    MakeMeasuredRecord(rig, {});
    FAIL() << "no error";
  } catch (const TruthRunDiverged& e) {
    EXPECT_NE(std::string(e.what()).find("diverged"), std::string::npos) << e.what();
  }
}

TEST(MeasuredRecordMaker, TableReadsBackThroughTheLoader) {
  const IdealRun& run = Ideal();
  const std::string text = "base = \"" + testing::ConfigPath(kRig) + "\"\n" +
                           MeasurementTableToml(run.params, run.made.measurement);
  const LoadedConfig loaded = LoadConfigFromString(text, "measurement_table_test.toml");
  ASSERT_TRUE(loaded.measurement.has_value()) << text;
  const MeasurementParams& m = *loaded.measurement;
  EXPECT_EQ(m.sample_rate_Hz, 20000.0);
  ASSERT_TRUE(m.trigger_time_s.has_value());
  EXPECT_EQ(*m.trigger_time_s, kTriggerS);
  ASSERT_EQ(m.channels.size(), run.made.measurement.channels.size());
  for (std::size_t c = 0; c < m.channels.size(); ++c) {
    const MeasurementChannel& want = run.made.measurement.channels[c];
    EXPECT_EQ(m.channels[c].column, want.column);
    EXPECT_EQ(m.channels[c].quantity, want.quantity) << want.column;
    EXPECT_EQ(m.channels[c].index, want.index) << want.column;
    EXPECT_EQ(m.channels[c].axis, want.axis) << want.column;
  }

  // Without a scheduled trigger the fit is told to find it.
  const ModelParams untriggered =
      Rig(true, {"trigger.enabled=false", "simulation.duration_s=0.01"});
  const SyntheticMeasurement levitated = MakeMeasuredRecord(untriggered, {});
  EXPECT_TRUE(levitated.measurement.detect_trigger);
  EXPECT_FALSE(levitated.measurement.trigger_time_s.has_value());
  EXPECT_NE(MeasurementTableToml(untriggered, levitated.measurement).find("trigger = \"detect\""),
            std::string::npos);
}

}  // namespace
}  // namespace ambdrop::measured_record_maker_test
