// AMBs after power loss (issue 24 items 1-2): the bias source and the coil-current laws, held
// against closed forms through the path a run takes (PowerState fills the input, the simulator
// steps it).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "controller_if/boundary/power_state.hpp"
#include "rt_core/amb_force.hpp"
#include "rt_core/model.hpp"
#include "rt_core/power_loss_drive.hpp"
#include "rt_core/simulator.hpp"

namespace ambdrop::amb_power_loss_test {
namespace {

constexpr double kMass_kg = 10.0;
constexpr double kKi_N_per_A = 100.0;
constexpr double kKs_N_per_m = 2e5;  // per AMB
constexpr double kStep_s = 5e-6;

// A rigid rotor between two linearised-law AMBs set symmetrically about its centre of mass, so
// that a parallel displacement is a pure translation (mass m, stiffness 2 ks). No TDB.
ModelParams TwoAmbRig(AmbBiasSource bias) {
  ModelParams p;
  p.rotor.kind = RotorKind::kRigid;
  p.rotor.rigid = {kMass_kg, 0.01, 0.5, 0.5};
  p.simulation.step_s = kStep_s;
  p.simulation.spin_speed_rad_s = 0.0;
  p.simulation.initial_position = InitialPosition::kCentred;
  p.trigger.enabled = false;
  for (double z : {0.0, 1.0}) {
    AmbParams a;
    a.name = std::string(1, z == 0.0 ? 'a' : 'b');  // not = "a": GCC 12 false -Wstringop-overflow
    a.position_m = z;
    a.law = AmbForceLaw::kLinearisedCurrents;
    a.current_gain_N_per_A = kKi_N_per_A;
    a.position_gain_N_per_m = kKs_N_per_m;
    a.bias_source = bias;
    p.ambs.push_back(a);
  }
  return p;
}

// Every AMB axis loses power at step 0 with `current_A` flowing.
PowerState FailedAtZero(const Model& model, double current_A) {
  PowerState power(model);
  ControlInput in;
  for (AmbDrive& d : in.amb) d.current_A = {current_A, current_A};
  power.Apply(PowerEvent{}, 0, in);
  return power;
}

// The rotor displaced by u_x_m at both AMBs (a translation), at rest.
State Displaced(const Model& model, const Simulator& sim, double u_x_m) {
  const int n = model.modes();
  Eigen::MatrixXd s(4, n);
  s << model.amb_shapes[0], model.amb_shapes[1];
  State state = sim.InitialState();
  state.y.head(n) = s.fullPivLu().solve(Eigen::Vector4d(u_x_m, 0.0, u_x_m, 0.0));
  return state;
}

double AmbX(const Model& model, const State& s) {
  return (model.amb_shapes[0] * s.y.head(model.modes()))(0);
}
double AmbY(const Model& model, const State& s) {
  return (model.amb_shapes[0] * s.y.head(model.modes()))(1);
}

TEST(PowerLossBias, PermanentMagnetKeepsTheNegativeStiffness) {
  // No control current and no decay: only the magnet's bias acts, f = ks u per AMB, so
  // m u'' = 2 ks u and u(t) = u0 cosh(lambda t), lambda = sqrt(2 ks / m). The first step at or
  // beyond u1 lies within one step after t1 = acosh(u1/u0)/lambda; RK4's own error,
  // ~(lambda dt)^4 lambda t1 ~ 1e-12 relative, is far below that.
  const Model model = BuildModel(TwoAmbRig(AmbBiasSource::kPermanentMagnet));
  Simulator sim(model);
  const PowerState power = FailedAtZero(model, 0.0);
  const double u0 = 10e-6;
  const double u1 = 100e-6;
  State s = Displaced(model, sim, u0);
  ControlInput in;
  while (AmbX(model, s) < u1 && sim.Time(s) < 0.1) {
    power.Fill(s.step_index, &in);
    ASSERT_EQ(sim.Step(&s, in), StepStatus::kOk);
  }
  const double lambda = std::sqrt(2.0 * kKs_N_per_m / kMass_kg);
  const double expected_s = std::acosh(u1 / u0) / lambda;
  EXPECT_GE(sim.Time(s), expected_s);
  EXPECT_LT(sim.Time(s), expected_s + kStep_s);
}

TEST(PowerLossBias, ElectromagnetBiasWithoutDecayFallsFreely) {
  // The amplifiers made the bias: without flux decay every AMB force is gone at once, so the
  // centred rotor falls as y = -g t^2 / 2 (RK4 integrates a constant force exactly) and x stays.
  const Model model = BuildModel(TwoAmbRig(AmbBiasSource::kElectromagnet));
  Simulator sim(model);
  const PowerState power = FailedAtZero(model, 0.5);
  State s = sim.InitialState();
  ControlInput in;
  for (int k = 0; k < 2000; ++k) {
    power.Fill(s.step_index, &in);
    ASSERT_EQ(sim.Step(&s, in), StepStatus::kOk);
  }
  const double t = sim.Time(s);
  EXPECT_NEAR(AmbY(model, s), -0.5 * 9.81 * t * t, 1e-12);
  EXPECT_EQ(AmbX(model, s), 0.0);
}

TEST(PowerLossBias, PermanentMagnetElectromagnetLawKeepsTheBiasForce) {
  // Electromagnet law, PM bias, control current gone: the pull is the magnet's alone,
  // k I0^2 (1/(g0 - u)^2 - 1/(g0 + u)^2), k = mu0 N^2 A cos(alpha) / 4 (seed 003, Eq. (2)).
  ModelParams p = TwoAmbRig(AmbBiasSource::kPermanentMagnet);
  p.gravity.enabled = false;
  for (AmbParams& a : p.ambs) {
    a.law = AmbForceLaw::kElectromagnet;
    a.electromagnet = {1.96e-4, 130.0, 0.25e-3, 2.0};
  }
  const Model model = BuildModel(p);
  Simulator sim(model);
  const PowerState power = FailedAtZero(model, 0.7);
  const double u = 50e-6;
  State s = Displaced(model, sim, u);
  ControlInput in;
  power.Fill(100, &in);
  StateVector rate = StateVector::Zero(model.state_size);
  std::array<TdbForce, kMaxTdbs> tdb{};
  sim.Derivative(s.y, in, &rate, &tdb);
  const double g0 = 0.25e-3;
  const double k =
      4e-7 * std::numbers::pi * 130.0 * 130.0 * 1.96e-4 * std::cos(std::numbers::pi / 8) / 4;
  const double pull = k * 4.0 * (1.0 / ((g0 - u) * (g0 - u)) - 1.0 / ((g0 + u) * (g0 + u)));
  const int n = model.modes();
  const double accel = (model.amb_shapes[0] * rate.segment(n, n))(0);
  EXPECT_NEAR(accel, 2.0 * pull / kMass_kg, 1e-6 * 2.0 * pull / kMass_kg);
}

// The reported control current of axis x of AMB 0 `seconds` after power loss, through the
// power state (and the same through ReportedCoilCurrent, what measured-like records carry).
double Reported(const Model& model, const PowerState& power, std::int64_t step) {
  ControlInput in;
  power.Fill(step, &in);
  const double via_input = in.amb[0].current_A[0] * std::sqrt(in.amb[0].force_scale[0]);
  const double via_sampler = ReportedCoilCurrent(
      PowerLossDrive(model.params.ambs[0], 1.5, static_cast<double>(step) * kStep_s));
  EXPECT_EQ(via_input, via_sampler) << step;
  return via_input;
}

TEST(PowerLossLaws, RampReachesZeroAtCurrentOverSlewRate) {
  // PM bias: the coil carries the control current alone, i(t) = i0 - S t until i0 / S.
  ModelParams p = TwoAmbRig(AmbBiasSource::kPermanentMagnet);
  const double slew = 100.0;
  for (AmbParams& a : p.ambs) {
    a.flux_decay.enabled = true;
    a.flux_decay.current_law = PowerLossCurrentLaw::kSlewLimitedRamp;
    a.flux_decay.slew_rate_A_per_s = slew;
  }
  const Model model = BuildModel(p);
  const PowerState power = FailedAtZero(model, 1.5);
  std::int64_t zero_step = -1;
  for (std::int64_t k = 0; k < 4000; ++k) {
    const double i = Reported(model, power, k);
    const double t = static_cast<double>(k) * kStep_s;
    if (zero_step < 0 && i == 0.0) zero_step = k;
    if (zero_step < 0) {
      EXPECT_NEAR(i, 1.5 - slew * t, 1e-12) << k;
    } else {
      EXPECT_EQ(i, 0.0) << k;  // it stops at zero
    }
  }
  EXPECT_NEAR(static_cast<double>(zero_step) * kStep_s, 1.5 / slew, kStep_s);
}

TEST(PowerLossLaws, ElectromagnetBiasRampsEachCoil) {
  // Linearised law, electromagnet bias I0: the coils I0 + i0 and I0 - i0 each fall at S to
  // zero; f = ki (I0(t)/I0) i(t) + ks (I0(t)/I0)^2 u with I0(t), i(t) the pair's half sum and
  // half difference (the electromagnet law linearised at the bias I0(t)).
  ModelParams p = TwoAmbRig(AmbBiasSource::kElectromagnet);
  p.gravity.enabled = false;
  const double slew = 100.0;
  const double bias = 2.0;
  const double i0 = 0.5;
  for (AmbParams& a : p.ambs) {
    a.flux_decay.enabled = true;
    a.flux_decay.current_law = PowerLossCurrentLaw::kSlewLimitedRamp;
    a.flux_decay.slew_rate_A_per_s = slew;
    a.flux_decay.bias_current_A = bias;
  }
  const Model model = BuildModel(p);
  Simulator sim(model);
  const PowerState power = FailedAtZero(model, i0);
  const double u = 20e-6;
  const State s = Displaced(model, sim, u);
  const int n = model.modes();
  for (const double t : {0.0, 5e-3, 14.5e-3, 20e-3, 24.9e-3, 30e-3}) {
    const double plus = std::max(bias + i0 - slew * t, 0.0);
    const double minus = std::max(bias - i0 - slew * t, 0.0);
    ControlInput in;
    power.Fill(std::llround(t / kStep_s), &in);
    const AmbDrive& d = in.amb[0];
    EXPECT_NEAR(bias * d.bias_scale[0] + d.current_A[0], plus, 1e-9) << t;
    EXPECT_NEAR(bias * d.bias_scale[0] - d.current_A[0], minus, 1e-9) << t;
    StateVector rate = StateVector::Zero(model.state_size);
    std::array<TdbForce, kMaxTdbs> tdb{};
    sim.Derivative(s.y, in, &rate, &tdb);
    const double b = 0.5 * (plus + minus) / bias;
    const double f = kKi_N_per_A * b * 0.5 * (plus - minus) + kKs_N_per_m * b * b * u;
    EXPECT_NEAR((model.amb_shapes[0] * rate.segment(n, n))(0), 2.0 * f / kMass_kg, 1e-9) << t;
  }
}

TEST(PowerLossLaws, ElectromagnetLawRampsEachCoil) {
  // The electromagnet law with its bias from the coils: the pull of each coil from its own
  // ramped current, k (I+^2/(g0 - u)^2 - I-^2/(g0 + u)^2) (seed 003, Eq. (2)).
  ModelParams p = TwoAmbRig(AmbBiasSource::kElectromagnet);
  p.gravity.enabled = false;
  const double slew = 100.0;
  const double bias = 2.0;
  const double i0 = 0.5;
  for (AmbParams& a : p.ambs) {
    a.law = AmbForceLaw::kElectromagnet;
    a.electromagnet = {1.96e-4, 130.0, 0.25e-3, bias};
    a.flux_decay.enabled = true;
    a.flux_decay.current_law = PowerLossCurrentLaw::kSlewLimitedRamp;
    a.flux_decay.slew_rate_A_per_s = slew;
  }
  const Model model = BuildModel(p);
  Simulator sim(model);
  const PowerState power = FailedAtZero(model, i0);
  const double u = 30e-6;
  const double g0 = 0.25e-3;
  const double k =
      4e-7 * std::numbers::pi * 130.0 * 130.0 * 1.96e-4 * std::cos(std::numbers::pi / 8) / 4;
  const State s = Displaced(model, sim, u);
  const int n = model.modes();
  for (const double t : {0.0, 5e-3, 14.5e-3, 20e-3, 30e-3}) {
    const double plus = std::max(bias + i0 - slew * t, 0.0);
    const double minus = std::max(bias - i0 - slew * t, 0.0);
    ControlInput in;
    power.Fill(std::llround(t / kStep_s), &in);
    StateVector rate = StateVector::Zero(model.state_size);
    std::array<TdbForce, kMaxTdbs> tdb{};
    sim.Derivative(s.y, in, &rate, &tdb);
    const double f =
        k * (plus * plus / ((g0 - u) * (g0 - u)) - minus * minus / ((g0 + u) * (g0 + u)));
    EXPECT_NEAR((model.amb_shapes[0] * rate.segment(n, n))(0), 2.0 * f / kMass_kg,
                1e-6 * std::abs(2.0 * f / kMass_kg) + 1e-9)
        << t;
  }
}

TEST(PowerLossLaws, HoldThenExponential) {
  // i0 for the hold time, then i0 exp(-(t - hold)/tau); the whole force by the square.
  for (const AmbBiasSource bias :
       {AmbBiasSource::kElectromagnet, AmbBiasSource::kPermanentMagnet}) {
    ModelParams p = TwoAmbRig(bias);
    for (AmbParams& a : p.ambs) {
      a.flux_decay.enabled = true;
      a.flux_decay.current_law = PowerLossCurrentLaw::kHoldThenExponential;
      a.flux_decay.hold_time_s = 2e-3;
      a.flux_decay.time_constant_s = 1e-3;
    }
    const Model model = BuildModel(p);
    const PowerState power = FailedAtZero(model, 1.5);
    for (std::int64_t k = 0; k < 2000; k += 7) {
      const double t = static_cast<double>(k) * kStep_s;
      const double expected = t < 2e-3 ? 1.5 : 1.5 * std::exp(-(t - 2e-3) / 1e-3);
      EXPECT_NEAR(Reported(model, power, k), expected, 1e-14 * 1.5) << k;
      ControlInput in;
      power.Fill(k, &in);
      // Electromagnet bias: the force fades with the square; a magnet's bias force stays.
      const double force_scale =
          bias == AmbBiasSource::kElectromagnet ? (expected / 1.5) * (expected / 1.5) : 1.0;
      EXPECT_NEAR(in.amb[0].force_scale[0], force_scale, 1e-14) << k;
    }
  }
}

TEST(PowerLossLaws, ExponentialIsTodaysFluxDecay) {
  // The default law with an electromagnet bias: the current held, the force by exp(-2t/tau),
  // bit for bit as FluxDecayForceScale gives it (the golden hashes hold the runs).
  ModelParams p = TwoAmbRig(AmbBiasSource::kElectromagnet);
  for (AmbParams& a : p.ambs) a.flux_decay = {true, 2e-3};
  const Model model = BuildModel(p);
  const PowerState power = FailedAtZero(model, 1.5);
  ControlInput in;
  power.Fill(400, &in);
  EXPECT_EQ(in.amb[0].current_A[0], 1.5);
  EXPECT_EQ(in.amb[0].bias_scale[0], 1.0);
  EXPECT_EQ(in.amb[0].force_scale[0], FluxDecayForceScale(model.params.ambs[0], 400 * kStep_s));
  EXPECT_NEAR(in.amb[0].force_scale[0], std::exp(-2.0), 1e-15);  // t = tau
  // With a magnet's bias the current fades as exp(-t/tau) and the force scale stays 1.
  for (AmbParams& a : p.ambs) a.bias_source = AmbBiasSource::kPermanentMagnet;
  const Model pm = BuildModel(p);
  const PowerState pm_power = FailedAtZero(pm, 1.5);
  pm_power.Fill(400, &in);
  EXPECT_NEAR(in.amb[0].current_A[0], 1.5 * std::exp(-1.0), 1e-14);
  EXPECT_EQ(in.amb[0].force_scale[0], 1.0);
}

}  // namespace
}  // namespace ambdrop::amb_power_loss_test
