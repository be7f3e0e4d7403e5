// An ambdrop run record read as a measured record for `ambdrop fit`
// (tools/fit/run_record_measurement.hpp): the rows are the sensor samples the run sent, bit for
// bit; the currents are the inputs in force (after the power failure the held current fading
// with the flux); the TDB forces and speeds are the run's own; the trigger is the recorded power
// failure; and the same rig through `ambdrop measure` gives the same record.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "controller_if/loop/hil_session.hpp"
#include "controller_if/loop/offline_run.hpp"
#include "controller_if/loop/step_driver.hpp"
#include "rt_core/amb_force.hpp"
#include "rt_core/model.hpp"
#include "scratch_directory.hpp"
#include "test_configs.hpp"
#include "tools/fit/measured_record_maker.hpp"
#include "tools/fit/run_record_measurement.hpp"
#include "tools/record/run_record_reader.hpp"
#include "tools/record/run_record_writer.hpp"

namespace ambdrop::run_record_measurement_test {
namespace {

namespace fs = std::filesystem;

bool SameBits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

/// Passes every event to the record's writer and keeps what the run sent.
class Tee final : public RunRecorder {
 public:
  explicit Tee(RunRecorder* next) : next_(next) {}
  void OnStart(const RecordedStart& s) noexcept override { next_->OnStart(s); }
  void OnInput(const RecordedInput& in) noexcept override {
    inputs.push_back(in);
    next_->OnInput(in);
  }
  void OnPower(const RecordedPower& p) noexcept override {
    power.push_back(p);
    next_->OnPower(p);
  }
  void OnSensors(const RecordedSensors& s) noexcept override {
    sensors.push_back(s);
    next_->OnSensors(s);
  }
  void OnState(const State& state, const Observation& obs) noexcept override {
    state_steps.push_back(state.step_index);
    observations.push_back(obs);
    next_->OnState(state, obs);
  }
  std::vector<RecordedInput> inputs;
  std::vector<RecordedPower> power;
  std::vector<RecordedSensors> sensors;
  std::vector<std::int64_t> state_steps;
  std::vector<Observation> observations;

