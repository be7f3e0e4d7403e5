#pragma once
// The equations of motion evaluated by bending plane with the plane size H fixed at compile
// time, so every product is a small unrolled kernel. Internal to the simulator.
#include <algorithm>
#include <array>
#include <cmath>

#include "rt_core/amb_force.hpp"
#include "rt_core/coast_down.hpp"
#include "rt_core/control_input.hpp"
#include "rt_core/model.hpp"
#include "rt_core/touchdown_bearing.hpp"

namespace ambdrop::detail {

// Flattened: GCC otherwise leaves the 6x6 gyroscopic products as out-of-line calls (6 % of the
// Dahl step). Inlining changes no rounding (contraction is off), so the bits stay the same.
// Not in the sanitizer builds: there, flattening every instrumented call into each plane size's
// kernel took GCC over 20 minutes and 1.8 GB for simulator.cpp alone.
#ifdef AMBDROP_NO_FLATTEN
#define AMBDROP_FLATTEN
#else
#define AMBDROP_FLATTEN [[gnu::flatten]]
#endif
template <int H>
AMBDROP_FLATTEN void PlaneDerivative(const Model& m, const StateVector& y,
                                     const ControlInput& input, StateVector* rate,
                                     std::array<TdbForce, kMaxTdbs>* tdb_out) noexcept {
  using Vec = Eigen::Matrix<double, H, 1>;
  using Mat = Eigen::Matrix<double, H, H>;
  const auto mat = [](const PlaneMatrix& a) { return Eigen::Map<const Mat>(a.data()); };
  // Linear supports as station forces, f = -(k u + c u').
  const auto support = [&](const PlaneSupport& s, const auto& qx, const auto& qy, const auto& vx,
                           const auto& vy, Vec* fx, Vec* fy) {
    const auto sx = Eigen::Map<const Vec>(s.shape.sx.data());
    const auto sy = Eigen::Map<const Vec>(s.shape.sy.data());
    *fx -= (s.stiffness_x_N_per_m * sx.dot(qx) + s.damping_x_N_s_per_m * sx.dot(vx)) * sx;
    *fy -= (s.stiffness_y_N_per_m * sy.dot(qy) + s.damping_y_N_s_per_m * sy.dot(vy)) * sy;
  };
  const auto vec = [](const PlaneVector& a) { return Eigen::Map<const Vec>(a.data()); };
  const PlaneModel& p = m.planes;
  const double* yd = y.data();
  const Eigen::Map<const Vec> qx(yd), qy(yd + H), vx(yd + 2 * H), vy(yd + 3 * H);
  const double spin = y(4 * H);
  const double angle = y(4 * H + 1);

  // Generalized forces: gravity, linear supports, then the AMBs scaled by their drive.
  Vec fx = vec(p.gravity_x);
  Vec fy = vec(p.gravity_y);
  for (const PlaneSupport& b : p.bearings) support(b, qx, qy, vx, vy, &fx, &fy);
  for (std::size_t a = 0; a < p.ambs.size(); ++a) {
    const PlaneAmb& amb = p.ambs[a];
    const AmbDrive& drive = input.amb[a];
    if (drive.force_scale[0] == 0.0 && drive.force_scale[1] == 0.0) continue;
    const auto sx = vec(amb.shape.sx);
    const auto sy = vec(amb.shape.sy);
    const double ux = sx.dot(qx);
    const double uy = sy.dot(qy);
    double f[2] = {0.0, 0.0};
    switch (amb.params.law) {
      case AmbForceLaw::kEquivalent: {
        const double k = amb.params.stiffness_N_per_m;
        const double c = amb.params.damping_N_s_per_m;
        f[0] = amb.bias_x_N - k * ux - c * sx.dot(vx);
        f[1] = amb.bias_y_N - k * uy - c * sy.dot(vy);
        break;
      }
      case AmbForceLaw::kLinearisedCurrents: {
        // ki = 4 k I0 / g0^2 and ks = 4 k I0^2 / g0^3 (seed 003, the electromagnet law
        // linearised at the centre): a fading bias scales ki by b and ks by b^2. b = 1 is exact.
        const double ki = amb.params.current_gain_N_per_A;
        const double ks = amb.params.position_gain_N_per_m;
        const double bx = drive.bias_scale[0];
        const double by = drive.bias_scale[1];
        f[0] =
            (ki * bx) * std::clamp(drive.current_A[0], -amb.current_limit_A, amb.current_limit_A) +
            (ks * (bx * bx)) * ux;
        f[1] =
            (ki * by) * std::clamp(drive.current_A[1], -amb.current_limit_A, amb.current_limit_A) +
            (ks * (by * by)) * uy;
        break;
      }
      case AmbForceLaw::kElectromagnet: {
        const ElectromagnetParams& e = amb.params.electromagnet;
        const double lim = amb.current_limit_A;
        f[0] = ElectromagnetForce(
            amb.electromagnet_constant, e.nominal_gap_m, e.bias_current_A * drive.bias_scale[0],
            std::clamp(drive.current_A[0], -lim, lim), ux, amb.max_coil_force_N);
        f[1] = ElectromagnetForce(
            amb.electromagnet_constant, e.nominal_gap_m, e.bias_current_A * drive.bias_scale[1],
            std::clamp(drive.current_A[1], -lim, lim), uy, amb.max_coil_force_N);
        break;
      }
    }
    fx += (drive.force_scale[0] * f[0]) * sx;
    fy += (drive.force_scale[1] * f[1]) * sy;
  }

  // Touchdown bearings: journal motion at each TDB plane → contact forces and race rates.
  double torque = 0.0;
  for (std::size_t i = 0; i < m.tdbs.size(); ++i) {
    const auto sx = vec(p.tdbs[i].sx);
    const auto sy = vec(p.tdbs[i].sy);
    const JournalMotion journal{sx.dot(qx), sy.dot(qy), sx.dot(vx), sy.dot(vy), spin};
    TdbForce& out = (*tdb_out)[i];
    const int offset = m.tdb_state_offset[i];
    m.tdbs[i]->Evaluate(journal, yd + offset, rate->data() + offset, &out);
    fx += out.fx_N * sx;
    fy += out.fy_N * sy;
    torque += out.torque_on_rotor_N_m;
  }

  // Spin: the motor holds the speed while powered; afterwards friction and, if enabled, the
  // coast-down losses act (Ip W' = T). The branch leaves the default's sum untouched.
  const CoastDownParams& coast = m.params.rotor.coast_down;
  if (coast.enabled && !input.motor_on) torque += CoastDownTorque(coast, spin);
  const double spin_rate = input.motor_on ? 0.0 : torque / m.rotor.polar_inertia_kg_m2;

  // Unbalance, constant- and variable-speed terms (Jarroux 2019 Eq. (13), F_mu).
  for (std::size_t u = 0; u < m.params.unbalances.size(); ++u) {
    const UnbalanceParams& ub = m.params.unbalances[u];
    if (!ub.enabled) continue;
    const double me = ub.mass_kg * ub.eccentricity_m;
    const double c = std::cos(angle + ub.phase_rad);
    const double s = std::sin(angle + ub.phase_rad);
    fx += (me * (spin * spin * c + spin_rate * s)) * vec(p.unbalances[u].sx);
    fy += (me * (spin * spin * s - spin_rate * c)) * vec(p.unbalances[u].sy);
  }

  // q'' = F - C q' - K q - G (W q' + W' q)   (Jarroux 2019 Eq. (13), M = I), plane by plane,
  // with the modal C and K diagonal.
  const Vec gx = spin * vx + spin_rate * qx;
  const Vec gy = spin * vy + spin_rate * qy;
  Eigen::Map<Vec> ax(rate->data() + 2 * H), ay(rate->data() + 3 * H);
  ax = fx - vec(p.modal_damping_x).cwiseProduct(vx) - vec(p.modal_stiffness_x).cwiseProduct(qx);
  ax.noalias() -= mat(p.gyroscopic_xy) * gy;
  ay = fy - vec(p.modal_damping_y).cwiseProduct(vy) - vec(p.modal_stiffness_y).cwiseProduct(qy);
  ay.noalias() -= mat(p.gyroscopic_yx) * gx;
  Eigen::Map<Vec>(rate->data()) = vx;
  Eigen::Map<Vec>(rate->data() + H) = vy;
  (*rate)(4 * H) = spin_rate;
  (*rate)(4 * H + 1) = spin;
}

}  // namespace ambdrop::detail
