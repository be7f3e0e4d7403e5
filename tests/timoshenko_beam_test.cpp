// Free-free Timoshenko beam: the FE model's bending frequencies converge to the analytical
// Timoshenko values (a 4 x 4 frequency determinant solved by bisection) as the mesh is refined.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <numbers>
#include <vector>

#include "rt_core/fe_rotor.hpp"
#include "rt_core/natural_frequencies.hpp"
#include "rt_core/timoshenko_element.hpp"

namespace ambdrop::timoshenko_beam_test {
namespace {

struct Beam {
  double length_m, diameter_m, E, G, rho;
  double area() const { return std::numbers::pi / 4 * diameter_m * diameter_m; }
  double inertia() const { return std::numbers::pi / 64 * std::pow(diameter_m, 4); }
  double kappa() const { return HollowCircleShearCoefficient(E / (2 * G) - 1, 0.0); }
};

// Timoshenko free-free frequency determinant. With w = A1 ch(az) + A2 sh(az) + A3 cos(bz) +
// A4 sin(bz), the section rotation is psi = ga (A1 sh + A2 ch) + gb (A3 sin - A4 cos), where
// a^2, -b^2 are the roots of EI kGA p^2 + (EI rhoA + rhoI kGA) w^2 p + rhoA w^2 (rhoI w^2 - kGA);
// free ends: bending moment EI psi' = 0 and shear force kGA (w' - psi) = 0 at z = 0 and L.
double FrequencyDeterminant(const Beam& b, double w) {
  const double EI = b.E * b.inertia();
  const double kGA = b.kappa() * b.G * b.area();
  const double rA = b.rho * b.area();
  const double rI = b.rho * b.inertia();
  const double qa = EI * kGA;
  const double qb = (EI * rA + rI * kGA) * w * w;
  const double qc = rA * w * w * (rI * w * w - kGA);
  const double disc = std::sqrt(qb * qb - 4 * qa * qc);
  const double a = std::sqrt((-qb + disc) / (2 * qa));
  const double bb = std::sqrt((qb + disc) / (2 * qa));
  const double ga = (kGA * a * a + rA * w * w) / (kGA * a);
  const double gb = (rA * w * w - kGA * bb * bb) / (kGA * bb);
  const double L = b.length_m;
  const double ch = std::cosh(a * L), sh = std::sinh(a * L), c = std::cos(bb * L),
               s = std::sin(bb * L);
  Eigen::Matrix4d m;
  m << ga * a, 0, gb * bb, 0,                              //
      0, a - ga, 0, bb + gb,                               //
      ga * a * ch, ga * a * sh, gb * bb * c, gb * bb * s,  //
      (a - ga) * sh, (a - ga) * ch, -(bb + gb) * s, (bb + gb) * c;
  // Scale out the growth of cosh so the sign change is found cleanly.
  return m.determinant() / ch;
}

std::vector<double> AnalyticalFrequencies(const Beam& b, int count) {
  std::vector<double> roots;
  const double step = 1.0;
  double w0 = 1.0;
  double f0 = FrequencyDeterminant(b, w0);
  while (static_cast<int>(roots.size()) < count) {
    const double w1 = w0 + step;
    const double f1 = FrequencyDeterminant(b, w1);
    if (std::signbit(f0) != std::signbit(f1)) {
      double lo = w0, hi = w1;
      for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        if (std::signbit(FrequencyDeterminant(b, mid)) == std::signbit(FrequencyDeterminant(b, lo)))
          lo = mid;
        else
          hi = mid;
      }
      roots.push_back(0.5 * (lo + hi));
    }
    w0 = w1;
    f0 = f1;
  }
  return roots;
}

std::vector<double> FeFrequencies(const Beam& b, int elements, int count) {
  RotorParams rotor;
  rotor.sections.push_back({b.length_m, b.diameter_m, 0.0, Material{b.E, b.G, b.rho}, elements});
  const FeRotor fe = AssembleFeRotor(rotor, {});
  const std::vector<double> all = UndampedNaturalFrequencies(fe.mass, fe.stiffness);
  // Four rigid-body zeros, then each bending frequency twice (x and y planes).
  std::vector<double> bending;
  for (int i = 0; i < count; ++i) bending.push_back(all[4 + 2 * i]);
  return bending;
}

TEST(TimoshenkoBeam, SlenderBeamMatchesEulerBernoulli) {
  const Beam b{1.0, 0.01, 211e9, 81.2e9, 7810};
  const double euler = 4.730040744862704 * 4.730040744862704 *
                       std::sqrt(b.E * b.inertia() / (b.rho * b.area())) /
                       (b.length_m * b.length_m);
  const std::vector<double> w = AnalyticalFrequencies(b, 1);
  EXPECT_NEAR(w[0] / euler, 1.0, 1e-3);  // shear and rotary inertia matter little at L/D = 100
  EXPECT_LT(w[0], euler);                // ...but they only ever lower the frequency
}

TEST(TimoshenkoBeam, FreeFreeFrequenciesConvergeToAnalytical) {
  const Beam b{1.0, 0.15, 211e9, 81.2e9, 7810};  // stubby: L/D = 6.7, shear matters
  const int count = 3;
  const std::vector<double> exact = AnalyticalFrequencies(b, count);
  std::vector<std::vector<double>> fe;
  double previous_error = 1e9;
  for (int elements : {2, 4, 8, 16, 32}) {
    fe.push_back(FeFrequencies(b, elements, count));
    double error = 0.0;
    for (int i = 0; i < count; ++i)
      error = std::max(error, std::abs(fe.back()[i] / exact[i] - 1.0));
    EXPECT_LT(error, previous_error) << elements << " elements";
    previous_error = error;
  }
  EXPECT_LT(previous_error, 2e-3);
  // The element converges at second order in h (the error falls ~4x per halving), so the
  // Richardson extrapolation of the two finest meshes must land on the analytical values.
  const std::size_t last = fe.size() - 1;
  for (int i = 0; i < count; ++i) {
    const double e16 = fe[last - 1][i] - exact[i];
    const double e32 = fe[last][i] - exact[i];
    EXPECT_GT(e16 / e32, 3.5) << "mode " << i;
    const double extrapolated = fe[last][i] + (fe[last][i] - fe[last - 1][i]) / 3.0;
    EXPECT_NEAR(extrapolated / exact[i], 1.0, 1e-5) << "mode " << i;
  }
  // Shear deformation is in the model: an Euler-Bernoulli beam would be >5 % stiffer here.
  const double euler = 4.730040744862704 * 4.730040744862704 *
                       std::sqrt(b.E * b.inertia() / (b.rho * b.area())) /
                       (b.length_m * b.length_m);
  EXPECT_LT(exact[0], 0.95 * euler);
}

// A station a hair beside a subdivision node takes that node's place: the mesh, and with it
// the model, moves by the hair. Kept, the node made an element of the hair's length whose
// stiffness dwarfed its neighbours' (a TDB moved 10 um off its node on a 30 mm element changed
// the flexible truth rig's reduced drop by a jump). The stubby beam's first three free-free
// bending frequencies with a station on node 2 of 8 and 10 um beside it agree to a part in a
// million, its stiffest mode stays where the mesh had it, and the nodes are as many.
TEST(TimoshenkoBeam, AStationBesideANodeMovesTheModelByAHair) {
  const Beam b{1.0, 0.15, 211e9, 81.2e9, 7810};
  RotorParams rotor;
  rotor.sections.push_back({b.length_m, b.diameter_m, 0.0, Material{b.E, b.G, b.rho}, 8});
  const FeRotor on = AssembleFeRotor(rotor, {0.25});
  const FeRotor beside = AssembleFeRotor(rotor, {0.25 + 1e-5});
  ASSERT_EQ(on.node_positions_m.size(), beside.node_positions_m.size());
  EXPECT_GE(beside.NodeAt(0.25 + 1e-5), 0);
  const std::vector<double> w_on = UndampedNaturalFrequencies(on.mass, on.stiffness);
  const std::vector<double> w_beside = UndampedNaturalFrequencies(beside.mass, beside.stiffness);
  for (int i = 0; i < 3; ++i) {
    const std::size_t k = static_cast<std::size_t>(4 + 2 * i);
    EXPECT_NEAR(w_beside[k] / w_on[k], 1.0, 1e-6) << "mode " << i;
  }
  // The mesh's stiffest mode, what a reduction must leave out and a step must not excite: a
  // hair's element puts it (element / hair)^2 higher.
  EXPECT_NEAR(w_beside.back() / w_on.back(), 1.0, 0.01);
  // Further off (a quarter element), the node stays and the station gets its own.
  const FeRotor apart = AssembleFeRotor(rotor, {0.25 + 0.03});
  EXPECT_EQ(apart.node_positions_m.size(), on.node_positions_m.size() + 1);
}

}  // namespace
}  // namespace ambdrop::timoshenko_beam_test