 private:
  RunRecorder* next_;
};

/// A short `ambdrop sim --record` of the PID rig: levitated, then the power fails at 0.05 s and
/// the rotor drops onto its TDBs. The DE AMB's flux decays (τ = 2 ms); the NDE's goes at once.
struct RecordedDrop {
  LoadedConfig config;
  std::unique_ptr<Model> model;
  std::unique_ptr<Tee> live;
  RunRecordFile file;
};

RecordedDrop RecordDrop(const fs::path& path) {
  RecordedDrop d;
  d.config = LoadConfig(
      testing::ConfigPath("jarroux2019_industrial_pid.toml"),
      {"simulation.duration_s=0.1", "trigger.time_s=0.05", "amb.de.flux_decay.enabled=true"});
  d.model = std::make_unique<Model>(BuildModel(d.config.params));
  const Model& model = *d.model;
  RecordHeaderInfo h;
  h.source = "sim";
  h.controller = "internal";
  h.config_toml = d.config.effective_toml;
  h.sensor_every_steps = ControllerSubsteps(model);
  h.output_every_steps = OutputEverySteps(model);
  h.total_steps = model.total_steps;
  RunRecordWriter writer(path, model, h);
  d.live = std::make_unique<Tee>(&writer);
  const OfflineRunResult result = RunOffline(model, {}, {}, d.live.get());
  EXPECT_EQ(result.status, StepStatus::kOk);
  writer.Finish("ok", result.steps);
  d.file = ReadRunRecord(path);
  return d;
}

int Column(const MeasuredRecord& r, const std::string& name) {
  const int c = r.Column(name);
  EXPECT_GE(c, 0) << "no column " << name;
  return c;
}

TEST(RunRecordMeasurement, ReadsTheRecordedDropAsMeasured) {
  const testing::ScratchDirectory scratch("ambdrop_rrm");
  const RecordedDrop d = RecordDrop(scratch.File("drop.lcm"));
  ASSERT_TRUE(d.file.warnings.empty()) << d.file.warnings.front();
  const ModelParams& p = d.model->params;
  const double dt = p.simulation.step_s;
  const RecordAsMeasurement m = MeasurementFromRunRecord(d.file, p);
  const MeasuredRecord& r = m.record;

  // The columns, named as `ambdrop measure` names them, one channel each, in column order.
  std::vector<std::string> expected;
  for (const SensorParams& sensor : p.sensors) {
    expected.push_back("x_" + sensor.name);
    expected.push_back("y_" + sensor.name);
  }
  for (const AmbParams& amb : p.ambs) {
    expected.push_back("i_" + amb.name + "_x");
    expected.push_back("i_" + amb.name + "_y");
  }
  for (const TdbParams& tdb : p.tdbs) expected.push_back("f_" + tdb.name);
  for (const TdbParams& tdb : p.tdbs) expected.push_back("w_" + tdb.name);
  expected.push_back("w_rotor");
  ASSERT_EQ(p.sensors.size(), 2U);
  ASSERT_EQ(p.ambs.size(), 2U);
  ASSERT_EQ(p.tdbs.size(), 2U);
  ASSERT_EQ(r.columns, expected);
  ASSERT_EQ(m.measurement.channels.size(), r.columns.size());
  for (std::size_t c = 0; c < r.columns.size(); ++c) {
    EXPECT_EQ(m.measurement.channels[c].column, r.columns[c]);
  }
  // One row per sensor sample sent, at the controller's rate; the trigger is the config's.
  ASSERT_EQ(r.time_s.size(), d.live->sensors.size());
  EXPECT_NEAR(m.measurement.sample_rate_Hz, p.controller.rate_Hz, 1e-9 * p.controller.rate_Hz);
  ASSERT_TRUE(m.measurement.trigger_time_s.has_value());
  EXPECT_FALSE(m.measurement.detect_trigger);
  EXPECT_DOUBLE_EQ(*m.measurement.trigger_time_s, p.trigger.time_s);
  const double trigger = *m.measurement.trigger_time_s;
  ASSERT_EQ(d.live->power.size(), 1U);
  const std::int64_t trigger_step = d.live->power[0].step;

  const int w_rotor = Column(r, "w_rotor");
  std::size_t rows_before = 0;
  for (std::size_t row = 0; row < r.time_s.size(); ++row) {
    const RecordedSensors& sent = d.live->sensors[row];
    ASSERT_TRUE(SameBits(r.time_s[row], sent.time_s)) << row;
    // The displacements are the readings sent, bit for bit (before the trigger and after).
    for (std::size_t s = 0; s < p.sensors.size(); ++s) {
      for (int axis = 0; axis < 2; ++axis) {
        const int c = Column(r, std::string(axis == 0 ? "x_" : "y_") + p.sensors[s].name);
        ASSERT_TRUE(SameBits(r.values[c][row], sent.readings.reading_m[s][axis]))
            << r.columns[c] << " row " << row;
      }
    }
    // The currents: the input in force, the last one applied from the row's step or earlier.
    const auto in_force =
        std::upper_bound(d.live->inputs.begin(), d.live->inputs.end(), sent.step,
                         [](std::int64_t step, const RecordedInput& in) { return step < in.step; });
    ASSERT_NE(in_force, d.live->inputs.begin());
    const RecordedInput& applied = *(in_force - 1);
    for (std::size_t a = 0; a < p.ambs.size(); ++a) {
      for (int axis = 0; axis < 2; ++axis) {
        const int c = Column(r, "i_" + p.ambs[a].name + (axis == 0 ? "_x" : "_y"));
        if (sent.step < trigger_step) {
          ASSERT_TRUE(SameBits(r.values[c][row], applied.current_A[a][axis]))
              << r.columns[c] << " row " << row;
        }
      }
    }
    if (r.time_s[row] < trigger) {
      ++rows_before;
      // The motor holds the configured spin until the power fails.
      ASSERT_EQ(r.values[w_rotor][row], p.simulation.spin_speed_rad_s) << row;
    }
  }
  EXPECT_EQ(rows_before, static_cast<std::size_t>(trigger_step / ControllerSubsteps(*d.model)));

  // After the failure: each coil's current is the one it held then, fading with its flux (DE:
  // τ = 2 ms, sqrt of the force scale), or gone at once (NDE: no flux decay).
  const auto held =
      std::upper_bound(d.live->inputs.begin(), d.live->inputs.end(), trigger_step - 1,
                       [](std::int64_t step, const RecordedInput& in) { return step < in.step; });
  const RecordedInput& at_failure = *(held - 1);
  for (std::size_t row = rows_before; row < r.time_s.size(); ++row) {
    const double t = static_cast<double>(d.live->sensors[row].step - trigger_step) * dt;
    for (std::size_t a = 0; a < p.ambs.size(); ++a) {
      const double scale = std::sqrt(FluxDecayForceScale(p.ambs[a], t));
      for (int axis = 0; axis < 2; ++axis) {
        const int c = Column(r, "i_" + p.ambs[a].name + (axis == 0 ? "_x" : "_y"));
        ASSERT_EQ(r.values[c][row], at_failure.current_A[a][axis] * scale)
            << r.columns[c] << " row " << row;
      }
    }
  }
  const int i_de_y = Column(r, "i_de_y");
  const int i_nde_y = Column(r, "i_nde_y");
  EXPECT_GT(std::abs(r.values[i_de_y][rows_before + 4]), 0.1);  // 0.2 ms in: still there
  EXPECT_EQ(r.values[i_nde_y][rows_before], 0.0);

  // TDB normal forces: zero until the first contact, which follows the trigger; positive then.
  // Each row's value is the run's own observation at that step.
  for (std::size_t t = 0; t < p.tdbs.size(); ++t) {
    const int f = Column(r, "f_" + p.tdbs[t].name);
    const int w = Column(r, "w_" + p.tdbs[t].name);
    std::size_t first_contact = r.time_s.size();
    for (std::size_t row = 0; row < r.time_s.size(); ++row) {
      EXPECT_GE(r.values[f][row], 0.0);
      if (r.values[f][row] > 0.0 && first_contact == r.time_s.size()) first_contact = row;
      const std::int64_t step = d.live->sensors[row].step;
      const auto obs = std::find(d.live->state_steps.begin(), d.live->state_steps.end(), step);
      ASSERT_NE(obs, d.live->state_steps.end()) << "no state at step " << step;
      const Observation& o = d.live->observations[obs - d.live->state_steps.begin()];
      ASSERT_TRUE(SameBits(r.values[f][row], o.tdb[t].normal_force_N)) << row;
      ASSERT_TRUE(SameBits(r.values[w][row], o.tdb[t].tdb_spin_rad_s)) << row;
    }
    ASSERT_LT(first_contact, r.time_s.size()) << p.tdbs[t].name << " never touched";
    EXPECT_GT(r.time_s[first_contact], trigger);
    EXPECT_GT(r.values[f][first_contact], 0.0);
    const double peak = *std::max_element(r.values[f].begin(), r.values[f].end());
    EXPECT_GT(peak, 100.0) << p.tdbs[t].name;  // a drop, not a graze
  }
}

TEST(RunRecordMeasurement, IsWhatAmbdropMeasureReadsFromTheSameRig) {
  const testing::ScratchDirectory scratch("ambdrop_rrm");
  const RecordedDrop d = RecordDrop(scratch.File("same.lcm"));
  const RecordAsMeasurement from_record = MeasurementFromRunRecord(d.file, d.model->params);
  MeasureOptions options;  // at the controller's rate, no added noise
  const SyntheticMeasurement measured = MakeMeasuredRecord(d.config.params, options);
  ASSERT_EQ(measured.record.columns, from_record.record.columns);
  EXPECT_EQ(measured.measurement.sample_rate_Hz, from_record.measurement.sample_rate_Hz);
  // `measure` also samples the end of the run, where no sensor sample was sent.
  ASSERT_EQ(measured.record.time_s.size(), from_record.record.time_s.size() + 1);
  for (std::size_t c = 0; c < measured.record.columns.size(); ++c) {
    for (std::size_t row = 0; row < from_record.record.time_s.size(); ++row) {
      ASSERT_TRUE(SameBits(measured.record.values[c][row], from_record.record.values[c][row]))
          << measured.record.columns[c] << " row " << row << ": " << measured.record.values[c][row]
          << " vs " << from_record.record.values[c][row];
    }
  }
}

TEST(RunRecordMeasurement, WhatTheRecordLacksIsLeftOutOrRefused) {
  const testing::ScratchDirectory scratch("ambdrop_rrm");
  RecordedDrop d = RecordDrop(scratch.File("lacking.lcm"));
  const ModelParams& p = d.model->params;
  // No state events: no TDB or rotor speed channels. No power failure: the trigger is detected.
  RunRecordFile bare = d.file;
  bare.states.clear();
  bare.run.power.clear();
  const RecordAsMeasurement m = MeasurementFromRunRecord(bare, p);
  EXPECT_EQ(m.record.columns.size(), 2 * (p.sensors.size() + p.ambs.size()));
  EXPECT_GE(m.record.Column("i_de_y"), 0);
  EXPECT_EQ(m.record.Column("w_rotor"), -1);
  EXPECT_EQ(m.record.Column("f_de"), -1);
  EXPECT_TRUE(m.measurement.detect_trigger);
  EXPECT_FALSE(m.measurement.trigger_time_s.has_value());
  // A run without a controller sends no sensor samples: nothing to put rows at.
  RunRecordFile silent = d.file;
  silent.sensors.resize(1);
  EXPECT_THROW(MeasurementFromRunRecord(silent, p), std::invalid_argument);
  // State events of another rig.
  RunRecordFile other = d.file;
  other.states[3].tdb_count = 1;
  EXPECT_THROW(MeasurementFromRunRecord(other, p), std::invalid_argument);
}

}  // namespace
}  // namespace ambdrop::run_record_measurement_test
