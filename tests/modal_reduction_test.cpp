// Pseudo-modal reduction: the reduced model's frequencies approach the full FE model's from
// above as modes are added (Rayleigh-Ritz) and equal them once the basis is complete; the
// seed-000 rotor built from its config matches the paper's published mass, inertia and modes.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "rt_core/fe_rotor.hpp"
#include "rt_core/modal_analysis.hpp"
#include "rt_core/modal_reduction.hpp"
#include "test_configs.hpp"

namespace ambdrop::modal_reduction_test {
namespace {

TEST(ModalReduction, SupportedFrequenciesConvergeAsModesAreAdded) {
  const ModelParams base = testing::LoadTestConfig("friswell_5_9_1.toml");
  const ModalAnalysis full = AnalyseModes(base, 0.0, 6);
  double previous_error = 1e9;
  for (int modes : {8, 12, 16, 20, 28}) {
    ModelParams p = base;
    p.rotor.modes = modes;
    const ModalAnalysis reduced = AnalyseModes(p, 0.0, 6);
    double error = 0.0;
    for (int i = 0; i < 6; ++i) {
      // A Ritz basis can only stiffen the model.
      EXPECT_GE(reduced.reduced_supported_rad_s[i], full.supported_rad_s[i] * (1 - 1e-7));
      error = std::max(error, reduced.reduced_supported_rad_s[i] / full.supported_rad_s[i] - 1);
    }
    EXPECT_LE(error, previous_error + 1e-7) << modes << " modes";
    previous_error = error;
  }
  EXPECT_LT(std::abs(previous_error), 1e-6);  // 28 modes span all 28 DOF
}

TEST(ModalReduction, BasisIsMassNormalisedWithFourRigidBodyModes) {
  const ModelParams p = testing::LoadTestConfig("jarroux2019_industrial.toml");
  const FeRotor fe = AssembleFeRotor(p.rotor, StationPositions(p));
  const ReducedRotor r = BuildReducedRotor(p);
  const Eigen::MatrixXd modal_mass = r.basis.transpose() * fe.mass * r.basis;
  EXPECT_LT((modal_mass - Eigen::MatrixXd::Identity(r.size, r.size)).norm(), 1e-9);
  int rigid = 0;
  for (int i = 0; i < r.size; ++i) rigid += r.free_frequencies_rad_s(i) == 0.0 ? 1 : 0;
  EXPECT_EQ(rigid, 4);
  // The gyroscopic matrix stays skew-symmetric after projection.
  EXPECT_LT((r.gyroscopic + r.gyroscopic.transpose()).norm(), 1e-12 * r.gyroscopic.norm());
}

TEST(Seed000Rotor, ConfigMatchesThePublishedRig) {
  const ModelParams p = testing::LoadTestConfig("jarroux2019_industrial.toml");
  const ReducedRotor r = BuildReducedRotor(p);
  EXPECT_NEAR(r.mass_kg, 200.0, 0.03 * 200.0);  // Jarroux 2019 Sec. 5
  EXPECT_NEAR(r.polar_inertia_kg_m2, 0.97, 0.03 * 0.97);
  EXPECT_NEAR(r.length_m, 1.150, 1e-9);
  ASSERT_EQ(p.ambs.size(), 2u);
  EXPECT_NEAR(std::abs(p.ambs[0].position_m - p.ambs[1].position_m), 0.787, 1e-9);
  // "designed to have its first flexible mode above 25 000 rpm" (free-free).
  const double first_flexible = r.free_frequencies_rad_s(4);
  EXPECT_GT(first_flexible, 25000.0 * std::numbers::pi / 30.0);
  // Gravity acts on the whole mass: the generalized gravity force carries m g.
  const Eigen::VectorXd unit = r.vertical_unit_force;
  EXPECT_NEAR(unit.squaredNorm(), r.mass_kg, 1e-6 * r.mass_kg);
}

// The centre of mass the reduced rotor carries (the fit's static unbalance sits there): summed
// per FE element, it is the sections' (each uniform, from 0 one after another) and discs' own
// first moment over their mass, however the stations split the sections.
TEST(Seed000Rotor, CentreOfMassIsTheSectionsAndDiscsFirstMoment) {
  const ModelParams p = testing::LoadTestConfig("jarroux2019_industrial.toml");
  double mass = 0.0;
  double moment = 0.0;
  double start = 0.0;
  for (const ShaftSection& s : p.rotor.sections) {
    const double m =
        s.material.density_kg_m3 * std::numbers::pi / 4.0 *
        (s.outer_diameter_m * s.outer_diameter_m - s.inner_diameter_m * s.inner_diameter_m) *
        s.length_m;
    mass += m;
    moment += m * (start + 0.5 * s.length_m);
    start += s.length_m;
  }
  for (const Disc& d : p.rotor.discs) {
    mass += d.mass_kg;
    moment += d.mass_kg * d.position_m;
  }
  const ReducedRotor r = BuildReducedRotor(p);
  EXPECT_NEAR(r.mass_kg, mass, 1e-9 * mass);
  EXPECT_NEAR(r.centre_of_mass_m, moment / mass, 1e-9);
  // Not the shaft's middle: the rotor is not symmetric.
  EXPECT_GT(std::abs(r.centre_of_mass_m - 0.5 * r.length_m), 1e-3);
}

}  // namespace
}  // namespace ambdrop::modal_reduction_test
