// The contact-law TDB's ribbons in series (ContactLawTdb, contact_law.ribbon = "dahl" or
// "cross_coupled"): a massless race between the bearing (kbrg, cbrg) and the ribbon, Dahl
// (Jarroux 2019 Eq. (1)-(3)) or cross-coupled (Jarroux 2016 (seed 001) Eq. (1)); their config
// keys; and the whirl damping on every ribbon.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/config/config_loader.hpp"
#include "malloc_guard.hpp"
#include "rt_core/contact_law_tdb.hpp"
#include "rt_core/ribbon_dahl.hpp"
#include "test_configs.hpp"

namespace ambdrop::contact_law_ribbon_test {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

constexpr double kClearance = 0.2e-3;

TdbParams Series(ContactLawRibbon ribbon) {
  TdbParams p;
  p.name = std::string(1, 't');  // not = "t": GCC 12 warns falsely (-Wrestrict, PR 105329)
  p.journal_radius_m = 0.05;
  p.clearance_m = kClearance;
  ContactLawParams& c = p.contact_law();
  c.bearing_stiffness_N_per_m = 2e7;
  c.bearing_damping_N_s_per_m = 2e3;
  c.ribbon_damping_N_s_per_m = 7e3;
  c.ribbon = ribbon;
  c.dahl = {100.0, 1.0, 5e6, 1e7, 20.0, 2e4, 20.0, 2e4};
  c.cross_coupled = {5e6, 0.5, 2e3, 1e4};
  p.friction.law = FrictionLaw::kNone;
  p.friction.whirl_damping_N_s_per_m = 0.0;
  return p;
}

// Advances the TDB's states by explicit Euler under a prescribed journal motion; returns the
// last evaluation's forces.
template <class Journal>
TdbForce Advance(const ContactLawTdb& tdb, std::vector<double>* state, double t0, double t1,
                 double dt, Journal journal, double* work_J = nullptr) {
  std::vector<double> rate(state->size());
  TdbForce f;
  const int steps = static_cast<int>(std::lround((t1 - t0) / dt));
  for (int i = 0; i < steps; ++i) {
    const JournalMotion j = journal(t0 + i * dt);
    tdb.Evaluate(j, state->data(), rate.data(), &f);
    // Work the journal does on the TDB: minus the force on the rotor along its velocity.
    if (work_J != nullptr) *work_J -= (f.fx_N * j.vx_m_s + f.fy_N * j.vy_m_s) * dt;
    for (std::size_t k = 0; k < state->size(); ++k) (*state)[k] += dt * rate[k];
  }
  return f;
}

TEST(ContactLawRibbon, StateSizePerRibbon) {
  EXPECT_EQ(ContactLawTdb(Series(ContactLawRibbon::kBilinear)).StateSize(), 1);
  EXPECT_EQ(ContactLawTdb(Series(ContactLawRibbon::kCrossCoupled)).StateSize(), 3);
  EXPECT_EQ(ContactLawTdb(Series(ContactLawRibbon::kDahl)).StateSize(), 5);
  TdbParams p = Series(ContactLawRibbon::kDahl);
  p.contact_law().ribbon_damping_N_s_per_m = 0.0;  // a massless race needs it
  EXPECT_THROW(ContactLawTdb{p}, std::invalid_argument);
}

// A journal held d into the clearance settles where the bearing and the Dahl ribbon carry the
// same force: kbrg (d - u) = hu(u), the loading envelope (Jarroux 2019 Eq. (3)), i.e. the two
// compliances in series; the Dahl force trails hu by about hu'/beta on a loading path.
TEST(ContactLawRibbon, DahlStaticLoadSettlesAtTheSeriesDeflection) {
  const TdbParams p = Series(ContactLawRibbon::kDahl);
  const ContactLawTdb tdb(p);
  const DahlRibbonParams& dahl = p.contact_law().dahl;
  const double kb = p.contact_law().bearing_stiffness_N_per_m;
  const double d = 60e-6;
  std::vector<double> state(tdb.StateSize());
  tdb.InitialState(state.data());
  const TdbForce f = Advance(tdb, &state, 0.0, 0.03, 5e-7, [&](double) {
    return JournalMotion{0.0, -(kClearance + d), 0.0, 0.0, 0.0};
  });
  // kbrg (d - u) = hu(u) by bisection: the left side falls, the right side rises with u.
  double lo = 0.0, hi = d;
  for (int i = 0; i < 200; ++i) {
    const double u = 0.5 * (lo + hi);
    (kb * (d - u) > DahlUpperEnvelope(dahl, u) ? lo : hi) = u;
  }
  const double u_star = 0.5 * (lo + hi);
  const double slope =
      dahl.slipping_stiffness_N_per_m + dahl.upper_hardening_N * dahl.upper_hardening_rate_per_m *
                                            std::exp(dahl.upper_hardening_rate_per_m * u_star);
  const double tolerance = 3.0 * slope / (dahl.beta_per_m * (kb + slope));
  const double u = -state[ContactLawTdb::kRibbonY];  // the ribbon deflects downwards
  EXPECT_NEAR(u, u_star, tolerance);
  EXPECT_GT(u_star, 10.0 * tolerance);
  EXPECT_NEAR(state[ContactLawTdb::kRibbonX], 0.0, 1e-15);
  // The rotor, the race and the housing carry the same force (the race is massless).
  EXPECT_NEAR(f.normal_force_N, kb * (d - u), 1e-6 * f.normal_force_N);
  EXPECT_NEAR(f.fy_N, f.normal_force_N, 1e-9 * f.normal_force_N);
  EXPECT_NEAR(f.support_y_N, -f.fy_N, 1e-6 * f.normal_force_N);
  EXPECT_NEAR(-state[ContactLawTdb::kRibbonFy], f.normal_force_N, 1e-6 * f.normal_force_N);
}

// A slow load/unload cycle: the Dahl ribbon's loop between its envelopes, 2 muFN apart without
// hardening (Jarroux 2019 Eq. (3)), takes about 2 muFN times the ribbon's travel per cycle, and
// the cycle never returns energy.
TEST(ContactLawRibbon, DahlLoadUnloadCycleDissipates) {
  TdbParams p = Series(ContactLawRibbon::kDahl);
  p.contact_law().dahl.upper_hardening_N = 0.0;
  p.contact_law().dahl.lower_hardening_N = 0.0;
  const ContactLawTdb tdb(p);
  const double period = 0.5, d_max = 80e-6, w = 2.0 * std::numbers::pi / period;
  const auto journal = [&](double t) {
    const double d = 0.5 * d_max * (1.0 - std::cos(w * t));
    return JournalMotion{0.0, -(kClearance + d), 0.0, -0.5 * d_max * w * std::sin(w * t), 0.0};
  };
  std::vector<double> state(tdb.StateSize());
  tdb.InitialState(state.data());
  Advance(tdb, &state, 0.0, period, 5e-7, journal);  // the first cycle leaves the ribbon set
  double work = 0.0, u_min = 1.0, u_max = -1.0;
  for (int slice = 0; slice < 40; ++slice) {
    const double t0 = period * (1.0 + slice / 40.0);
    Advance(tdb, &state, t0, t0 + period / 40.0, 5e-7, journal, &work);
    u_min = std::min(u_min, -state[ContactLawTdb::kRibbonY]);
    u_max = std::max(u_max, -state[ContactLawTdb::kRibbonY]);
  }
  const double loop = 2.0 * DahlSlippingThreshold(p.contact_law().dahl) * (u_max - u_min);
  EXPECT_GT(u_max - u_min, 20e-6);
  EXPECT_GT(work, 0.9 * loop);
  EXPECT_LT(work, 1.15 * loop);  // the loop plus the slow cycle's viscous losses
}

// Mean tangential force on the rotor along its own whirl, for a journal whirling in contact at
// w (rad/s, > 0 along +spin), friction off.
double MeanWhirlForce(double eta, double w) {
  TdbParams p = Series(ContactLawRibbon::kCrossCoupled);
  p.contact_law().cross_coupled.cross_coupling = eta;
  const ContactLawTdb tdb(p);
  const double r = kClearance + 30e-6;
  const auto journal = [&](double t) {
    const double c = std::cos(w * t), s = std::sin(w * t);
    return JournalMotion{r * c, r * s, -r * w * s, r * w * c, 0.0};
  };
  std::vector<double> state(tdb.StateSize());
  tdb.InitialState(state.data());
  const double period = 2.0 * std::numbers::pi / std::abs(w), dt = 1e-6;
  Advance(tdb, &state, 0.0, 2.0 * period, dt, journal);
  std::vector<double> rate(state.size());
  double sum = 0.0;
  const int steps = static_cast<int>(period / dt);
  for (int i = 0; i < steps; ++i) {
    const double t = 2.0 * period + i * dt;
    const JournalMotion j = journal(t);
    TdbForce f;
    tdb.Evaluate(j, state.data(), rate.data(), &f);
    sum += (f.fx_N * j.vx_m_s + f.fy_N * j.vy_m_s) / (r * std::abs(w));
    for (std::size_t k = 0; k < state.size(); ++k) state[k] += dt * rate[k];
  }
  return sum / steps;
}

// Jarroux 2016 (seed 001) Eq. (1): the cross-coupled stiffness acts against the race's whirl,
// so through the massless race it opposes the rotor's whirl, in either direction, beyond what
// the ribbon's damping alone does.
TEST(ContactLawRibbon, CrossCoupledRibbonOpposesTheWhirl) {
  for (double w : {100.0, -100.0}) {
    const double damped_only = MeanWhirlForce(0.0, w);
    const double cross_coupled = MeanWhirlForce(0.5, w);
    EXPECT_LT(damped_only, 0.0) << w;
    EXPECT_LT(cross_coupled, 5.0 * damped_only) << w;
  }
}

// Jarroux 2019 Sec. 4.2: the viscous force on the whirl speed, with the bilinear law and with
// each ribbon in series.
TEST(ContactLawRibbon, WhirlDampingOnEveryRibbon) {
  for (ContactLawRibbon ribbon :
       {ContactLawRibbon::kBilinear, ContactLawRibbon::kDahl, ContactLawRibbon::kCrossCoupled}) {
    TdbParams p = Series(ribbon);
    p.contact_law().ribbon_stiffness_N_per_m = 5e6;
    p.contact_law().ribbon_crushing_m = 0.1e-3;
    p.friction.whirl_damping_N_s_per_m = 500.0;
    const ContactLawTdb tdb(p);
    std::vector<double> state(tdb.StateSize()), rate(tdb.StateSize());
    tdb.InitialState(state.data());
    TdbForce f;
    // At the bottom, 20 um in, whirling along +x (t = (-ny, nx) = (1, 0)) at 0.1 m/s.
    tdb.Evaluate({0.0, -(kClearance + 20e-6), 0.1, 0.0, 0.0}, state.data(), rate.data(), &f);
    ASSERT_GT(f.normal_force_N, 0.0);
    EXPECT_NEAR(f.fx_N, -500.0 * 0.1, 1e-9) << static_cast<int>(ribbon);
  }
}

const TdbParams& Nde(const ModelParams& params) {
  for (const TdbParams& t : params.tdbs) {
    if (t.name == "nde") return t;
  }
  throw std::out_of_range("no TDB nde");
}

// The step stays allocation-free and deterministic with either ribbon in series.
TEST(ContactLawRibbon, StepAllocationFreeAndBitIdentical) {
  for (ContactLawRibbon ribbon : {ContactLawRibbon::kDahl, ContactLawRibbon::kCrossCoupled}) {
    TdbParams p = Series(ribbon);
    p.friction.law = FrictionLaw::kRegularisedCoulomb;
    p.friction.whirl_damping_N_s_per_m = 500.0;
    const ContactLawTdb tdb(p);
    const auto journal = [](double t) {
      const double r = kClearance + 30e-6, w = 300.0;
      return JournalMotion{r * std::cos(w * t), r * std::sin(w * t), -r * w * std::sin(w * t),
                           r * w * std::cos(w * t), 600.0};
    };
    std::vector<double> a(tdb.StateSize()), b(tdb.StateSize());
    tdb.InitialState(a.data());
    tdb.InitialState(b.data());
    std::vector<double> rate(a.size());
    {
      testing::MallocGuard guard;
      TdbForce f;
      for (int i = 0; i < 5000; ++i) {
        tdb.Evaluate(journal(i * 1e-6), a.data(), rate.data(), &f);
        for (std::size_t k = 0; k < a.size(); ++k) a[k] += 1e-6 * rate[k];
      }
      if (testing::MallocGuard::Available()) {
        EXPECT_EQ(guard.allocations(), 0);
      }
    }
    Advance(tdb, &b, 0.0, 5000 * 1e-6, 1e-6, journal);
    EXPECT_GT(std::abs(a[ContactLawTdb::kRaceSpin]), 0.0);  // the contact happened
    EXPECT_EQ(std::memcmp(a.data(), b.data(), sizeof(double) * a.size()), 0);
  }
}

std::string ErrorOf(const std::vector<std::string>& overrides) {
  try {
    LoadConfig(testing::ConfigPath("jarroux2019_industrial.toml"), overrides);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

const std::vector<std::string> kDahlKeys = {
    "tdb.nde.contact_law.ribbon=\"dahl\"",
    "tdb.nde.contact_law.dahl.slipping_threshold_N=100",
    "tdb.nde.contact_law.dahl.slipping_stiffness_N_per_m=5e6",
    "tdb.nde.contact_law.dahl.beta_per_m=1e7",
    "tdb.nde.contact_law.dahl.upper_hardening_N=20",
    "tdb.nde.contact_law.dahl.upper_hardening_rate_per_m=2e4",
    "tdb.nde.contact_law.dahl.lower_hardening_N=20",
    "tdb.nde.contact_law.dahl.lower_hardening_rate_per_m=2e4"};

TEST(ConfigContactLawRibbon, BilinearByDefaultAndTheSwitchReadsItsTable) {
  const ModelParams shipped = testing::LoadTestConfig("jarroux2019_industrial.toml");
  EXPECT_EQ(Nde(shipped).contact_law().ribbon, ContactLawRibbon::kBilinear);
  const ContactLawParams dahl =
      Nde(testing::LoadTestConfig("jarroux2019_industrial.toml", kDahlKeys)).contact_law();
  EXPECT_EQ(dahl.ribbon, ContactLawRibbon::kDahl);
  EXPECT_EQ(dahl.dahl.beta_per_m, 1e7);
  EXPECT_EQ(dahl.dahl.threshold_scale, 1.0);
  EXPECT_EQ(dahl.ribbon_damping_N_s_per_m, 7e3);  // ceq, beside the Dahl element
  const ContactLawParams cc =
      Nde(testing::LoadTestConfig("jarroux2019_industrial.toml",
                                  {"tdb.nde.contact_law.ribbon=\"cross_coupled\"",
                                   "tdb.nde.contact_law.cross_coupled.stiffness_N_per_m=5e6",
                                   "tdb.nde.contact_law.cross_coupled.cross_coupling=0.3",
                                   "tdb.nde.contact_law.cross_coupled.damping_N_s_per_m=2e3"}))
          .contact_law();
  EXPECT_EQ(cc.ribbon, ContactLawRibbon::kCrossCoupled);
  EXPECT_EQ(cc.cross_coupled.cross_coupling, 0.3);
  EXPECT_EQ(cc.cross_coupled.sign_regularisation_s_per_m, 100.0);
}

TEST(ConfigContactLawRibbon, ErrorsNameKeyAndWhy) {
  EXPECT_THAT(ErrorOf({"tdb.nde.contact_law.ribbon=\"dahl\""}),
              HasSubstr("missing key 'tdb.nde.contact_law.dahl'"));
  EXPECT_THAT(ErrorOf({"tdb.nde.contact_law.ribbon=\"kelvin_voigt\""}),
              HasSubstr("tdb.nde.contact_law.ribbon"));
  std::vector<std::string> no_damping = kDahlKeys;
  no_damping.push_back("tdb.nde.contact_law.ribbon_damping_N_s_per_m=0");
  EXPECT_THAT(ErrorOf(no_damping),
              AllOf(HasSubstr("key 'tdb.nde.contact_law.ribbon_damping_N_s_per_m'"),
                    HasSubstr("massless")));
  EXPECT_THAT(ErrorOf({"tdb.nde.contact_law.ribbon=\"cross_coupled\"",
                       "tdb.nde.contact_law.cross_coupled.stiffness_N_per_m=5e6",
                       "tdb.nde.contact_law.cross_coupled.cross_coupling=0.3",
                       "tdb.nde.contact_law.cross_coupled.damping_N_s_per_m=0"}),
              AllOf(HasSubstr("key 'tdb.nde.contact_law.cross_coupled.damping_N_s_per_m'"),
                    HasSubstr("massless")));
  std::vector<std::string> bad_dahl = kDahlKeys;
  bad_dahl.push_back("tdb.nde.contact_law.dahl.beta=1");
  EXPECT_THAT(ErrorOf(bad_dahl), HasSubstr("unknown key 'tdb.nde.contact_law.dahl.beta'"));
}

// contact_law.outer_race_mass_kg (contact_law_race_mass_test.cpp): read with gravity, the
// ribbon's damping then allowed 0.
TEST(ConfigContactLawRaceMass, ReadWithGravityAndItsDampingMayBeZero) {
  std::vector<std::string> keys = kDahlKeys;
  keys.push_back("tdb.nde.contact_law.outer_race_mass_kg=0.3");
  keys.push_back("tdb.nde.contact_law.ribbon_damping_N_s_per_m=0");
  const ModelParams params = testing::LoadTestConfig("jarroux2019_industrial.toml", keys);
  const ContactLawParams& c = Nde(params).contact_law();
  EXPECT_EQ(c.outer_race_mass_kg, 0.3);
  EXPECT_EQ(c.ribbon_damping_N_s_per_m, 0.0);
  EXPECT_LT(c.gravity_y_m_s2, -9.0);
  EXPECT_EQ(
      Nde(testing::LoadTestConfig("jarroux2019_industrial.toml")).contact_law().outer_race_mass_kg,
      0.0);
  // With the bilinear law it is kept for a switch of the ribbon and does not enter the law.
  const ContactLawParams bilinear =
      Nde(testing::LoadTestConfig("jarroux2019_industrial.toml",
                                  {"tdb.nde.contact_law.outer_race_mass_kg=0.3"}))
          .contact_law();
  EXPECT_EQ(bilinear.outer_race_mass_kg, 0.3);
  EXPECT_EQ(bilinear.ribbon, ContactLawRibbon::kBilinear);
  keys.back() = "tdb.nde.contact_law.outer_race_mass_kg=-1";
  EXPECT_THAT(ErrorOf(keys), HasSubstr("key 'tdb.nde.contact_law.outer_race_mass_kg'"));
}

}  // namespace
}  // namespace ambdrop::contact_law_ribbon_test
