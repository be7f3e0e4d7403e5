// The generalized Dahl ribbon (Jarroux 2019 Eq. (1)-(3)) under an imposed displacement cycle:
// the force traces the upper envelope hu while loading and the lower hl while unloading, lagging
// each by the envelope slope over beta (the steady solution of de/du = h' - beta e); it never
// leaves the band between them; and each cycle dissipates energy, close to the area between the
// envelopes.
#include <gtest/gtest.h>

#include <cmath>

#include "rt_core/ribbon_dahl.hpp"

namespace ambdrop::dahl_envelope_test {
namespace {

DahlRibbonParams Ribbon() {
  DahlRibbonParams p;
  p.slipping_threshold_N = 400.0;
  p.threshold_scale = 1.0;
  p.slipping_stiffness_N_per_m = 5.13e6;
  p.beta_per_m = 2e5;
  p.upper_hardening_N = 20.0;
  p.upper_hardening_rate_per_m = 2.5e4;
  p.lower_hardening_N = 20.0;
  p.lower_hardening_rate_per_m = 2.5e4;
  return p;
}

// Slopes of the envelopes, Eq. (3) differentiated.
double UpperSlope(const DahlRibbonParams& p, double u) {
  return p.slipping_stiffness_N_per_m + p.upper_hardening_N * p.upper_hardening_rate_per_m *
                                            std::exp(p.upper_hardening_rate_per_m * u);
}
double LowerSlope(const DahlRibbonParams& p, double u) {
  return p.slipping_stiffness_N_per_m + p.lower_hardening_N * p.lower_hardening_rate_per_m *
                                            std::exp(-p.lower_hardening_rate_per_m * u);
}

// |Second derivatives| of the envelopes: the next term of the lag, h''/beta^2.
double UpperCurvature(const DahlRibbonParams& p, double u) {
  const double b = p.upper_hardening_rate_per_m;
  return p.upper_hardening_N * b * b * std::exp(b * u);
}
double LowerCurvature(const DahlRibbonParams& p, double u) {
  const double d = p.lower_hardening_rate_per_m;
  return p.lower_hardening_N * d * d * std::exp(-d * u);
}

struct CycleResult {
  double loop_area_J = 0.0;  ///< integral of f du over the last cycle
  int checked_loading = 0;
  int checked_unloading = 0;
  int outside_band = 0;  ///< samples above hu or below hl
  int off_upper = 0;     ///< loading samples whose gap to hu is not the predicted lag
  int off_lower = 0;     ///< unloading samples whose gap to hl is not the predicted lag
};

// Triangle wave u(t) between -amplitude and +amplitude at `speed`, RK4 on frd.
CycleResult RunCycles(const DahlRibbonParams& p, double amplitude, int cycles) {
  const double speed = 0.01;
  const double dt = 1e-7;
  const double settle = 10.0 / p.beta_per_m;
  const double beta2 = p.beta_per_m * p.beta_per_m;  // travel after a reversal before checking
  double u = 0.0, f = 0.0, direction = 1.0, travel = 0.0;
  const long steps_per_cycle = std::lround(4.0 * amplitude / (speed * dt));
  CycleResult r;
  for (long i = 0; i < cycles * steps_per_cycle; ++i) {
    const double v = direction * speed;
    const auto rate = [&](double uu, double ff) { return DahlRibbonForceRate(p, uu, v, ff); };
    const double k1 = rate(u, f);
    const double k2 = rate(u + 0.5 * dt * v, f + 0.5 * dt * k1);
    const double k3 = rate(u + 0.5 * dt * v, f + 0.5 * dt * k2);
    const double k4 = rate(u + dt * v, f + dt * k3);
    const double f_next = f + dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    if (i >= (cycles - 1) * steps_per_cycle) r.loop_area_J += 0.5 * (f + f_next) * v * dt;
    f = f_next;
    u += v * dt;
    travel += speed * dt;
    // Never outside the band between the envelopes (a little slack for the start at f = 0).
    if (f > DahlUpperEnvelope(p, u) + 1e-6 || f < DahlLowerEnvelope(p, u) - 1e-6) {
      ++r.outside_band;
    }
    if (travel > settle && i > steps_per_cycle) {
      if (direction > 0) {
        // Loading: on hu, behind it by hu'/beta (to first order).
        const double gap = DahlUpperEnvelope(p, u) - f;
        const double lag = UpperSlope(p, u) / p.beta_per_m;
        if (std::abs(gap - lag) > 0.02 * lag + 2.0 * UpperCurvature(p, u) / beta2) ++r.off_upper;
        ++r.checked_loading;
      } else {
        const double gap = f - DahlLowerEnvelope(p, u);
        const double lag = LowerSlope(p, u) / p.beta_per_m;
        if (std::abs(gap - lag) > 0.02 * lag + 2.0 * LowerCurvature(p, u) / beta2) ++r.off_lower;
        ++r.checked_unloading;
      }
    }
    if (direction * u >= amplitude - 1e-15) {
      direction = -direction;
      travel = 0.0;
    }
  }
  return r;
}

TEST(DahlRibbon, TracesUpperEnvelopeLoadingAndLowerUnloading) {
  const DahlRibbonParams p = Ribbon();
  const CycleResult r = RunCycles(p, 1.2e-4, 3);
  EXPECT_EQ(r.outside_band, 0);
  EXPECT_EQ(r.off_upper, 0);
  EXPECT_EQ(r.off_lower, 0);
  EXPECT_GT(r.checked_loading, 1000);
  EXPECT_GT(r.checked_unloading, 1000);
}

TEST(DahlRibbon, EachCycleDissipatesAboutTheAreaBetweenTheEnvelopes) {
  const DahlRibbonParams p = Ribbon();
  const double a = 1.2e-4;
  const CycleResult r = RunCycles(p, a, 2);
  EXPECT_EQ(r.outside_band, 0);
  // Area between hu and hl over [-a, a], Eq. (3) integrated by hand.
  const double mu_fn = DahlSlippingThreshold(p);
  const double b = p.upper_hardening_rate_per_m, d = p.lower_hardening_rate_per_m;
  const double envelope_area = 2.0 * mu_fn * 2.0 * a +
                               p.upper_hardening_N / b * (std::exp(b * a) - std::exp(-b * a)) +
                               p.lower_hardening_N / d * (std::exp(d * a) - std::exp(-d * a));
  EXPECT_GT(r.loop_area_J, 0.0);  // energy leaves the mechanism every cycle
  EXPECT_LT(r.loop_area_J, envelope_area);
  EXPECT_GT(r.loop_area_J, 0.85 * envelope_area);
}

TEST(DahlRibbon, SmallerThresholdDissipatesLess) {
  DahlRibbonParams p = Ribbon();
  const double full = RunCycles(p, 1.2e-4, 2).loop_area_J;
  p.threshold_scale = 1.0 / 30.0;  // the paper's DE cut
  const double cut = RunCycles(p, 1.2e-4, 2).loop_area_J;
  EXPECT_GT(cut, 0.0);
  EXPECT_LT(cut, 0.5 * full);
}

}  // namespace
}  // namespace ambdrop::dahl_envelope_test
