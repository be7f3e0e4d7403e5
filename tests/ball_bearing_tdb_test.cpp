// The seed-002 TDB (Chen 2019, BallBearingTdb) against hand-computed forces: the Hertz line
// contact (Eq. (5)), static/kinetic friction switching, Harris's curvature sums and krb
// (Eq. (14)-(17)), the discrete-ball sum (Eq. (13), (18)-(19)) at a few positions, the
// linearised stiffness against the paper's Kb; the races' static equilibrium; fixed-seed
// randomised impacts that never gain energy; no allocation and bit-identical repeats.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>

#include "malloc_guard.hpp"
#include "rt_core/ball_bearing_tdb.hpp"
#include "rt_core/hertz_line_contact.hpp"
#include "rt_core/slip_friction.hpp"

namespace ambdrop::ball_bearing_tdb_test {
namespace {

using S = BallBearingTdb;
constexpr double kPi = std::numbers::pi;
using States = std::array<double, S::kStatesElasticSupport>;

// The rig of configs/chen_itri_flexible.toml (Chen 2019 Tables II, III).
DiscreteBallParams ChenBalls() {
  DiscreteBallParams b;
  b.balls = 27;
  b.ball_diameter_m = 7.938e-3;
  b.pitch_diameter_m = 0.0725;
  b.inner_groove_conformity = 0.52;
  b.outer_groove_conformity = 0.53;
  b.inner_delta_star = 0.612;
  b.outer_delta_star = 0.706;
  b.race_youngs_modulus_Pa = 208e9;
  b.race_poisson_ratio = 0.3;
  b.ball_youngs_modulus_Pa = 310e9;
  b.ball_poisson_ratio = 0.26;
  b.damping_N_s_per_m = 1320.0;
  return b;
}

TdbParams Tdb(bool support = false) {
  TdbParams p;
  p.name = std::string(1, 't');  // not = "t": GCC 12 warns falsely (-Wrestrict, PR 105329)
  p.UseBallBearing();
  p.journal_radius_m = 0.0299;
  p.clearance_m = 1e-4;
  p.spin = {true, 6e-5, 0.0, 0.0, 0.0, 0.0};
  BallBearingTdbParams& b = p.ball_bearing();
  b.inner_race_mass_kg = 0.08;
  b.line_contact = {208e9, 0.013};
  b.friction = {SlipFrictionLaw::kStaticKinetic, 0.15, 0.1, 1e-3};
  b.bearing = ChenBalls();
  b.support = {support, 5e8, 27900.0, 0.12};
  return p;
}

TEST(LineContact, HertzLineContactByHand) {
  const LineContactParams p{208e9, 0.013};
  // Eq. (5): pi/2 * 1e-5 * 208e9 * 0.013 * sqrt(1e-5 / (2 * (1e-4 + 1e-5))) = 9055.56 N.
  EXPECT_NEAR(LineContactForce(p, 1e-4, 1e-5), 9055.558153363561, 1e-6);
  // Twice the deflection: (2)(sqrt(2e-5/2.4e-4)/sqrt(1e-5/2.2e-4)) times, 2.708 x.
  EXPECT_NEAR(LineContactForce(p, 1e-4, 2e-5) / 9055.558153363561,
              2.0 * std::sqrt(2e-5 / 2.4e-4) / std::sqrt(1e-5 / 2.2e-4), 1e-12);
  EXPECT_EQ(LineContactForce(p, 1e-4, 0.0), 0.0);
  EXPECT_EQ(LineContactForce(p, 1e-4, -1e-6), 0.0);
}

TEST(SlipFriction, StaticAndKineticBySignOfSlip) {
  const SlipFrictionParams p{SlipFrictionLaw::kStaticKinetic, 0.15, 0.1, 1e-3};
  EXPECT_DOUBLE_EQ(SlipFrictionForce(p, 1000.0, 0.5), 100.0);    // vs > vi: +mu_d
  EXPECT_DOUBLE_EQ(SlipFrictionForce(p, 1000.0, -0.5), -100.0);  // vs < vi: -mu_d
  EXPECT_DOUBLE_EQ(SlipFrictionForce(p, 1000.0, 1.001e-3), 100.0);
  EXPECT_DOUBLE_EQ(SlipFrictionForce(p, 1000.0, 1e-3), 150.0);  // static limit at the band edge
  EXPECT_DOUBLE_EQ(SlipFrictionForce(p, 1000.0, -0.5e-3), -75.0);
  EXPECT_EQ(SlipFrictionForce(p, 1000.0, 0.0), 0.0);  // rolling together, nothing to resist
  const SlipFrictionParams none{SlipFrictionLaw::kNone, 0.15, 0.1, 1e-3};
  EXPECT_EQ(SlipFrictionForce(none, 1000.0, 0.5), 0.0);
}

TEST(DiscreteBalls, CurvatureSumsAndStiffnessByHand) {
  const DiscreteBallParams b = ChenBalls();
  const double g = 7.938e-3 / 0.0725;  // gamma
  // Eq. (16)-(17)
  const RacewayCurvature in = InnerRacewayCurvature(b);
  const RacewayCurvature out = OuterRacewayCurvature(b);
  EXPECT_NEAR(in.sum_rho_per_m, (4.0 - 1.0 / 0.52 + 2.0 * g / (1.0 - g)) / 7.938e-3, 1e-9);
  EXPECT_NEAR(in.sum_rho_per_m, 292.621, 1e-3);
  EXPECT_NEAR(out.sum_rho_per_m, 241.350, 1e-3);
  EXPECT_NEAR(in.difference, 0.93377, 1e-5);
  EXPECT_NEAR(out.difference, 0.88182, 1e-5);
  // Eq. (15) for steel on steel is Harris's 2.15e5 (sum_rho)^-1/2 (delta*)^-3/2 in N, mm.
  DiscreteBallParams steel = b;
  steel.ball_youngs_modulus_Pa = 208e9;
  steel.ball_poisson_ratio = 0.3;
  const double k_mm = RacewayContactStiffness(steel, 292.621, 0.612) * std::pow(1e-3, 1.5);
  EXPECT_NEAR(k_mm / (2.15e5 / std::sqrt(0.292621) / std::pow(0.612, 1.5)), 1.0, 3e-3);
  // Eq. (14): series law of the two contacts.
  const double ki = RacewayContactStiffness(b, in.sum_rho_per_m, 0.612);
  const double ko = RacewayContactStiffness(b, out.sum_rho_per_m, 0.706);
  const DiscreteBallBearing bb = MakeDiscreteBallBearing(b);
  EXPECT_NEAR(bb.ball_stiffness_N_per_m1_5,
              std::pow(std::pow(ki, -2.0 / 3.0) + std::pow(ko, -2.0 / 3.0), -1.5), 1.0);
  EXPECT_NEAR(bb.cage_speed_ratio, 0.5 * (1.0 - g), 1e-15);
}

TEST(DiscreteBalls, SumOverBallsAtAFewPositions) {
  DiscreteBallBearing b;
  b.balls = 4;
  b.ball_stiffness_N_per_m1_5 = 1e10;
  double fx = 0.0, fy = 0.0;
  // Straight down onto ball 3 (theta = 3pi/2): only it is loaded, Q = krb d^1.5.
  double q = DiscreteBallForce(b, 0.0, -4e-6, 0.0, &fx, &fy);
  EXPECT_NEAR(fy, 1e10 * 8e-9, 1e-6);  // 4e-6^1.5 = 8e-9
  EXPECT_NEAR(fx, 0.0, 1e-9);
  EXPECT_NEAR(q, 80.0, 1e-9);
  // Along 225 deg between balls 2 and 3: each sees d cos(45 deg).
  const double d = 4e-6, each = 1e10 * std::pow(d / std::sqrt(2.0), 1.5);
  DiscreteBallForce(b, -d / std::sqrt(2.0), -d / std::sqrt(2.0), 0.0, &fx, &fy);
  EXPECT_NEAR(fx, each, 1e-6);
  EXPECT_NEAR(fy, each, 1e-6);
  // The cage turned 45 deg: now straight down sits between two balls.
  DiscreteBallForce(b, 0.0, -d, kPi / 4.0, &fx, &fy);
  EXPECT_NEAR(fy, 2.0 * each / std::sqrt(2.0), 1e-6);
  EXPECT_NEAR(fx, 0.0, 1e-9);
  // Radial play of 1 um: ball 3 sees 3 um.
  b.radial_clearance_m = 1e-6;
  DiscreteBallForce(b, 0.0, -d, 0.0, &fx, &fy);
  EXPECT_NEAR(fy, 1e10 * std::pow(3e-6, 1.5), 1e-6);
  DiscreteBallForce(b, 0.0, -0.5e-6, 0.0, &fx, &fy);
  EXPECT_EQ(fy, 0.0);
}

TEST(DiscreteBalls, LinearisedAtTheStaticLoadGivesThePapersKb) {
  // Chen 2019 Table III: Kb = 1.32e8 N/m. The 27 balls of Eq. (13)-(19), linearised at the
  // rear/front static share of a 32 kg rotor (~157 N), come within 10 %.
  const DiscreteBallBearing b = MakeDiscreteBallBearing(ChenBalls());
  const double load = 32.0 * 9.81 / 2.0;
  double low = 0.0, high = 1e-4, fx = 0.0, fy = 0.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (low + high);
    DiscreteBallForce(b, 0.0, -mid, 0.0, &fx, &fy);
    (fy < load ? low : high) = mid;
  }
  double f1 = 0.0, f2 = 0.0;
  DiscreteBallForce(b, 0.0, -1.001 * low, 0.0, &fx, &f2);
  DiscreteBallForce(b, 0.0, -0.999 * low, 0.0, &fx, &f1);
  const double k = (f2 - f1) / (0.002 * low);
  EXPECT_NEAR(k / 1.32e8, 1.0, 0.10) << k;
}

TEST(BallBearingTdb, StateSizeAndStaticEquilibriumUnderGravity) {
  for (const bool support : {false, true}) {
    TdbParams p = Tdb(support);
    p.ball_bearing().gravity_y_m_s2 = -9.81;
    const BallBearingTdb tdb(p);
    EXPECT_EQ(tdb.StateSize(), support ? 10 : 6);
    States s{}, rate{};
    tdb.InitialState(s.data());
    TdbForce f;
    tdb.Evaluate({0.0, 0.0, 0.0, 0.0, 0.0}, s.data(), rate.data(), &f);
    for (int i = 0; i < tdb.StateSize(); ++i) EXPECT_NEAR(rate[i], 0.0, 1e-6) << i;
    EXPECT_LT(s[S::kInnerY], support ? s[S::kOuterY] : 0.0);
    const double carried = support ? 0.2 : 0.08;  // the housing carries the races' weight
    EXPECT_NEAR(f.support_force_N(), carried * 9.81, 1e-6);
    EXPECT_EQ(f.normal_force_N, 0.0);
  }
}

// The state storage beyond StateSize() belongs to the next TDB or to nothing: the initial state
// must neither read nor write it (it once read the absent outer-race slots, and runs after the
// first in a process started from whatever the memory held).
TEST(BallBearingTdb, InitialStateUsesOnlyItsOwnStates) {
  for (const bool support : {false, true}) {
    TdbParams p = Tdb(support);
    p.ball_bearing().gravity_y_m_s2 = -9.81;
    const BallBearingTdb tdb(p);
    States clean{}, dirty{};
    dirty.fill(std::numeric_limits<double>::quiet_NaN());
    for (int i = tdb.StateSize(); i < static_cast<int>(dirty.size()); ++i) dirty[i] = 1e17;
    tdb.InitialState(clean.data());
    tdb.InitialState(dirty.data());
    for (int i = 0; i < tdb.StateSize(); ++i)
      EXPECT_EQ(clean[i], dirty[i]) << "support " << support << ", state " << i;
    for (int i = tdb.StateSize(); i < static_cast<int>(dirty.size()); ++i)
      EXPECT_EQ(dirty[i], 1e17) << i;
  }
}

TEST(BallBearingTdb, JournalOnTheRaceByHand) {
  const BallBearingTdb tdb(Tdb());
  States s{}, rate{};
  TdbForce f;
  // 10 um beyond the clearance below the centred race, spinning at 1885 rad/s, race at rest.
  tdb.Evaluate({0.0, -1.1e-4, 0.0, 0.0, 1885.0}, s.data(), rate.data(), &f);
  const double fn = 9055.558153363561;  // Eq. (5), as above
  EXPECT_NEAR(f.normal_force_N, fn, 1e-6);
  EXPECT_NEAR(f.penetration_m, 1e-5, 1e-15);
  // vs = 1885 * 0.0299 > vi = 0: kinetic, mu_d fn on the race along +x (the journal's surface
  // at the bottom moves along +x), against it on the rotor.
  EXPECT_NEAR(f.tangential_force_N, 0.1 * fn, 1e-6);
  EXPECT_NEAR(f.fy_N, fn, 1e-6);
  EXPECT_NEAR(f.fx_N, -0.1 * fn, 1e-6);
  EXPECT_NEAR(f.torque_on_rotor_N_m, -0.1 * fn * 0.0299, 1e-9);
  EXPECT_NEAR(rate[S::kInnerVy], -fn / 0.08, 1e-6);
  EXPECT_NEAR(rate[S::kInnerVx], 0.1 * fn / 0.08, 1e-6);
  EXPECT_NEAR(rate[S::kRaceSpin], 0.1 * fn * 0.03 / 6e-5, 1e-3);  // Ieq w' = Ft Ri
  EXPECT_EQ(f.support_force_N(), 0.0);                            // the balls are not loaded yet
  // The race spinning with the journal: static band, no friction.
  s[S::kRaceSpin] = 1885.0 * 0.0299 / 0.03;
  tdb.Evaluate({0.0, -1.1e-4, 0.0, 0.0, 1885.0}, s.data(), rate.data(), &f);
  EXPECT_NEAR(f.tangential_force_N, 0.0, 1e-6);
  EXPECT_NEAR(rate[S::kCageAngle], s[S::kRaceSpin] * 0.5 * (1.0 - 7.938e-3 / 0.0725), 1e-9);
}

// Chen 2019 (seed 002) Eq. (9)-(10) as printed take the slip from the spins alone; the contact
// point's slip adds the journal's whirl. A journal whirling backwards (along -t) at 0.5 m/s
// while its spin surface moves at only 0.3 m/s over a race at rest tells the two apart.
TEST(BallBearingTdb, SpinOnlySlipFeedsABackwardWhirlThatContactPointSlipBrakes) {
  const double fn = 9055.558153363561;                           // Eq. (5) at 10 um, as above
  const JournalMotion j{0.0, -1.1e-4, -0.5, 0.0, 0.3 / 0.0299};  // t = +x at the bottom
  States s{}, rate{};
  TdbForce f;

  const BallBearingTdb contact_point(Tdb());
  contact_point.Evaluate(j, s.data(), rate.data(), &f);
  // vs - vi = -0.5 + 0.3 = -0.2 m/s: -mu_d fn on the race, +mu_d fn on the rotor along t.
  EXPECT_NEAR(f.tangential_force_N, -0.1 * fn, 1e-6);
  EXPECT_NEAR(f.fx_N, 0.1 * fn, 1e-6);
  EXPECT_LT(f.fx_N * j.vx_m_s, 0.0);  // brakes the whirl
  // The pair dissipates: the friction's power, -Ft (vs - vi), is negative.
  EXPECT_LT(-f.tangential_force_N * (-0.2), 0.0);

  TdbParams literal = Tdb();
  literal.ball_bearing().friction.slip_speeds = SlipSpeeds::kSpinOnly;
  const BallBearingTdb spin_only(literal);
  spin_only.Evaluate(j, s.data(), rate.data(), &f);
  // vs - vi = 0.3 m/s: +mu_d fn on the race, the rotor pushed along -t, with its whirl.
  EXPECT_NEAR(f.tangential_force_N, 0.1 * fn, 1e-6);
  EXPECT_NEAR(f.fx_N, -0.1 * fn, 1e-6);
  EXPECT_GT(f.fx_N * j.vx_m_s, 0.0);  // feeds the whirl
  // ... and the pair's power is positive: the printed law can add energy, the contact point's
  // slip cannot (the energy test below holds for the latter).
  EXPECT_GT(-f.tangential_force_N * (-0.2), 0.0);
  // With the race rolling at the journal's spin surface speed the printed law sees no slip at
  // all, whatever the whirl.
  s[S::kRaceSpin] = 0.3 / 0.03;
  spin_only.Evaluate(j, s.data(), rate.data(), &f);
  EXPECT_NEAR(f.tangential_force_N, 0.0, 1e-9);
  contact_point.Evaluate(j, s.data(), rate.data(), &f);
  EXPECT_NEAR(f.tangential_force_N, -0.1 * fn, 1e-6);
}

TEST(BallBearingTdb, SupportSpringAndDamperCarryTheOuterRace) {
  const BallBearingTdb tdb(Tdb(true));
  States s{}, rate{};
  s[S::kOuterY] = -2e-6;
  s[S::kOuterVy] = -0.01;
  s[S::kInnerY] = -2e-6;  // races together: no ball force
  s[S::kInnerVy] = -0.01;
  TdbForce f;
  tdb.Evaluate({0.0, 0.0, 0.0, 0.0, 0.0}, s.data(), rate.data(), &f);
  const double support = 5e8 * -2e-6 + 27900.0 * -0.01;  // Ks y + Cs y', Fig. 16
  EXPECT_NEAR(rate[S::kOuterVy], -support / 0.12, 1e-6);
  EXPECT_NEAR(f.support_force_N(), -support, 1e-9);
  EXPECT_EQ(rate[S::kInnerVy], 0.0);
}

// ---- Randomised impacts of a spinning point mass (fixed seed), gravity off ----

constexpr int kY = 5 + S::kStatesElasticSupport;  // x, y, vx, vy, spin, TDB states
struct Impact {
  double mass_kg, polar_inertia_kg_m2;
  std::array<double, kY> y;
};

// Elastic energy of Eq. (5): int_0^d F, with s = u^2 so that Simpson sees a smooth integrand.
double LineContactEnergy(const TdbParams& p, double deflection) {
  if (!(deflection > 0.0)) return 0.0;
  const int n = 64;
  const double h = std::sqrt(deflection) / n;
  double sum = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double u = i * h;
    const double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    sum += w * LineContactForce(p.ball_bearing().line_contact, p.clearance_m, u * u) * 2.0 * u;
  }
  return sum * h / 3.0;
}

