// The contact-law TDB's race with mass between the bearing and a ribbon in series
// (contact_law.outer_race_mass_kg, ContactLawTdb): Newton on the race (Jarroux 2019 Sec. 4.1,
// model #3's outer race) against closed-form limits: its free vibration on the ribbon, an
// elastic strike by a journal that does not yield, the static balance a massless race reaches,
// and its weight carried from the first step. Its config key: contact_law_ribbon_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "malloc_guard.hpp"
#include "rt_core/contact_law_tdb.hpp"
#include "rt_core/ribbon_dahl.hpp"

namespace ambdrop::contact_law_race_mass_test {
namespace {

constexpr double kClearance = 0.2e-3;
constexpr double kMass = 0.3;  // kg, a bearing housing's

TdbParams WithMass(ContactLawRibbon ribbon, double mass_kg) {
  TdbParams p;
  p.name = std::string(1, 't');  // not = "t": GCC 12 warns falsely (-Wrestrict, PR 105329)
  p.journal_radius_m = 0.05;
  p.clearance_m = kClearance;
  ContactLawParams& c = p.contact_law();
  c.bearing_stiffness_N_per_m = 2e7;
  c.bearing_damping_N_s_per_m = 0.0;
  c.ribbon_damping_N_s_per_m = 0.0;
  c.ribbon = ribbon;
  c.dahl = {100.0, 1.0, 5e6, 1e7, 20.0, 2e4, 20.0, 2e4};
  c.cross_coupled = {5e6, 0.0, 0.0, 1e4};
  c.outer_race_mass_kg = mass_kg;
  p.friction.law = FrictionLaw::kNone;
  p.friction.whirl_damping_N_s_per_m = 0.0;
  return p;
}

// Classical fourth-order Runge-Kutta on the TDB's states under a prescribed journal motion; the
// race's oscillations on the stiff bearing need more than Euler to keep their energy.
template <class Journal>
void Rk4(const ContactLawTdb& tdb, std::vector<double>* y, double t, double dt, Journal journal) {
  const std::size_t n = y->size();
  std::vector<double> k1(n), k2(n), k3(n), k4(n), tmp(n);
  TdbForce f;
  tdb.Evaluate(journal(t), y->data(), k1.data(), &f);
  for (std::size_t i = 0; i < n; ++i) tmp[i] = (*y)[i] + 0.5 * dt * k1[i];
  tdb.Evaluate(journal(t + 0.5 * dt), tmp.data(), k2.data(), &f);
  for (std::size_t i = 0; i < n; ++i) tmp[i] = (*y)[i] + 0.5 * dt * k2[i];
  tdb.Evaluate(journal(t + 0.5 * dt), tmp.data(), k3.data(), &f);
  for (std::size_t i = 0; i < n; ++i) tmp[i] = (*y)[i] + dt * k3[i];
  tdb.Evaluate(journal(t + dt), tmp.data(), k4.data(), &f);
  for (std::size_t i = 0; i < n; ++i) {
    (*y)[i] += dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
  }
}

JournalMotion Centred(double) {
  return JournalMotion{0.0, 0.0, 0.0, 0.0, 0.0};
}

TEST(ContactLawRaceMass, TwoStatesMoreAndTheMasslessRaceUnchanged) {
  EXPECT_EQ(ContactLawTdb(WithMass(ContactLawRibbon::kCrossCoupled, kMass)).StateSize(), 5);
  EXPECT_EQ(ContactLawTdb(WithMass(ContactLawRibbon::kDahl, kMass)).StateSize(), 7);
  EXPECT_EQ(ContactLawTdb(WithMass(ContactLawRibbon::kDahl, kMass)).RaceVelocityIndex(), 5);
  // The bilinear law has no race in series: the mass does not enter it.
  EXPECT_EQ(ContactLawTdb(WithMass(ContactLawRibbon::kBilinear, kMass)).StateSize(), 1);
  // A race with mass needs no ribbon damping; a massless one does.
  EXPECT_THROW(ContactLawTdb(WithMass(ContactLawRibbon::kDahl, 0.0)), std::invalid_argument);
}

// Off the journal, the race on the cross-coupled ribbon without cross-coupling or damping is a
// mass on a spring: it swings at sqrt(kcrd / m) (Jarroux 2016 (seed 001) Eq. (1), eta = 0).
TEST(ContactLawRaceMass, SwingsOnItsRibbonAtTheSpringMassFrequency) {
  const TdbParams p = WithMass(ContactLawRibbon::kCrossCoupled, kMass);
  const ContactLawTdb tdb(p);
  std::vector<double> y(tdb.StateSize(), 0.0);
  const double u0 = 20e-6;
  y[ContactLawTdb::kRibbonX] = u0;
  const double w = std::sqrt(p.contact_law().cross_coupled.stiffness_N_per_m / kMass);
  const double period = 2.0 * std::numbers::pi / w;
  const double dt = period / 2000.0;
  // Upward crossings of u = 0 give the period; the amplitude stays (no damping).
  std::vector<double> crossings;
  double previous = u0, peak = 0.0;
  for (int i = 0; i < 2000 * 5; ++i) {
    Rk4(tdb, &y, i * dt, dt, Centred);
    const double u = y[ContactLawTdb::kRibbonX];
    if (previous < 0.0 && u >= 0.0) {
      crossings.push_back((i + previous / (previous - u)) * dt);  // linear between the steps
    }
    peak = std::max(peak, std::abs(u));
    previous = u;
  }
  ASSERT_GE(crossings.size(), 4u);
  const double measured = (crossings.back() - crossings.front()) / (crossings.size() - 1);
  EXPECT_NEAR(measured, period, 1e-4 * period);
  EXPECT_NEAR(peak, u0, 1e-4 * u0);
  EXPECT_EQ(y[ContactLawTdb::kRibbonY], 0.0);  // no cross-coupling: x alone
}

// A journal that does not yield (prescribed motion) strikes the resting race at v through an
// elastic contact (cbrg = 0, no friction): the race leaves at 2v, as off an infinitely heavy
// body, after half a period of the bearing's sqrt(kbrg / m). The ribbon is soft enough not to
// matter within the strike.
TEST(ContactLawRaceMass, AnElasticStrikeByAnUnyieldingJournalSendsItOffAtTwiceItsSpeed) {
  TdbParams p = WithMass(ContactLawRibbon::kCrossCoupled, kMass);
  p.contact_law().cross_coupled.stiffness_N_per_m = 1.0;  // N/m: keeps it centred, no more
  const ContactLawTdb tdb(p);
  const double v = 0.05;                  // m/s, along -y
  const double gap = 5e-6;                // from the journal's start to the contact
  const double y0 = -(kClearance - gap);  // journal centre at the start
  const auto journal = [&](double t) { return JournalMotion{0.0, y0 - v * t, 0.0, -v, 0.0}; };
  std::vector<double> y(tdb.StateSize(), 0.0);
  const double contact_time =
      std::numbers::pi * std::sqrt(kMass / p.contact_law().bearing_stiffness_N_per_m);
  const double dt = contact_time / 4000.0;
  double contact_start = -1.0, contact_end = -1.0;
  TdbForce f;
  std::vector<double> rate(y.size());
  for (int i = 0; i < 4000 * 4; ++i) {
    const double t = i * dt;
    tdb.Evaluate(journal(t), y.data(), rate.data(), &f);
    if (f.normal_force_N > 0.0 && contact_start < 0.0) contact_start = t;
    if (f.normal_force_N == 0.0 && contact_start >= 0.0 && contact_end < 0.0) contact_end = t;
    Rk4(tdb, &y, t, dt, journal);
  }
  ASSERT_GT(contact_end, contact_start);
  const double vy = y[tdb.RaceVelocityIndex() + 1];
  EXPECT_NEAR(vy, -2.0 * v, 2e-3 * v);
  EXPECT_NEAR(contact_end - contact_start, contact_time, 2e-3 * contact_time);
}

// Held at a fixed penetration with the ribbon's damping on, the race with mass settles at the
// static balance a massless race would reach under the journal's force and its weight,
// kbrg (d - u) + m g = hu(u) on the Dahl loading envelope: mass changes the way there, not the
// balance; the housing carries the contact's force and the weight.
TEST(ContactLawRaceMass, SettlesUnderAStaticLoadWhereTheMasslessRaceDoes) {
  const double d = 60e-6;
  const auto held = [&](double) { return JournalMotion{0.0, -(kClearance + d), 0.0, 0.0, 0.0}; };
  TdbParams massless = WithMass(ContactLawRibbon::kDahl, 0.0);
  massless.contact_law().ribbon_damping_N_s_per_m = 7e3;
  massless.contact_law().bearing_damping_N_s_per_m = 2e3;
  TdbParams heavy = massless;
  heavy.contact_law().outer_race_mass_kg = kMass;
  heavy.contact_law().gravity_y_m_s2 = -9.81;
  const ContactLawTdb a(massless), b(heavy);
  std::vector<double> ya(a.StateSize()), yb(b.StateSize());
  a.InitialState(ya.data());
  b.InitialState(yb.data());
  const double dt = 2e-7;
  for (int i = 0; i < 150000; ++i) {
    Rk4(a, &ya, i * dt, dt, held);
    Rk4(b, &yb, i * dt, dt, held);
  }
  TdbForce fa, fb;
  std::vector<double> rate(yb.size());
  a.Evaluate(held(0.0), ya.data(), rate.data(), &fa);
  b.Evaluate(held(0.0), yb.data(), rate.data(), &fb);
  const double weight = kMass * 9.81;
  // Jarroux 2019 Eq. (3), loading envelope, by bisection as in contact_law_ribbon_test.
  const DahlRibbonParams& dahl = heavy.contact_law().dahl;
  const double kb = heavy.contact_law().bearing_stiffness_N_per_m;
  double lo = 0.0, hi = d;
  for (int i = 0; i < 200; ++i) {
    const double u = 0.5 * (lo + hi);
    (kb * (d - u) + weight > DahlUpperEnvelope(dahl, u) ? lo : hi) = u;
  }
  const double slope = dahl.slipping_stiffness_N_per_m;
  const double trail = 3.0 * slope / (dahl.beta_per_m * (kb + slope));  // the Dahl lag, as there
  EXPECT_NEAR(-yb[ContactLawTdb::kRibbonY], 0.5 * (lo + hi), trail);
  EXPECT_LT(std::abs(yb[b.RaceVelocityIndex() + 1]), 1e-9);  // at rest
  // The housing carries the contact's force and the race's weight.
  EXPECT_NEAR(fb.support_y_N, -fb.fy_N - weight, 1e-6 * fb.normal_force_N);
  EXPECT_NEAR(fa.support_y_N, -fa.fy_N, 1e-6 * fa.normal_force_N);
}

// Its weight rests on the ribbon from the first step: off the journal every rate is zero.
TEST(ContactLawRaceMass, StartsAtRestWithItsWeightOnTheRibbon) {
  for (ContactLawRibbon ribbon : {ContactLawRibbon::kDahl, ContactLawRibbon::kCrossCoupled}) {
    TdbParams p = WithMass(ribbon, kMass);
    p.contact_law().gravity_y_m_s2 = -9.81;
    const ContactLawTdb tdb(p);
    std::vector<double> y(tdb.StateSize()), rate(tdb.StateSize(), 1.0);
    tdb.InitialState(y.data());
    TdbForce f;
    tdb.Evaluate(Centred(0.0), y.data(), rate.data(), &f);
    for (double r : rate) EXPECT_NEAR(r, 0.0, 1e-12);  // m g / m - g rounds
    EXPECT_NEAR(f.support_y_N, -kMass * 9.81, 1e-12);
    EXPECT_LT(y[ContactLawTdb::kRibbonY], kClearance);  // a sag, not a contact
  }
}

TEST(ContactLawRaceMass, StepAllocationFreeAndBitIdentical) {
  TdbParams p = WithMass(ContactLawRibbon::kDahl, kMass);
  p.friction.law = FrictionLaw::kRegularisedCoulomb;
  p.contact_law().gravity_y_m_s2 = -9.81;
  p.contact_law().bearing_damping_N_s_per_m = 2e3;
  const ContactLawTdb tdb(p);
  const auto journal = [](double t) {
    const double r = kClearance + 30e-6, w = 300.0;
    return JournalMotion{r * std::cos(w * t), r * std::sin(w * t), -r * w * std::sin(w * t),
                         r * w * std::cos(w * t), 600.0};
  };
  std::vector<double> a(tdb.StateSize()), b(tdb.StateSize()), rate(tdb.StateSize());
  tdb.InitialState(a.data());
  tdb.InitialState(b.data());
  for (std::vector<double>* y : {&a, &b}) {
    testing::MallocGuard guard;
    TdbForce f;
    for (int i = 0; i < 5000; ++i) {
      tdb.Evaluate(journal(i * 1e-7), y->data(), rate.data(), &f);
      for (std::size_t k = 0; k < y->size(); ++k) (*y)[k] += 1e-7 * rate[k];
    }
    if (testing::MallocGuard::Available()) {
      EXPECT_EQ(guard.allocations(), 0);
    }
  }
  EXPECT_GT(std::abs(a[ContactLawTdb::kRaceSpin]), 0.0);  // the contact happened
  EXPECT_EQ(std::memcmp(a.data(), b.data(), sizeof(double) * a.size()), 0);
}

}  // namespace
}  // namespace ambdrop::contact_law_race_mass_test
