// rotor.element_theory: Euler-Bernoulli and Rayleigh shaft elements. Free-free beam frequencies
// converge to the closed form (Euler-Bernoulli: beta_n L roots of cos cosh = 1) and to the
// Rayleigh frequency equation solved here by bisection; rigid tilts give the cylinder's closed-form
// transverse and polar inertias (no rotary inertia and no shaft gyroscopics for Euler-Bernoulli).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "io/config/config_loader.hpp"
#include "rt_core/fe_rotor.hpp"
#include "rt_core/natural_frequencies.hpp"

namespace ambdrop::shaft_element_theory_test {
namespace {

using ::testing::HasSubstr;

struct Beam {
  double length_m, diameter_m, E, G, rho;
  double area() const { return std::numbers::pi / 4 * diameter_m * diameter_m; }
  double inertia() const { return std::numbers::pi / 64 * std::pow(diameter_m, 4); }
};

// Stubby (L/D = 6.7): shear and rotary inertia each move the frequencies by percents, so a theory
// that is not the one asked for fails the tolerances below.
const Beam kStubby{1.0, 0.15, 211e9, 81.2e9, 7810};

// Free-free Euler-Bernoulli: cos(bL) cosh(bL) = 1, omega = (bL)^2 sqrt(EI / (rho A L^4))
// (Timoshenko & Gere / Blevins, "Formulas for Natural Frequency and Mode Shape", Table 8-1).
constexpr double kBetaL[3] = {4.730040744862704, 7.853204624095838, 10.995607838001671};

double EulerBernoulliFrequency(const Beam& b, int mode) {
  const double bl = kBetaL[mode];
  return bl * bl * std::sqrt(b.E * b.inertia() / (b.rho * b.area())) / (b.length_m * b.length_m);
}

// Rayleigh beam, EI w'''' - rho I w''_tt + rho A w_tt = 0 (Rayleigh, "Theory of Sound", Sec. 186;
// Han, Benaroya & Wei 1999, J. Sound Vib. 225(5), Sec. 4). With w = e^{kz} e^{i omega t}:
// EI k^4 + rho I omega^2 k^2 - rho A omega^2 = 0, roots k^2 = a^2 > 0 and -b^2 < 0. Free ends:
// moment EI w'' = 0 and shear EI w''' + rho I omega^2 w' = 0 at z = 0 and L.
double RayleighDeterminant(const Beam& b, double w, double rotary_scale = 1.0) {
  const double EI = b.E * b.inertia();
  const double rA = b.rho * b.area();
  const double rI = rotary_scale * b.rho * b.inertia();
  const double qb = rI * w * w;
  const double disc = std::sqrt(qb * qb + 4 * EI * rA * w * w);
  const double a = std::sqrt((-qb + disc) / (2 * EI));
  const double bb = std::sqrt((qb + disc) / (2 * EI));
  const double alpha = EI * a * a * a + rI * w * w * a;
  const double beta = EI * bb * bb * bb - rI * w * w * bb;
  const double L = b.length_m;
  const double ch = std::cosh(a * L), sh = std::sinh(a * L), c = std::cos(bb * L),
               s = std::sin(bb * L);
  // Columns: A1 cosh(az), A2 sinh(az), A3 cos(bz), A4 sin(bz).
  Eigen::Matrix4d m;
  m << a * a, 0, -bb * bb, 0,                              //
      0, alpha, 0, -beta,                                  //
      a * a * ch, a * a * sh, -bb * bb * c, -bb * bb * s,  //
      alpha * sh, alpha * ch, beta * s, -beta * c;
  m.row(1) /= EI * a * a * a;  // rows to order one, so the sign change is found cleanly
  m.row(3) /= EI * a * a * a;
  return m.determinant() / ch;
}

std::vector<double> RayleighFrequencies(const Beam& b, int count, double rotary_scale = 1.0) {
  std::vector<double> roots;
  double w0 = 10.0;
  double f0 = RayleighDeterminant(b, w0, rotary_scale);
  while (static_cast<int>(roots.size()) < count) {
    const double w1 = w0 + 1.0;
    const double f1 = RayleighDeterminant(b, w1, rotary_scale);
    if (std::signbit(f0) != std::signbit(f1)) {
      double lo = w0, hi = w1;
      const bool lo_sign = std::signbit(f0);
      for (int i = 0; i < 100; ++i) {
        const double mid = 0.5 * (lo + hi);
        (std::signbit(RayleighDeterminant(b, mid, rotary_scale)) == lo_sign ? lo : hi) = mid;
      }
      roots.push_back(0.5 * (lo + hi));
    }
    w0 = w1;
    f0 = f1;
  }
  return roots;
}

RotorParams Shaft(const Beam& b, int elements, ShaftElementTheory theory) {
  RotorParams rotor;
  rotor.element_theory = theory;
  rotor.sections.push_back({b.length_m, b.diameter_m, 0.0, Material{b.E, b.G, b.rho}, elements});
  return rotor;
}

std::vector<double> FeFrequencies(const Beam& b, int elements, int count,
                                  ShaftElementTheory theory) {
  const FeRotor fe = AssembleFeRotor(Shaft(b, elements, theory), {});
  const std::vector<double> all = UndampedNaturalFrequencies(fe.mass, fe.stiffness);
  // Four rigid-body zeros, then each bending frequency twice (x and y planes).
  std::vector<double> bending;
  for (int i = 0; i < count; ++i) bending.push_back(all[4 + 2 * i]);
  return bending;
}

/// The FE frequencies of 2 .. 32 elements converge to `exact` from above (the consistent
/// elements are a Ritz method) at fourth order in h (the cubic Hermite element).
void ExpectConvergence(const std::vector<double>& exact, ShaftElementTheory theory) {
  const int count = static_cast<int>(exact.size());
  std::vector<double> previous;
  for (int elements : {2, 4, 8, 16, 32}) {
    const std::vector<double> fe = FeFrequencies(kStubby, elements, count, theory);
    for (int i = 0; i < count; ++i) {
      EXPECT_GT(fe[i], exact[i] * (1.0 - 1e-12)) << elements << " elements, mode " << i;
      if (elements >= 16) {
        // Error ratio per halving ~2^4 once the mesh resolves the mode.
        EXPECT_GT((previous[i] - exact[i]) / (fe[i] - exact[i]), 14.0)
            << elements << " elements, mode " << i;
      }
    }
    if (elements == 32) {
      for (int i = 0; i < count; ++i) {
        EXPECT_NEAR(fe[i] / exact[i], 1.0, 2e-5) << "mode " << i << " at 32 elements";
        // Richardson extrapolation at fourth order lands on the exact value.
        const double extrapolated = fe[i] + (fe[i] - previous[i]) / 15.0;
        EXPECT_NEAR(extrapolated / exact[i], 1.0, 1e-6) << "mode " << i;
      }
    }
    previous = fe;
  }
}

TEST(ShaftElementTheory, EulerBernoulliFreeFreeConvergesToClosedForm) {
  std::vector<double> exact;
  for (int i = 0; i < 3; ++i) exact.push_back(EulerBernoulliFrequency(kStubby, i));
  ExpectConvergence(exact, ShaftElementTheory::kEulerBernoulli);
}

TEST(ShaftElementTheory, RayleighSolverReducesToEulerBernoulli) {
  // The bisection solver with the rotary inertia scaled out must give the closed form.
  const std::vector<double> w = RayleighFrequencies(kStubby, 3, 1e-12);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(w[i] / EulerBernoulliFrequency(kStubby, i), 1.0, 1e-9) << "mode " << i;
  }
}

TEST(ShaftElementTheory, RayleighFreeFreeConvergesToFrequencyEquation) {
  const std::vector<double> exact = RayleighFrequencies(kStubby, 3);
  // Rotary inertia matters here (the third mode > 3 % below Euler-Bernoulli), so a missing or
  // doubled rotary matrix fails the convergence.
  EXPECT_LT(exact[2], 0.97 * EulerBernoulliFrequency(kStubby, 2));
  ExpectConvergence(exact, ShaftElementTheory::kRayleigh);
}

TEST(ShaftElementTheory, ShearAndRotaryInertiaEachLowerTheFrequencies) {
  const int count = 3;
  const auto eb = FeFrequencies(kStubby, 32, count, ShaftElementTheory::kEulerBernoulli);
  const auto rayleigh = FeFrequencies(kStubby, 32, count, ShaftElementTheory::kRayleigh);
  const auto timoshenko = FeFrequencies(kStubby, 32, count, ShaftElementTheory::kTimoshenko);
  for (int i = 0; i < count; ++i) {
    EXPECT_LT(rayleigh[i], eb[i]) << "mode " << i;
    EXPECT_LT(timoshenko[i], 0.99 * rayleigh[i]) << "mode " << i;  // shear: > 1 % at L/D = 6.7
  }
}

// Rigid tilts of the whole shaft about its centre: about x (y = -(z - zc), theta_x = 1) and about
// y (x = z - zc, theta_y = 1); the FE interpolates them exactly.
Eigen::VectorXd Tilt(const FeRotor& fe, bool about_x) {
  Eigen::VectorXd t = Eigen::VectorXd::Zero(fe.dofs());
  const double zc = 0.5 * fe.length_m;
  for (std::size_t n = 0; n < fe.node_positions_m.size(); ++n) {
    const double dz = fe.node_positions_m[n] - zc;
    const int b = 4 * static_cast<int>(n);
    if (about_x) {
      t(b + 1) = -dz;
      t(b + 2) = 1.0;
    } else {
      t(b + 0) = dz;
      t(b + 3) = 1.0;
    }
  }
  return t;
}

TEST(ShaftElementTheory, RigidTiltInertiasMatchTheCylinder) {
  const Beam& b = kStubby;
  const double mass = b.rho * b.area() * b.length_m;
  const double translational = mass * b.length_m * b.length_m / 12.0;  // m L^2 / 12
  const double rotary = b.rho * b.inertia() * b.length_m;              // m D^2 / 16
  const double polar = 2.0 * rotary;                                   // m D^2 / 8
  struct Expect {
    ShaftElementTheory theory;
    double transverse, gyroscopic;
  };
  for (const Expect& e : {Expect{ShaftElementTheory::kEulerBernoulli, translational, 0.0},
                          Expect{ShaftElementTheory::kRayleigh, translational + rotary, polar},
                          Expect{ShaftElementTheory::kTimoshenko, translational + rotary, polar}}) {
    const FeRotor fe = AssembleFeRotor(Shaft(b, 8, e.theory), {});
    const Eigen::VectorXd tx = Tilt(fe, true), ty = Tilt(fe, false);
    const int theory = static_cast<int>(e.theory);
    EXPECT_NEAR(ty.dot(fe.mass * ty) / e.transverse, 1.0, 1e-12) << "theory " << theory;
    EXPECT_NEAR(tx.dot(fe.mass * tx) / e.transverse, 1.0, 1e-12) << "theory " << theory;
    EXPECT_NEAR(tx.dot(fe.gyroscopic * ty), e.gyroscopic, 1e-12 * polar) << "theory " << theory;
    // The spin inertia is the shaft's whatever the bending theory.
    EXPECT_NEAR(fe.polar_inertia_kg_m2 / polar, 1.0, 1e-12) << "theory " << theory;
  }
  // Euler-Bernoulli drops the shaft's gyroscopics entirely, not only on rigid tilts.
  EXPECT_EQ(AssembleFeRotor(Shaft(b, 8, ShaftElementTheory::kEulerBernoulli), {})
                .gyroscopic.cwiseAbs()
                .maxCoeff(),
            0.0);
}

TEST(ShaftElementTheory, ShearModulusIsIgnoredWithoutShear) {
  Beam other = kStubby;
  other.G = 1e3;  // absurd; only the Timoshenko element reads it
  for (ShaftElementTheory t :
       {ShaftElementTheory::kEulerBernoulli, ShaftElementTheory::kRayleigh}) {
    const FeRotor a = AssembleFeRotor(Shaft(kStubby, 4, t), {});
    const FeRotor b = AssembleFeRotor(Shaft(other, 4, t), {});
    EXPECT_EQ(a.stiffness, b.stiffness);
    EXPECT_EQ(a.mass, b.mass);
  }
}

// ---------------------------------------------------------------------------------------------
// The key.

constexpr char kSource[] = "theory.toml";
const std::string kFlexible = R"(name = "beam"
[rotor]
model = "flexible"
element_theory = "rayleigh"
[rotor.materials.steel]
youngs_modulus_Pa = 211e9
shear_modulus_Pa = 81.2e9
density_kg_m3 = 7810
[[rotor.sections]]
length_m = 1.0
outer_diameter_m = 0.15
material = "steel"
elements = 8
)";

