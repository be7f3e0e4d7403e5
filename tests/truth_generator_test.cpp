// The independent truth generator (tools/truth) against physics it must obey: free fall after
// power loss, the set point held by an integrating controller, the race's spin-up rate under
// sliding friction, no energy created in a frictional contact, and bit-exact repeat runs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "drop_run.hpp"
#include "plant.hpp"
#include "rig.hpp"
#include "tdb_contact.hpp"

namespace ambdrop_truth {
namespace {

Rig RigA() {
  return ReadRig(std::string(AMBDROP_SOURCE_DIR) + "/tools/truth/rigs/rigid_rotor_a.json");
}

RunOptions Quiet() {
  RunOptions o;
  o.add_noise = false;
  return o;
}

// With form-a decay at tau -> 0 the AMB force vanishes at the trigger: every point of the
// (levitated, at rest) rotor falls as g t^2 / 2 until the journal meets a TDB.
TEST(TruthGenerator, FreeFallAfterPowerLossFollowsGravity) {
  Rig rig = RigA();
  rig.power_loss.form = FluxDecayForm::kFormA;
  rig.power_loss.time_constant_s = 1e-8;
  rig.acquisition.sensor_quantisation_m = 0.0;
  rig.acquisition.record_length_s = rig.acquisition.trigger_time_s + 0.012;
  const RunResult run = RunDrop(rig, 1, Quiet());
  ASSERT_TRUE(run.finite);
  const double tp = rig.acquisition.trigger_time_s;
  const double g = rig.gravity_m_s2;
  const double contact_s = std::sqrt(2.0 * rig.tdbs[0].clearance_m / g);
  double y0 = 0.0;
  int checked = 0;
  bool touched = false;
  for (const RecordRow& r : run.rows) {
    const double since = r.t_s - tp;
    if (std::abs(since) < 1e-9) y0 = r.displacement_m[1][1];
    if (since > 0.0 && since < 0.9 * contact_s) {
      // One fine step of held force at the trigger is the only departure: g t h.
      const double tolerance = g * since * rig.step_s + 1e-9;
      EXPECT_NEAR(r.displacement_m[1][1], y0 - 0.5 * g * since * since, tolerance) << since;
      EXPECT_NEAR(r.displacement_m[0][1], y0 - 0.5 * g * since * since, tolerance) << since;
      EXPECT_EQ(r.normal_force_N[0], 0.0);
      ++checked;
    }
    if (since > contact_s + 1e-3 && (r.normal_force_N[0] > 0.0 || r.normal_force_N[1] > 0.0)) {
      touched = true;
    }
  }
  EXPECT_GT(checked, 100);
  EXPECT_TRUE(touched) << "the fall must end on the TDBs";
}

// An integral in the PID drives the static error to zero: started centred with empty
// integrals (the rotor sags under its weight and a side pull), it ends at the set point,
// each sensor reading zero. Without the integral it stays off by the load over the stiffness.
TEST(TruthGenerator, IntegralHoldsTheSetPoint) {
  Rig rig = RigA();
  rig.acquisition.trigger_time_s = 10.0;  // never
  rig.acquisition.record_length_s = 1.2;
  rig.acquisition.sensor_quantisation_m = 0.0;
  rig.side_pull.force_N = {20.0, 0.0};
  rig.side_pull.position_m = 0.2;
  RunOptions options = Quiet();
  options.start_at_equilibrium = false;
  const RunResult with_integral = RunDrop(rig, 1, options);
  ASSERT_TRUE(with_integral.finite);
  const RecordRow& end = with_integral.rows.back();
  for (int s = 0; s < 2; ++s) {
    for (int axis = 0; axis < 2; ++axis) EXPECT_NEAR(end.displacement_m[s][axis], 0.0, 2e-8);
  }
  rig.controller.ki_per_s = 0.0;
  const RunResult proportional = RunDrop(rig, 1, options);
  EXPECT_LT(proportional.rows.back().displacement_m[0][1], -1e-6);
}

// Jarroux 2019 Eq. (9) with the journal sliding (slip >> v0): the race spins up at the
// constant rate mu N R_ir / J, with the rig's own inner-race radius.
TEST(TruthGenerator, RaceSpinUpUnderSlidingFrictionIsMuNROverJ) {
  TdbRig tdb = RigA().tdbs[0];
  tdb.inner_race_radius_m = 1.1 * tdb.journal_radius_m;  // so that the radius shows
  tdb.race_viscous_drag_N_m_s = 0.0;
  tdb.race_drag_torque_N_m = 0.0;
  const double penetration = 5e-6;
  JournalAtTdb j;
  j.y_m = -(tdb.clearance_m + penetration);
  j.spin_rad_s = 1200.0;
  const double normal = tdb.contact_stiffness * penetration;
  const double rate =
      tdb.friction_coefficient * normal * tdb.inner_race_radius_m / tdb.race_inertia_kg_m2;
  double race = 0.0;
  const double h = 1e-6;
  const int steps = 20000;
  for (int k = 0; k < steps; ++k) {
    const ContactForces c = EvaluateContact(tdb, j, race);
    race += h * c.race_acceleration_rad_s2;
  }
  ASSERT_LT(race * tdb.inner_race_radius_m, j.spin_rad_s * tdb.journal_radius_m - 1.0);
  EXPECT_NEAR(race, rate * h * steps, 1e-9 * rate * h * steps);
  const ContactForces c = EvaluateContact(tdb, j, 0.0);
  EXPECT_NEAR(c.normal_N, normal, 1e-9 * normal);
  EXPECT_NEAR(c.spin_torque_N_m, -tdb.friction_coefficient * normal * tdb.journal_radius_m, 1e-12);
}

// No AMB, no motor: a rotor thrown against its TDBs with spin and friction. The mechanical
// energy (kinetic, gravity, contact springs) may only fall, and friction takes a share of it.
TEST(TruthGenerator, FrictionalContactNeverAddsEnergy) {
  Rig rig = RigA();
  Plant plant(rig);
  PlantState y = PlantState::Zero();
  y(kVx) = 0.05;
  y(kVy) = -0.08;
  y(kWx) = 0.1;
  y(kSpin) = rig.spin_speed_rad_s;
  PlantInput input;
  input.motor_on = false;  // coils at zero: no AMB
  double previous = plant.Energy(y);
  const double start = previous;
  int touches = 0;
  PlantState rate;
  PlantOutputs out;
  for (int k = 0; k < 40000; ++k) {
    plant.Step(&y, input);
    const double e = plant.Energy(y);
    // Rounding of a 1e2 J sum: far below one step's friction loss while sliding.
    EXPECT_LE(e, previous + 1e-9 * std::abs(start)) << "step " << k;
    previous = e;
    plant.Derivative(y, input, &rate, &out);
    touches += out.tdb[0].normal_N > 0.0 || out.tdb[1].normal_N > 0.0;
  }
  EXPECT_GT(touches, 100);
  EXPECT_LT(previous, start - 1e-3 * std::abs(start));
}

// The same rig and seed give the same record to the bit; another seed, other noise.
TEST(TruthGenerator, RepeatRunsAreBitIdentical) {
  Rig rig = RigA();
  rig.acquisition.record_length_s = rig.acquisition.trigger_time_s + 0.02;
  const RunResult a = RunDrop(rig, 7);
  const RunResult b = RunDrop(rig, 7);
  const RunResult c = RunDrop(rig, 8);
  ASSERT_EQ(a.rows.size(), b.rows.size());
  ASSERT_EQ(a.rows.size(), c.rows.size());
  EXPECT_EQ(std::memcmp(a.rows.data(), b.rows.data(), a.rows.size() * sizeof(RecordRow)), 0);
  EXPECT_NE(std::memcmp(a.rows.data(), c.rows.data(), a.rows.size() * sizeof(RecordRow)), 0);
}

}  // namespace
}  // namespace ambdrop_truth