double Energy(const BallBearingTdb& tdb, const Impact& m) {
  const TdbParams& p = tdb.params();
  const BallBearingTdbParams& b = p.ball_bearing();
  const double* s = m.y.data() + 5;
  auto sq = [](double a, double c) { return a * a + c * c; };
  double e = 0.5 * m.mass_kg * sq(m.y[2], m.y[3]) + 0.5 * m.polar_inertia_kg_m2 * m.y[4] * m.y[4];
  e += 0.5 * p.spin.inertia_kg_m2 * s[S::kRaceSpin] * s[S::kRaceSpin];
  e += 0.5 * b.inner_race_mass_kg * sq(s[S::kInnerVx], s[S::kInnerVy]);
  e += 0.5 * b.support.outer_race_mass_kg * sq(s[S::kOuterVx], s[S::kOuterVy]);
  e += 0.5 * b.support.stiffness_N_per_m * sq(s[S::kOuterX], s[S::kOuterY]);
  // Balls: 2/5 krb delta^(5/2) each (cage fixed in this test).
  const DiscreteBallBearing& bb = tdb.bearing();
  for (int j = 0; j < bb.balls; ++j) {
    const double th = s[S::kCageAngle] + 2.0 * kPi / bb.balls * j;
    const double d = (s[S::kInnerX] - s[S::kOuterX]) * std::cos(th) +
                     (s[S::kInnerY] - s[S::kOuterY]) * std::sin(th) - bb.radial_clearance_m;
    if (d > 0.0) e += 0.4 * bb.ball_stiffness_N_per_m1_5 * d * d * std::sqrt(d);
  }
  const double delta =
      std::sqrt(sq(m.y[0] - s[S::kInnerX], m.y[1] - s[S::kInnerY])) - p.clearance_m;
  return e + LineContactEnergy(p, delta);
}