TEST(ShaftElementTheoryKey, ReadFromFileAndOverride) {
  EXPECT_EQ(LoadConfigFromString(kFlexible, kSource).params.rotor.element_theory,
            ShaftElementTheory::kRayleigh);
  const ModelParams eb =
      LoadConfigFromString(kFlexible, kSource, {"rotor.element_theory=euler_bernoulli"}).params;
  EXPECT_EQ(eb.rotor.element_theory, ShaftElementTheory::kEulerBernoulli);
  std::string without(kFlexible);
  without.erase(without.find("element_theory = \"rayleigh\"\n"), 28);
  EXPECT_EQ(LoadConfigFromString(without, kSource).params.rotor.element_theory,
            ShaftElementTheory::kTimoshenko);
  // The key reaches the assembly: the loaded rotor's first frequency is Euler-Bernoulli's.
  const FeRotor fe = AssembleFeRotor(eb.rotor, {});
  const std::vector<double> w = UndampedNaturalFrequencies(fe.mass, fe.stiffness);
  EXPECT_NEAR(w[4] / EulerBernoulliFrequency(kStubby, 0), 1.0, 1e-4);
}

std::string ErrorOf(const std::string& text) {
  try {
    LoadConfigFromString(text, kSource);
  } catch (const ConfigError& error) {
    return error.what();
  }
  ADD_FAILURE() << "loaded without a ConfigError";
  return {};
}

