// The catcher-bearing TDB (seed 003 SDCB/DDCB, seed 004 metal rubber ring): the impact function
// (seed 003 Eq. (1)-(2)) against hand-computed values for both exponents and at the ends and
// middle of its STEP ramp; one ball bearing's force by hand; the static equilibrium under
// gravity; fixed-seed randomised impacts of a spinning mass that never gain energy; and the
// step through a drop allocation-free and bit-identical.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>

#include "malloc_guard.hpp"
#include "rt_core/catcher_bearing_tdb.hpp"
#include "rt_core/impact_function.hpp"
#include "rt_core/model.hpp"
#include "rt_core/simulator.hpp"
#include "test_configs.hpp"

namespace ambdrop::catcher_bearing_test {
namespace {

using C = CatcherBearingTdb;

TEST(ImpactFunction, StepRampsCubicallyFromZeroToOne) {
  // ADAMS STEP(x, 0, 0, dm, 1) = a^2 (3 - 2a), a = x / dm.
  const double dm = 1e-5;
  EXPECT_EQ(AdamsStep(-1e-6, 0.0, 0.0, dm, 1.0), 0.0);
  EXPECT_EQ(AdamsStep(0.0, 0.0, 0.0, dm, 1.0), 0.0);
  EXPECT_NEAR(AdamsStep(0.25 * dm, 0.0, 0.0, dm, 1.0), 0.15625, 1e-15);  // 1/16 * 5/2
  EXPECT_NEAR(AdamsStep(0.5 * dm, 0.0, 0.0, dm, 1.0), 0.5, 1e-15);
  EXPECT_NEAR(AdamsStep(0.75 * dm, 0.0, 0.0, dm, 1.0), 0.84375, 1e-15);  // 9/16 * 3/2
  EXPECT_EQ(AdamsStep(dm, 0.0, 0.0, dm, 1.0), 1.0);
  EXPECT_EQ(AdamsStep(2 * dm, 0.0, 0.0, dm, 1.0), 1.0);
  // Smooth at both ends: the slope d STEP / da = 6a(1-a) vanishes there (a = 1e-7: 3e-7).
  const double h = 1e-7 * dm;
  EXPECT_LT(AdamsStep(h, 0.0, 0.0, dm, 1.0) / 1e-7, 1e-6);
  EXPECT_LT((1.0 - AdamsStep(dm - h, 0.0, 0.0, dm, 1.0)) / 1e-7, 1e-6);
}

TEST(ImpactFunction, PointContactExponentThreeHalves) {
  const ImpactParams p{1e9, 1.5, 1000.0, 1e-5};
  // 4 um: k d^1.5 = 1e9 * 8e-9 = 8 N; damping 1000 * 0.01 * STEP(0.4) = 10 * 0.352 = 3.52 N.
  EXPECT_NEAR(ImpactForce(p, 4e-6, 0.01), 11.52, 1e-12);
  // Beyond dm the damping is full: 1e9 * (1.6e-5)^1.5 = 64 N, + 1000 * 0.02.
  EXPECT_NEAR(ImpactForce(p, 16e-6, 0.02), 64.0 + 20.0, 1e-9);
  // At first contact no damping jump: 1 nm approaching at 1 m/s gives ~ 1e9*3.2e-14 + 1000*3e-8.
  EXPECT_LT(ImpactForce(p, 1e-9, 1.0), 1e-3);
  EXPECT_EQ(ImpactForce(p, 0.0, 1.0), 0.0);
  EXPECT_EQ(ImpactForce(p, -1e-6, 1.0), 0.0);
  // A fast-receding contact does not pull.
  EXPECT_EQ(ImpactForce(p, 16e-6, -1.0), 0.0);
}

TEST(ImpactFunction, LineContactExponentTenNinthsWithEquationTwoStiffness) {
  // Eq. (2): L = 10 mm: k = 7.85e10 * 10^(-16/9) = 7.85e10 * 0.0166810 = 1.30946e9 N/m^(10/9).
  const double k = LineContactStiffness(0.01);
  EXPECT_NEAR(k, 1.30946e9, 1e4);
  const ImpactParams p{k, 10.0 / 9.0, 500.0, 1e-5};
  // 10 um = dm: k * 10^(-50/9) = 1.30946e9 * 2.78256e-6 = 3643.67 N, + 500 * 0.1 (full damping).
  EXPECT_NEAR(ImpactForce(p, 1e-5, 0.1), 3643.67 + 50.0, 0.05);
  // Middle of the ramp, 5 um receding slowly: k * 5e-6^(10/9) = 1.30946e9 * 1.288147e-6
  // = 1686.78 N, minus 500 * 0.1 * STEP(1/2) = 25 N.
  EXPECT_NEAR(ImpactForce(p, 5e-6, -0.1), 1686.78 - 25.0, 0.05);
}

TdbParams Catcher(int decks, CatcherMount mount) {
  TdbParams p;
  p.name = std::string(1, 'c');  // not = "c": GCC 12 warns falsely (-Wrestrict, PR 105329)
  p.UseCatcher();
  p.journal_radius_m = 5.875e-3;
  p.clearance_m = 0.125e-3;
  p.friction = {FrictionLaw::kRegularisedCoulomb, 0.1, 200.0, 0.0};
  CatcherBearingParams& c = p.catcher();
  c.decks = decks;
  c.mount = mount;
  c.impact = {LineContactStiffness(0.01), 10.0 / 9.0, 1000.0, 1e-5};
  c.inner_race = {4e-3, 3.2e-7};
  c.inner_bearing = {12, 2, 2.381e-3, 16.5e-3, 1.55e10, 1.36e10, 800.0, 1e-6, 6e-6, 5.9e-6, 1e-3};
  c.intermediate_race = {0.026, 6.3e-6};
  c.outer_bearing = {15, 1, 3.5e-3, 31e-3, 1.89e10, 1.64e10, 1000.0, 1e-6, 10e-6, 1.95e-5, 1e-3};
  c.ring = {0.35, 1e6, 1e4};
  return p;
}

using States = std::array<double, kMaxTdbStates>;

TEST(CatcherBearing, StateLayoutPerDecksAndMount) {
  EXPECT_EQ(C(Catcher(1, CatcherMount::kRigid)).StateSize(), 6);
  EXPECT_EQ(C(Catcher(2, CatcherMount::kRigid)).StateSize(), 12);
  const C both(Catcher(2, CatcherMount::kMetalRubberRing));
  EXPECT_EQ(both.StateSize(), 16);
  EXPECT_EQ(both.intermediate_offset(), 6);
  EXPECT_EQ(both.house_offset(), 12);
  EXPECT_EQ(C(Catcher(1, CatcherMount::kMetalRubberRing)).house_offset(), 6);
}

TEST(CatcherBearing, OneBallBearingByHand) {
  // 4 balls, cage at 0: balls at 0, 90, 180, 270 deg. The inner ring 3 um + Pd/2 below the outer
  // ring loads the bottom ball only: rows * kn * (3 um)^1.5 upwards, kn the series stiffness.
  BallBearingRowParams b{4, 2, 2e-3, 16e-3, 1.6e10, 1.6e10, 0.0, 1e-6, 6e-6, 0.0, 0.0};
  const BallRow row = MakeBallRow(b, "test");
  const double kn = 1.6e10 / (2.0 * std::sqrt(2.0));  // (2 k^(-2/3))^(-3/2) = k / 2^1.5
  EXPECT_NEAR(row.ball_contact.stiffness_N_per_m_e, kn, 1e-6 * kn);
  double fx = 0.0, fy = 0.0;
  BallRowForce(row, 0.0, 0.0, -6e-6, 0.0, 0.0, &fx, &fy);
  EXPECT_NEAR(fy, 2.0 * kn * 3e-6 * std::sqrt(3e-6), 1e-9);
  EXPECT_NEAR(fx, 0.0, 1e-9);
  BallRowForce(row, 0.0, 0.0, -2e-6, 0.0, 0.0, &fx, &fy);  // inside the clearance
  EXPECT_EQ(fy, 0.0);
  // Cage turned 45 deg: two balls at -45 and -135 deg share the load, each at d cos 45 - Pd/2.
  const double d = 20e-6;
  BallRowForce(row, std::numbers::pi / 4.0, 0.0, -d, 0.0, 0.0, &fx, &fy);
  const double each = kn * std::pow(d * std::sqrt(0.5) - 3e-6, 1.5);
  EXPECT_NEAR(fy, 2.0 * 2.0 * each * std::sqrt(0.5), 1e-9 * fy);
  EXPECT_NEAR(fx, 0.0, 1e-9 * fy);
  // Cage speed (Harris): (1 - D/dm)/2 of the inner ring's speed.
  EXPECT_NEAR(row.cage_inner_factor, 0.5 * (1.0 - 0.125), 1e-15);
}

TEST(CatcherBearing, JournalImpactFrictionAndSpin) {
  const C tdb(Catcher(1, CatcherMount::kRigid));
  States s{}, rate{};
  TdbForce f;
  const double spin = 1000.0;
  tdb.Evaluate({0.0, -0.135e-3, 0.0, 0.0, spin}, s.data(), rate.data(), &f);
  const double fn = LineContactStiffness(0.01) * std::pow(1e-5, 10.0 / 9.0);  // Eq. (1)
  EXPECT_NEAR(f.normal_force_N, fn, 1e-6 * fn);
  EXPECT_NEAR(f.fy_N, fn, 1e-6 * fn);
  const double ft = 0.1 * fn * 2.0 / std::numbers::pi * std::atan(200.0 * spin * 5.875e-3);
  EXPECT_NEAR(f.tangential_force_N, ft, 1e-6 * ft);
  EXPECT_NEAR(rate[C::kVy], -fn / 4e-3, 1e-6 * fn / 4e-3);  // no bearing force yet (centred)
  EXPECT_NEAR(rate[C::kSpin], ft * 6e-3 / 3.2e-7, 1e-6 * ft * 6e-3 / 3.2e-7);  // seed 004 Eq. (3)
}

TEST(CatcherBearing, StartsInStaticEquilibriumUnderGravity) {
  for (int decks : {1, 2}) {
    for (CatcherMount mount : {CatcherMount::kRigid, CatcherMount::kMetalRubberRing}) {
      TdbParams p = Catcher(decks, mount);
      p.catcher().gravity_y_m_s2 = -9.81;
      const C tdb(p);
      States s{}, rate{};
      tdb.InitialState(s.data());
      TdbForce f;
      tdb.Evaluate({0.0, 0.0, 0.0, 0.0, 0.0}, s.data(), rate.data(), &f);
      // Vertical accelerations vanish (odd ball counts leave a tiny sideways force).
      EXPECT_NEAR(rate[C::kVy], 0.0, 1e-6);
      if (decks == 2) {
        EXPECT_NEAR(rate[tdb.intermediate_offset() + C::kVy], 0.0, 1e-6);
      }
      if (mount == CatcherMount::kMetalRubberRing) {
        EXPECT_NEAR(rate[tdb.house_offset() + C::kHouseVy], 0.0, 1e-6);
      }
      EXPECT_LT(s[C::kY], -3e-6);  // sags at least the inner bearing's radial clearance
      // The foundation carries every race's weight (within 1 %: the 15-ball outer bearing's
      // vertical sag also pushes the intermediate race a little sideways).
      double weight = 4e-3 + (decks == 2 ? 0.026 : 0.0) +
                      (mount == CatcherMount::kMetalRubberRing ? 0.35 : 0.0);
      EXPECT_NEAR(f.support_force_N(), weight * 9.81, 0.01 * weight * 9.81);
    }
  }
}

// ---- Fixed-seed randomised impacts of a spinning point mass: energy is never gained ----

constexpr int kY0 = 5;  // journal x, y, vx, vy, spin, then the TDB states
constexpr int kN = kY0 + kMaxTdbStates;
using Y = std::array<double, kN>;

double BallEnergy(const BallRow& r, double dx, double dy) {
  double e = 0.0;
  for (int j = 0; j < r.balls; ++j) {
    const double d = dx * r.cos_ball[j] + dy * r.sin_ball[j] - r.radial_clearance_m;
    if (d > 0.0) e += r.rows * r.ball_contact.stiffness_N_per_m_e * d * d * std::sqrt(d) / 2.5;
  }
  return e;
}

// Kinetic energy of journal, races, house and spins plus the contacts' and ring's elastic energy.
double Energy(const C& tdb, double mass, double inertia, const Y& y) {
  const TdbParams& p = tdb.params();
  const CatcherBearingParams& c = p.catcher();
  const double* s = y.data() + kY0;
  auto sq = [](double a, double b) { return a * a + b * b; };
  double e = 0.5 * mass * sq(y[2], y[3]) + 0.5 * inertia * y[4] * y[4];
  e += 0.5 * c.inner_race.mass_kg * sq(s[C::kVx], s[C::kVy]) +
       0.5 * c.inner_race.polar_inertia_kg_m2 * s[C::kSpin] * s[C::kSpin];
  const double pen = std::sqrt(sq(y[0] - s[C::kX], y[1] - s[C::kY])) - p.clearance_m;
  if (pen > 0.0) {
    const double ex = c.impact.exponent;
    e += c.impact.stiffness_N_per_m_e * std::pow(pen, ex + 1.0) / (ex + 1.0);
  }
  double hx = 0.0, hy = 0.0;
  if (tdb.house_offset() >= 0) {
    const double* h = s + tdb.house_offset();
    hx = h[C::kHouseX];
    hy = h[C::kHouseY];
    e += 0.5 * c.ring.house_mass_kg * sq(h[C::kHouseVx], h[C::kHouseVy]) +
         0.5 * c.ring.stiffness_N_per_m * sq(hx, hy);
  }
  double ox = hx, oy = hy;
  if (tdb.intermediate_offset() >= 0) {
    const double* m = s + tdb.intermediate_offset();
    ox = m[C::kX];
    oy = m[C::kY];
    e += 0.5 * c.intermediate_race.mass_kg * sq(m[C::kVx], m[C::kVy]) +
         0.5 * c.intermediate_race.polar_inertia_kg_m2 * m[C::kSpin] * m[C::kSpin];
    e += BallEnergy(tdb.outer_bearing(), ox - hx, oy - hy);
  }
  e += BallEnergy(tdb.inner_bearing(), s[C::kX] - ox, s[C::kY] - oy);
  return e;
}

void Rate(const C& tdb, double mass, double inertia, const Y& y, Y* dy) {
  TdbForce f;
  dy->fill(0.0);
  tdb.Evaluate({y[0], y[1], y[2], y[3], y[4]}, y.data() + kY0, dy->data() + kY0, &f);
  (*dy)[0] = y[2];
  (*dy)[1] = y[3];
  (*dy)[2] = f.fx_N / mass;
  (*dy)[3] = f.fy_N / mass;
  (*dy)[4] = f.torque_on_rotor_N_m / inertia;
}

TEST(CatcherBearingEnergy, RandomisedImpactsNeverGainEnergy) {
  // Ball passage off: the cage then carries no balls round. (With it on, the kinematic cage
  // moves loaded balls, a parametric excitation fed in reality by the race spin: not a test
  // of dissipation.)
  std::uint64_t seed = 0x9E3779B97F4A7C15ull;
  auto uniform = [&seed]() {
    seed ^= seed << 13;
    seed ^= seed >> 7;
    seed ^= seed << 17;
    return static_cast<double>(seed >> 11) * 0x1.0p-53;
  };
  int trial = 0;
  for (int decks : {1, 2}) {
    for (CatcherMount mount : {CatcherMount::kRigid, CatcherMount::kMetalRubberRing}) {
      for (int k = 0; k < 3; ++k, ++trial) {
        TdbParams p = Catcher(decks, mount);
        p.catcher().ball_passage = false;
        p.catcher().impact.exponent = uniform() < 0.5 ? 1.5 : 10.0 / 9.0;
        p.catcher().impact.max_damping_N_s_per_m = 2000.0 * uniform();
        p.friction.coefficient = 0.3 * uniform();
        p.catcher().ring.damping_N_s_per_m = 1e4 * uniform();
        const C tdb(p);
        const double mass = 0.5 + 2.0 * uniform();
        const double inertia = 1e-4 + 1e-3 * uniform();
        Y y{};
        const double angle = 2.0 * std::numbers::pi * uniform();
        const double speed = 0.02 + 0.3 * uniform();
        const double tilt = 0.6 * (uniform() - 0.5);
        y[0] = 0.999 * p.clearance_m * std::cos(angle);
        y[1] = 0.999 * p.clearance_m * std::sin(angle);
        y[2] = speed * std::cos(angle + tilt);
        y[3] = speed * std::sin(angle + tilt);
        y[4] = 1200.0 * uniform();
        const double e0 = Energy(tdb, mass, inertia, y);
        double previous = e0;
        bool touched = false;
        const double h = 2e-8;
        for (int i = 0; i < 100000; ++i) {
          Y k1, k2, k3, k4, st;
          Rate(tdb, mass, inertia, y, &k1);
          for (int n = 0; n < kN; ++n) st[n] = y[n] + 0.5 * h * k1[n];
          Rate(tdb, mass, inertia, st, &k2);
          for (int n = 0; n < kN; ++n) st[n] = y[n] + 0.5 * h * k2[n];
          Rate(tdb, mass, inertia, st, &k3);
          for (int n = 0; n < kN; ++n) st[n] = y[n] + h * k3[n];
          Rate(tdb, mass, inertia, st, &k4);
          for (int n = 0; n < kN; ++n) y[n] += h / 6.0 * (k1[n] + 2 * k2[n] + 2 * k3[n] + k4[n]);
          const double e = Energy(tdb, mass, inertia, y);
          ASSERT_LE(e, previous + 1e-9 * e0) << "trial " << trial << " step " << i;
          previous = e;
          TdbForce f;
          Y rate{};
          tdb.Evaluate({y[0], y[1], y[2], y[3], y[4]}, y.data() + kY0, rate.data() + kY0, &f);
          touched = touched || f.normal_force_N > 0.0;
          if (touched && f.penetration_m < -0.3 * p.clearance_m) break;
        }
        EXPECT_TRUE(touched) << "trial " << trial;
        EXPECT_LT(Energy(tdb, mass, inertia, y), e0) << "trial " << trial;
      }
    }
  }
}

// ---- The step through a drop: no heap, bit-identical repeats ----

Model Rig(int variant) {
  ModelParams p = testing::LoadTestConfig(
      variant == 0 ? "ddcb_rigid.toml" : "metal_rubber_ring.toml", {"trigger.time_s=0.001"});
  if (variant == 2) {  // the largest layout: two decks on the metal rubber ring (16 states)
    p = testing::LoadTestConfig("ddcb_rigid.toml", {"trigger.time_s=0.001"});
    for (TdbParams& t : p.tdbs) {
      t.catcher().mount = CatcherMount::kMetalRubberRing;
      t.catcher().ring = {0.35, 1e6, 1e4};
    }
  }
  return BuildModel(p);
}

ControlInput InputAt(const Model& m, std::int64_t step) {
  return step < m.trigger_step ? ControlInput::Powered() : ControlInput::PowerOff();
}

TEST(CatcherBearingStep, NoHeapAllocationAndBitIdenticalRepeats) {
  for (int variant = 0; variant < 3; ++variant) {
    SCOPED_TRACE(variant);
    const Model model = Rig(variant);
    Simulator a(model), b(model);
    State sa = a.InitialState(), sb = b.InitialState();
    Observation obs;
    double peak = 0.0;
    std::int64_t allocations = 0;
    {
      testing::MallocGuard guard;
      for (int i = 0; i < 20000; ++i) {
        if (a.Step(&sa, InputAt(model, sa.step_index)) != StepStatus::kOk) break;
        a.Observe(sa, &obs);
        peak = std::max(peak, obs.tdb[0].normal_force_N);
      }
      allocations = guard.allocations();
    }
    ASSERT_EQ(sa.step_index, 20000);
    EXPECT_GT(peak, 0.0);  // the window contained contacts
    if (testing::MallocGuard::Available()) {
      EXPECT_EQ(allocations, 0);
    }
    for (int i = 0; i < 20000; ++i)
      ASSERT_EQ(b.Step(&sb, InputAt(model, sb.step_index)), StepStatus::kOk);
    EXPECT_EQ(std::memcmp(sa.y.data(), sb.y.data(), sizeof(double) * model.state_size), 0);
  }
}

}  // namespace
}  // namespace ambdrop::catcher_bearing_test