void Rate(const BallBearingTdb& tdb, const Impact& m, const std::array<double, kY>& y,
          std::array<double, kY>* dy) {
  TdbForce f;
  dy->fill(0.0);
  tdb.Evaluate({y[0], y[1], y[2], y[3], y[4]}, y.data() + 5, dy->data() + 5, &f);
  (*dy)[0] = y[2];
  (*dy)[1] = y[3];
  (*dy)[2] = f.fx_N / m.mass_kg;
  (*dy)[3] = f.fy_N / m.mass_kg;
  (*dy)[4] = f.torque_on_rotor_N_m / m.polar_inertia_kg_m2;
}

void Rk4(const BallBearingTdb& tdb, Impact* m, double h) {
  std::array<double, kY> k1, k2, k3, k4, stage;
  const auto& y = m->y;
  Rate(tdb, *m, y, &k1);
  for (int i = 0; i < kY; ++i) stage[i] = y[i] + 0.5 * h * k1[i];
  Rate(tdb, *m, stage, &k2);
  for (int i = 0; i < kY; ++i) stage[i] = y[i] + 0.5 * h * k2[i];
  Rate(tdb, *m, stage, &k3);
  for (int i = 0; i < kY; ++i) stage[i] = y[i] + h * k3[i];
  Rate(tdb, *m, stage, &k4);
  for (int i = 0; i < kY; ++i) m->y[i] += h / 6.0 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
}