TEST(ShaftElementTheoryKey, UnknownTheoryNamesFileLineKeyAndChoices) {
  std::string text(kFlexible);
  text.replace(text.find("\"rayleigh\""), 10, "\"bernoulli\"");
  EXPECT_THAT(ErrorOf(text), ::testing::StartsWith(std::string(kSource) + ":4:"));
  EXPECT_THAT(ErrorOf(text), HasSubstr("'rotor.element_theory'"));
  EXPECT_THAT(ErrorOf(text),
              HasSubstr("expected one of \"timoshenko\", \"rayleigh\", \"euler_bernoulli\""));
  EXPECT_THAT(ErrorOf(text), HasSubstr("found \"bernoulli\""));
}

TEST(ShaftElementTheoryKey, RigidRotorRejectsIt) {
  const std::string text = R"(name = "rigid"
[rotor]
model = "rigid"
element_theory = "rayleigh"
[rotor.rigid]
mass_kg = 1
polar_inertia_kg_m2 = 0.1
transverse_inertia_kg_m2 = 0.1
centre_of_mass_m = 0
)";
  const std::string message = ErrorOf(text);
  EXPECT_THAT(message, ::testing::StartsWith(std::string(kSource) + ":4:"));
  EXPECT_THAT(message, HasSubstr("'rotor.element_theory'"));
  EXPECT_THAT(message, HasSubstr("expected no element_theory with model = \"rigid\""));
}

}  // namespace
}  // namespace ambdrop::shaft_element_theory_test
