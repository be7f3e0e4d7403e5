// A rigid rotor released at the centre with no spin: free fall until it meets the TDBs at
// t = sqrt(2 c / g), then it settles at the static penetration the contact law gives for its
// weight share.
#include <gtest/gtest.h>

#include <cmath>

#include "rt_core/model.hpp"
#include "rt_core/simulator.hpp"

namespace ambdrop::rigid_drop_test {
namespace {

ModelParams DropRig() {
  ModelParams p;
  p.rotor.kind = RotorKind::kRigid;
  p.rotor.rigid = {100.0, 1.0, 10.0, 0.5};
  p.simulation.step_s = 5e-6;
  p.simulation.spin_speed_rad_s = 0.0;
  p.simulation.initial_position = InitialPosition::kCentred;
  p.trigger.enabled = true;
  p.trigger.time_s = 0.0;
  for (double z : {0.0, 1.0}) {
    TdbParams t;
    t.name = std::string(1, z == 0.0 ? 'a' : 'b');  // not = "a": GCC 12 false -Wrestrict
    t.position_m = z;
    t.journal_radius_m = 0.04;
    t.clearance_m = 0.2e-3;
    t.contact_law() = {2e8, 2e3, 5e6, 7e3, 0.05e-3, ContactLawRibbon::kBilinear, {}, {}};
    p.tdbs.push_back(t);
  }
  return p;
}

TEST(RigidDrop, FirstContactAtFreeFallTime) {
  const Model model = BuildModel(DropRig());
  Simulator sim(model);
  State s = sim.InitialState();
  const ControlInput off = ControlInput::PowerOff();
  const double dt = model.params.simulation.step_s;
  const double expected = std::sqrt(2.0 * 0.2e-3 / 9.81);
  Observation obs;
  double contact_time = -1.0;
  while (contact_time < 0.0 && sim.Time(s) < 0.02) {
    ASSERT_EQ(sim.Step(&s, off), StepStatus::kOk);
    sim.Observe(s, &obs);
    if (obs.tdb[0].penetration_m > 0.0) contact_time = obs.time_s;
  }
  EXPECT_NEAR(contact_time, expected, dt);
  EXPECT_GT(contact_time, expected - dt);
  // Both TDBs share the symmetric rotor, and it fell straight down.
  EXPECT_NEAR(obs.tdb[1].penetration_m, obs.tdb[0].penetration_m, 1e-12);
  EXPECT_EQ(obs.tdb_journal_xy_m[0][0], 0.0);
}

TEST(RigidDrop, SettlesAtTheContactLawStaticPenetration) {
  for (double crushing_m : {0.05e-3, 0.2e-3}) {  // crushed ribbon, and ribbon alone
    ModelParams p = DropRig();
    for (auto& t : p.tdbs) t.contact_law().ribbon_crushing_m = crushing_m;
    const Model model = BuildModel(p);
    Simulator sim(model);
    State s = sim.InitialState();
    const ControlInput off = ControlInput::PowerOff();
    for (int i = 0; i < 300000; ++i) ASSERT_EQ(sim.Step(&s, off), StepStatus::kOk);
    Observation obs;
    sim.Observe(s, &obs);
    const ContactLawParams& c = p.tdbs[0].contact_law();
    const double share_N = 100.0 * 9.81 / 2.0;
    const double expected =
        share_N < c.ribbon_stiffness_N_per_m * c.ribbon_crushing_m
            ? share_N / c.ribbon_stiffness_N_per_m
            : c.ribbon_crushing_m + (share_N - c.ribbon_stiffness_N_per_m * c.ribbon_crushing_m) /
                                        c.bearing_stiffness_N_per_m;
    EXPECT_NEAR(obs.tdb[0].penetration_m, expected, 1e-6 * expected) << "urd " << crushing_m;
    EXPECT_NEAR(obs.tdb[0].normal_force_N, share_N, 1e-5 * share_N);
  }
}

}  // namespace
}  // namespace ambdrop::rigid_drop_test