TEST(BallBearingTdbEnergy, DissipativeContactNeverAddsEnergy) {
  std::uint64_t seed = 0x9E3779B97F4A7C15ull;
  auto uniform = [&seed]() {
    seed ^= seed << 13;
    seed ^= seed >> 7;
    seed ^= seed << 17;
    return static_cast<double>(seed >> 11) * 0x1.0p-53;
  };
  for (int trial = 0; trial < 10; ++trial) {
    TdbParams p = Tdb(trial % 2 == 1);
    BallBearingTdbParams& b = p.ball_bearing();
    // The ball set's potential moves with the cage, which the model turns kinematically
    // (no torque from it): hold the cage still so that the energy balance is closed.
    b.bearing.cage_rotation = false;
    b.bearing.balls = 9;
    b.bearing.damping_N_s_per_m = 3000.0 * uniform();
    b.support.damping_N_s_per_m = 3e4 * uniform();
    b.friction.kinetic_coefficient = 0.3 * uniform();
    b.friction.static_coefficient = b.friction.kinetic_coefficient * (1.0 + uniform());
    const BallBearingTdb tdb(p);
    Impact m{5.0 + 30.0 * uniform(), 0.01 + 0.1 * uniform(), {}};
    const double angle = 2.0 * kPi * uniform();
    const double speed = 0.02 + 0.3 * uniform();
    const double tilt = 0.6 * (uniform() - 0.5);
    m.y[0] = 0.999 * p.clearance_m * std::cos(angle);
    m.y[1] = 0.999 * p.clearance_m * std::sin(angle);
    m.y[2] = speed * std::cos(angle + tilt);
    m.y[3] = speed * std::sin(angle + tilt);
    m.y[4] = 2000.0 * uniform();
    const double e0 = Energy(tdb, m);
    double previous = e0;
    bool touched = false;
    for (int i = 0; i < 100000; ++i) {
      Rk4(tdb, &m, 1e-7);
      const double e = Energy(tdb, m);
      ASSERT_LE(e, previous + 1e-9 * e0) << "trial " << trial << " step " << i;
      previous = e;
      const double* s = m.y.data() + 5;
      const double delta = std::hypot(m.y[0] - s[S::kInnerX], m.y[1] - s[S::kInnerY]);
      touched = touched || delta > p.clearance_m;
      if (touched && delta < 0.7 * p.clearance_m) break;  // clear of the race
    }
    ASSERT_TRUE(touched) << "trial " << trial;
    EXPECT_LT(Energy(tdb, m), e0) << "trial " << trial;
  }
}

