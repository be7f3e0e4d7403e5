// With no damping and no contact, the spinning rotor's mechanical energy is conserved: the
// gyroscopic forces do no work at constant speed. The integrator must hold it to 1e-9 over 1 s.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <cmath>

#include "rt_core/model.hpp"
#include "rt_core/simulator.hpp"
#include "test_configs.hpp"

namespace ambdrop::energy_test {
namespace {

// Mechanical energy about the static equilibrium q0 = K^-1 F_gravity (M = I): the constant
// gravity force only shifts the potential's minimum.
double Energy(const Model& m, const State& s) {
  const int n = m.modes();
  const Eigen::MatrixXd k = m.rotor.stiffness;
  const Eigen::VectorXd q0 = k.ldlt().solve(Eigen::VectorXd(m.gravity_force));
  const Eigen::VectorXd dq = s.y.head(n) - q0;
  const Eigen::VectorXd qd = s.y.segment(n, n);
  return 0.5 * qd.squaredNorm() + 0.5 * dq.dot(k * dq);
}

TEST(Energy, ConservedWithoutDampingOrContactOverOneSecond) {
  ModelParams p = testing::LoadTestConfig(
      "friswell_5_9_1.toml", {"rotor.modes=12", "gravity.enabled=true", "simulation.duration_s=1.0",
                              "simulation.initial_position=\"equilibrium\""});
  const Model model = BuildModel(p);
  Simulator sim(model);
  State s = sim.InitialState();
  // Whirl in the four lowest supported modes (the bearing modes), as a drop or knock would.
  const Eigen::MatrixXd k = model.rotor.stiffness;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> modes(k);
  for (int i = 0; i < 4; ++i)
    s.y.segment(model.modes(), model.modes()) += 1e-3 * modes.eigenvectors().col(i);
  const double e0 = Energy(model, s);
  ASSERT_GT(e0, 0.0);
  double worst = 0.0;
  for (std::int64_t i = 0; i < model.total_steps; ++i) {
    ASSERT_EQ(sim.Step(&s, ControlInput{}), StepStatus::kOk);
    if (i % 1000 == 0) worst = std::max(worst, std::abs(Energy(model, s) / e0 - 1.0));
  }
  worst = std::max(worst, std::abs(Energy(model, s) / e0 - 1.0));
  EXPECT_LT(worst, 1e-9);
  EXPECT_NE(s.y(model.spin_index()), 0.0);  // the rotor really was spinning (gyroscopics on)
}

TEST(Energy, ModalDampingOnlyEverRemovesEnergy) {
  ModelParams p = testing::LoadTestConfig("friswell_5_9_1.toml",
                                          {"rotor.modes=12", "rotor.modal_damping_ratio=0.02"});
  const Model model = BuildModel(p);
  Simulator sim(model);
  State s = sim.InitialState();
  for (int i = 0; i < 6; ++i) s.y(model.modes() + i) = 1e-3 * (i + 1);
  double previous = Energy(model, s);
  for (int i = 0; i < 20000; ++i) {
    ASSERT_EQ(sim.Step(&s, ControlInput{}), StepStatus::kOk);
    const double e = Energy(model, s);
    ASSERT_LE(e, previous * (1 + 1e-12)) << "step " << i;
    previous = e;
  }
}

}  // namespace
}  // namespace ambdrop::energy_test
