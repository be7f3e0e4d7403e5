// A fit's runs resumed from an earlier run's levitated time (tools/fit/levitated_prefix_cache):
// a run that resumes must be bit for bit the run it replaces, on every channel and row, and the
// cache must resume exactly the runs whose levitated time repeats: models that differ only in
// their TDBs (which the levitated journal never touches), in their power-loss laws or in their
// coast-down losses. A sensor's gain acts before the trigger, and a TDB that the levitated
// journal touches acts too: neither resumes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "io/config/config_loader.hpp"
#include "tools/fit/measured_record_maker.hpp"
#include "tools/fit/simulate_on_record.hpp"

namespace ambdrop::fit_levitated_prefix_test {
namespace {

struct Rig {
  std::string path;
  LoadedConfig config;
  SyntheticMeasurement made;
};

// A truth rig's translation (a declared controller), shortened to 12 ms after its trigger, and
// its own record with every channel a load cell adds.
Rig MakeRig(const std::string& file, double trigger_s, double settle_s = 0.0) {
  const std::vector<std::string> timing = {
      "simulation.duration_s=" + std::to_string(trigger_s + 0.012),
      "simulation.settle_s=" + std::to_string(settle_s)};
  const std::string path = std::string(AMBDROP_SOURCE_DIR) + "/tests/truth/" + file;
  Rig rig{path, LoadConfig(path, timing), {}};
  MeasureOptions options;
  options.rate_Hz = 20000.0;
  options.channels.tdb_support_force = true;
  rig.made = MakeMeasuredRecord(rig.config.params, options);
  return rig;
}

ModelParams With(const Rig& rig, const std::vector<std::string>& set) {
  std::vector<std::string> all = {
      "simulation.duration_s=" + std::to_string(rig.config.params.simulation.duration_s),
      "simulation.settle_s=" + std::to_string(rig.config.params.simulation.settle_s)};
  all.insert(all.end(), set.begin(), set.end());
  return LoadConfig(rig.path, all).params;
}

// Equal bit for bit: every value (NaN where the other is NaN), the rows and the outcome.
void ExpectSameRun(const SimulatedRecord& a, const SimulatedRecord& b) {
  EXPECT_EQ(a.status, b.status);
  EXPECT_EQ(a.rows, b.rows);
  EXPECT_EQ(a.first_row, b.first_row);
  ASSERT_EQ(a.values.size(), b.values.size());
  for (std::size_t c = 0; c < a.values.size(); ++c) {
    ASSERT_EQ(a.values[c].size(), b.values[c].size());
    for (std::size_t j = 0; j < a.values[c].size(); ++j) {
      if (std::isnan(a.values[c][j])) {
        ASSERT_TRUE(std::isnan(b.values[c][j])) << "channel " << c << " row " << j;
      } else {
        ASSERT_EQ(a.values[c][j], b.values[c][j]) << "channel " << c << " row " << j;
      }
    }
  }
  ASSERT_EQ(a.states.size(), b.states.size());
  for (std::size_t j = 0; j < a.states.size(); ++j) {
    ASSERT_EQ(a.states[j].size(), b.states[j].size());
    for (Eigen::Index i = 0; i < a.states[j].size(); ++i) ASSERT_EQ(a.states[j](i), b.states[j](i));
  }
}

struct Case {
  const char* name;
  std::vector<std::string> set;
  bool resumes;
};

// Runs the declared model into a fresh cache, then each case with the cache and alone: the two
// must agree bit for bit, and the cache resumes exactly the cases that say so. With
// `trigger_state_from_record` the runs fit the state at the trigger to a lead window of the
// record: they resume at the window's start and each fits it with its own model.
void CheckCases(const Rig& rig, const std::vector<Case>& cases, bool keep_states,
                bool trigger_state_from_record = false) {
  MeasurementParams m = rig.made.measurement;
  m.trigger_state_from_record = trigger_state_from_record;
  RecordRunOptions cached;
  cached.keep_states = keep_states;
  cached.prefix_cache = std::make_shared<LevitatedPrefixCache>();
  RecordRunOptions alone = cached;
  alone.prefix_cache = nullptr;
  const SimulatedRecord declared = SimulateOnRecord(rig.config.params, m, rig.made.record, cached);
  ASSERT_TRUE(declared.closed_loop);
  EXPECT_EQ(cached.prefix_cache->hits(), 0);
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const ModelParams params = With(rig, c.set);
    const std::int64_t before = cached.prefix_cache->hits();
    const SimulatedRecord resumed = SimulateOnRecord(params, m, rig.made.record, cached);
    EXPECT_EQ(cached.prefix_cache->hits() - before, c.resumes ? 1 : 0);
    ExpectSameRun(resumed, SimulateOnRecord(params, m, rig.made.record, alone));
  }
  // The declared model again: resumed from its own levitated time, as run before.
  const std::int64_t before = cached.prefix_cache->hits();
  ExpectSameRun(SimulateOnRecord(rig.config.params, m, rig.made.record, cached), declared);
  EXPECT_EQ(cached.prefix_cache->hits() - before, 1);
}

// Contact-law TDBs whose races rest at the axis: a changed TDB keeps its initial state.
TEST(LevitatedPrefix, ContactLawRigResumesWhatActsAfterThePowerLossBitForBit) {
  const Rig rig = MakeRig("rigid_rotor_a.toml", 0.1);
  CheckCases(rig,
             {{"friction", {"tdb.de.friction.coefficient=0.31"}, true},
              {"clearance", {"tdb.nde.clearance_m=2.1e-4"}, true},
              {"offset",
               {"tdb.de.misalignment.enabled=true", "tdb.de.misalignment.x_m=6e-5",
                "tdb.de.misalignment.y_m=-3e-5"},
               true},
              {"race inertia", {"tdb.nde.spin.inertia_kg_m2=1.2e-4"}, true},
              {"coast-down",
               {"rotor.coast_down.enabled=true", "rotor.coast_down.windage_N_m_s2=1e-3"},
               true},
              {"flux decay",
               {"amb.de.flux_decay.enabled=true", "amb.de.flux_decay.time_constant_s=4e-3"},
               true},
              // Acts on the levitated rotor: its readings feed the controller.
              {"sensor gain", {"sensor.de.gain=1.02"}, false},
              // A TDB whose centre sits beyond a clearance off: the levitated journal touches it.
              {"touching offset",
               {"tdb.nde.misalignment.enabled=true", "tdb.nde.misalignment.y_m=2.6e-4"},
               false}},
             /*keep_states=*/true);
}

// 4-DOF TDBs: races with mass on bearings and ribbons, which settle under their weight while
// the rotor levitates; a changed TDB's states are integrated alone, its load cell recomputed.
TEST(LevitatedPrefix, FourDofRigResumesWithItsRacesIntegratedAloneBitForBit) {
  const Rig rig = MakeRig("rigid_fourdof_c.toml", 0.05);
  CheckCases(rig,
             {{"friction", {"tdb.nde.friction.coefficient=0.3"}, true},
              {"race masses",
               {"tdb.de.four_dof.inner_race_mass_kg=0.5", "tdb.de.four_dof.outer_race_mass_kg=0.6"},
               true},
              {"hold time", {"amb.nde.flux_decay.hold_time_s=2e-3"}, true},
              {"rotor mass", {"rotor.rigid.mass_kg=33"}, false}},
             /*keep_states=*/false);
}

// measurement.trigger_state = "record" (the magnet-biased flexible rig's translation has it).
TEST(LevitatedPrefix, ARunThatFitsTheTriggerStateResumesAtItsLeadWindowBitForBit) {
  const Rig rig = MakeRig("rigid_rotor_a.toml", 0.1);
  CheckCases(rig,
             {{"friction", {"tdb.nde.friction.coefficient=0.3"}, true},
              {"clearance", {"tdb.de.clearance_m=3e-4"}, true},
              {"sensor gain", {"sensor.nde.gain=0.98"}, false}},
             /*keep_states=*/false, /*trigger_state_from_record=*/true);
}

// A settled start (simulation.settle_s): the controller runs before t = 0, the races settle
// through it too; its steps are watched and integrated as the levitated time's.
TEST(LevitatedPrefix, ASettledStartResumesWithItsSettlingStepsBitForBit) {
  const Rig rig = MakeRig("rigid_fourdof_c.toml", 0.05, 0.02);
  ASSERT_GT(rig.config.params.simulation.settle_s, 0.0);
  CheckCases(rig,
             {{"friction", {"tdb.de.friction.coefficient=0.3"}, true},
              {"race masses", {"tdb.nde.four_dof.outer_race_mass_kg=0.6"}, true},
              {"sensor offset", {"sensor.nde.offset_m=2e-6"}, false}},
             /*keep_states=*/true);
}

}  // namespace
}  // namespace ambdrop::fit_levitated_prefix_test