// ---- The step: no heap, and the same bits twice ----

Impact RunSteps(const BallBearingTdb& tdb, int steps) {
  Impact m{16.0, 0.05, {}};
  tdb.InitialState(m.y.data() + 5);
  m.y[1] = -0.99e-4;
  m.y[2] = 0.03;
  m.y[3] = -0.05;
  m.y[4] = 1885.0;
  for (int i = 0; i < steps; ++i) Rk4(tdb, &m, 2e-7);
  return m;
}

TEST(BallBearingTdbStep, AllocationFreeAndBitIdentical) {
  TdbParams p = Tdb(true);
  p.ball_bearing().gravity_y_m_s2 = -9.81;
  const BallBearingTdb tdb(p);
  Impact a{}, b{};
  {
    testing::MallocGuard guard;
    a = RunSteps(tdb, 5000);
    if (testing::MallocGuard::Available()) {
      EXPECT_EQ(guard.allocations(), 0);
    }
  }
  b = RunSteps(tdb, 5000);
  EXPECT_GT(std::abs(a.y[5 + S::kRaceSpin]), 0.0);  // the contact happened: the race spins
  EXPECT_EQ(std::memcmp(a.y.data(), b.y.data(), sizeof(double) * kY), 0);
}

}  // namespace
}  // namespace ambdrop::ball_bearing_tdb_test
