#include "plant.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ambdrop_truth {

double AmbAxisForce(const AmbRig& a, double coil_plus_A, double coil_minus_A, double u_m) {
  const double g0 = a.nominal_gap_m;
  // The TDBs stop the rotor long before the poles; the law is singular there.
  const double u = std::clamp(u_m, -kAmbLawGapFraction * g0, kAmbLawGapFraction * g0);
  const double k = a.electromagnet_constant_N_m2_per_A2;
  return k * (coil_plus_A * coil_plus_A / ((g0 - u) * (g0 - u)) -
              coil_minus_A * coil_minus_A / ((g0 + u) * (g0 + u)));
}

namespace {

RotorModes ModesOf(const Rig& r) {
  return r.shaft.enabled ? FlexibleRotorModes(r.shaft, HardwareStations(r))
                         : RigidRotorModes(r.rotor);
}

}  // namespace

Plant::Plant(const Rig& rig) : rig_(rig), modes_(ModesOf(rig)) {
  layout_.n = modes_.n;
  std::vector<double> z = HardwareStations(rig);
  z.push_back(rig.rotor.centre_of_mass_m);
  z.push_back(rig.side_pull.position_m);
  z.push_back(rig.unbalance.couple_planes_m[0]);
  z.push_back(rig.unbalance.couple_planes_m[1]);
  for (double station : z) shapes_.emplace_back(station, modes_.AtStation(station));
  for (PlantState* v : {&k1_, &k2_, &k3_, &k4_, &stage_}) *v = ZeroState();
  for (Eigen::VectorXd* v : {&fx_, &fy_, &ax_, &ay_}) *v = Eigen::VectorXd::Zero(modes_.n);
}

const Eigen::RowVectorXd& Plant::Shape(double z_m) const {
  for (const auto& [z, phi] : shapes_) {
    if (z == z_m) return phi;
  }
  // Only a station the rig does not list gets here (tests); computed once, kept.
  const_cast<Plant*>(this)->shapes_.emplace_back(z_m, modes_.AtStation(z_m));
  return shapes_.back().second;
}

std::array<double, 2> Plant::AtStation(const PlantState& y, double z_m) const {
  const Eigen::RowVectorXd& phi = Shape(z_m);
  const int n = layout_.n;
  return {phi.dot(y.segment(layout_.qx(0), n)), phi.dot(y.segment(layout_.qy(0), n))};
}

std::array<double, 2> Plant::VelocityAtStation(const PlantState& y, double z_m) const {
  const Eigen::RowVectorXd& phi = Shape(z_m);
  const int n = layout_.n;
  return {phi.dot(y.segment(layout_.vx(0), n)), phi.dot(y.segment(layout_.vy(0), n))};
}

void Plant::Derivative(const PlantState& y, const PlantInput& in, PlantState* rate,
                       PlantOutputs* out) const {
  const Rig& r = rig_;
  const StateLayout& L = layout_;
  const int n = L.n;
  rate->setZero(layout_.size());
  fx_.setZero();
  fy_.setZero();
  const auto apply = [&](double z, double f_x, double f_y) {
    const Eigen::RowVectorXd& phi = Shape(z);
    fx_ += f_x * phi.transpose();
    fy_ += f_y * phi.transpose();
  };

  // AMBs: seed 003 Eq. (2) per axis; the amplifier's current loop while it is powered.
  const double w_amp = 2.0 * std::numbers::pi * r.controller.amplifier.bandwidth_Hz;
  const double slew = r.controller.amplifier.slew_rate_A_per_s;
  for (int a = 0; a < 2; ++a) {
    const AmbRig& amb = r.ambs[a];
    const auto u = AtStation(y, amb.position_m);
    for (int axis = 0; axis < 2; ++axis) {
      double plus = in.coil_A[a][axis][0], minus = in.coil_A[a][axis][1];
      if (in.amplifier_on) {
        const double i = y(L.coil(a, axis));
        plus = amb.bias_current_A + i;
        minus = amb.bias_current_A - i;
        double di = w_amp * (in.command_A[a][axis] - i);
        if (slew > 0.0) di = std::clamp(di, -slew, slew);
        (*rate)(L.coil(a, axis)) = di;
      }
      out->amb_force_N[a][axis] = AmbAxisForce(amb, plus, minus, u[axis]);
      out->amb_displacement_m[a][axis] = u[axis];
    }
    apply(amb.position_m, out->amb_force_N[a][0], out->amb_force_N[a][1]);
  }

  // TDBs: the journal relative to the TDB centre (misalignment plus the housing's deflection).
  const double spin = y(L.spin());
  double spin_torque = 0.0;
  for (int t = 0; t < 2; ++t) {
    const TdbRig& tdb = r.tdbs[t];
    const int h = L.housing(t);
    const auto p = AtStation(y, tdb.position_m);
    const auto v = VelocityAtStation(y, tdb.position_m);
    JournalAtTdb j;
    j.x_m = p[0] - tdb.misalignment_m[0] - y(h + 0);
    j.y_m = p[1] - tdb.misalignment_m[1] - y(h + 1);
    j.vx_m_s = v[0] - y(h + 2);
    j.vy_m_s = v[1] - y(h + 3);
    j.spin_rad_s = spin;
    const ContactForces c = EvaluateContact(tdb, j, y(L.race(t)));
    out->tdb[t] = c;
    out->support_N[t] = {-c.fx_N, -c.fy_N};
    apply(tdb.position_m, c.fx_N, c.fy_N);
    spin_torque += c.spin_torque_N_m;
    (*rate)(L.race(t)) = c.race_acceleration_rad_s2;
    if (tdb.four_dof.enabled) {
      // Jarroux 2019 models #2/#3 (Sec. 4.1): the inner race takes the contact's reaction,
      // its weight and the bearing (linearised, Sec. 3.1); the outer race the bearing, its
      // weight and the ribbon (Eq. (4), or Eq. (1)-(3) with the Dahl ribbon).
      const FourDofMountRig& m = tdb.four_dof;
      const int o = L.outer_race(t);
      const double bx = m.bearing_stiffness_N_per_m * (y(h + 0) - y(o + 0)) +
                        m.bearing_damping_N_s_per_m * (y(h + 2) - y(o + 2));
      const double by = m.bearing_stiffness_N_per_m * (y(h + 1) - y(o + 1)) +
                        m.bearing_damping_N_s_per_m * (y(h + 3) - y(o + 3));
      std::array<double, 2> ribbon{};
      if (tdb.dahl.enabled) {
        ribbon = {y(h + 4), y(h + 5)};
        (*rate)(h + 4) = DahlForceRate(tdb.dahl, y(h + 4), y(o + 0), y(o + 2));
        (*rate)(h + 5) = DahlForceRate(tdb.dahl, y(h + 5), y(o + 1), y(o + 3));
      } else {
        ribbon = {m.ribbon_stiffness_N_per_m * y(o + 0) + m.ribbon_damping_N_s_per_m * y(o + 2),
                  m.ribbon_stiffness_N_per_m * y(o + 1) + m.ribbon_damping_N_s_per_m * y(o + 3)};
      }
      out->support_N[t] = ribbon;
      (*rate)(h + 0) = y(h + 2);
      (*rate)(h + 1) = y(h + 3);
      (*rate)(h + 2) = (-c.fx_N - bx) / m.inner_race_mass_kg;
      (*rate)(h + 3) = (-c.fy_N - by) / m.inner_race_mass_kg - r.gravity_m_s2;
      (*rate)(o + 0) = y(o + 2);
      (*rate)(o + 1) = y(o + 3);
      (*rate)(o + 2) = (bx - ribbon[0]) / m.outer_race_mass_kg;
      (*rate)(o + 3) = (by - ribbon[1]) / m.outer_race_mass_kg - r.gravity_m_s2;
    } else if (tdb.dahl.enabled) {
      // The housing takes the contact's reaction, its weight and the ribbon (Jarroux 2019
      // Eq. (1)-(3)) per axis.
      const DahlRibbonRig& d = tdb.dahl;
      (*rate)(h + 0) = y(h + 2);
      (*rate)(h + 1) = y(h + 3);
      (*rate)(h + 2) = (-c.fx_N - y(h + 4)) / d.housing_mass_kg;
      (*rate)(h + 3) = (-c.fy_N - y(h + 5)) / d.housing_mass_kg - r.gravity_m_s2;
      (*rate)(h + 4) = DahlForceRate(d, y(h + 4), y(h + 0), y(h + 2));
      (*rate)(h + 5) = DahlForceRate(d, y(h + 5), y(h + 1), y(h + 3));
    }
  }
  double spin_rate = 0.0;
  if (!in.motor_on) {
    const CoastDownRig& cd = r.coast_down;
    const double loss = cd.viscous_N_m_s * spin + cd.windage_N_m_s2 * spin * std::abs(spin);
    spin_rate = (spin_torque - loss) / r.rotor.polar_inertia_kg_m2;
  }
  (*rate)(L.spin_angle()) = spin;
  (*rate)(L.spin()) = spin_rate;

  // Unbalance: static at the centre of mass, couple in two planes half a turn apart.
  const double zc = r.rotor.centre_of_mass_m;
  const auto unbalance = [&](double me, double phase, double z) {
    const double angle = y(L.spin_angle()) + phase;
    const double c = std::cos(angle), s = std::sin(angle);
    apply(z, me * (spin * spin * c + spin_rate * s), me * (spin * spin * s - spin_rate * c));
  };
  const UnbalanceRig& u = r.unbalance;
  if (u.static_kg_m != 0.0) unbalance(u.static_kg_m, u.static_phase_rad, zc);
  if (u.couple_kg_m != 0.0) {
    unbalance(u.couple_kg_m, u.couple_phase_rad, u.couple_planes_m[0]);
    unbalance(u.couple_kg_m, u.couple_phase_rad + std::numbers::pi, u.couple_planes_m[1]);
  }
  if (r.side_pull.force_N[0] != 0.0 || r.side_pull.force_N[1] != 0.0) {
    apply(r.side_pull.position_m, r.side_pull.force_N[0], r.side_pull.force_N[1]);
  }

  // The rotor in its two planes (rotor_modes.hpp).
  const RotorModes& m = modes_;
  const auto qx = y.segment(L.qx(0), n), qy = y.segment(L.qy(0), n);
  const auto vx = y.segment(L.vx(0), n), vy = y.segment(L.vy(0), n);
  fx_.noalias() -= m.damping * vx;
  fx_.noalias() -= m.stiffness * qx;
  fx_.noalias() -= m.gyroscopic * (spin * vy + spin_rate * qy);
  fy_.noalias() -= m.damping * vy;
  fy_.noalias() -= m.stiffness * qy;
  fy_.noalias() += m.gyroscopic * (spin * vx + spin_rate * qx);
  ax_ = fx_.cwiseQuotient(m.mass);
  ay_ = fy_.cwiseQuotient(m.mass) - r.gravity_m_s2 * m.gravity_acceleration;
  rate->segment(L.qx(0), n) = vx;
  rate->segment(L.qy(0), n) = vy;
  rate->segment(L.vx(0), n) = ax_;
  rate->segment(L.vy(0), n) = ay_;

  // The acquisition chain's first-order low-pass on every sensor axis.
  const double tau = r.acquisition.lag_time_constant_s;
  for (int s = 0; s < 2; ++s) {
    const auto disp = AtStation(y, r.sensors[s].position_m);
    out->sensor_displacement_m[s] = disp;
    if (tau > 0.0) {
      for (int axis = 0; axis < 2; ++axis) {
        (*rate)(L.lag(s, axis)) = (disp[axis] - y(L.lag(s, axis))) / tau;
      }
    }
  }
}

void Plant::Step(PlantState* y, const PlantInput& in) const {
  const double h = rig_.step_s;
  Derivative(*y, in, &k1_, &scratch_);
  stage_ = *y + 0.5 * h * k1_;
  Derivative(stage_, in, &k2_, &scratch_);
  stage_ = *y + 0.5 * h * k2_;
  Derivative(stage_, in, &k3_, &scratch_);
  stage_ = *y + h * k3_;
  Derivative(stage_, in, &k4_, &scratch_);
  *y += (h / 6.0) * (k1_ + 2.0 * k2_ + 2.0 * k3_ + k4_);
}

double Plant::Energy(const PlantState& y) const {
  const Rig& r = rig_;
  const StateLayout& L = layout_;
  const int n = L.n;
  const auto qx = y.segment(L.qx(0), n), qy = y.segment(L.qy(0), n);
  const auto vx = y.segment(L.vx(0), n), vy = y.segment(L.vy(0), n);
  const RotorModes& m = modes_;
  double e = 0.5 * (vx.dot(m.mass.cwiseProduct(vx)) + vy.dot(m.mass.cwiseProduct(vy))) +
             0.5 * (qx.dot(m.stiffness * qx) + qy.dot(m.stiffness * qy)) +
             0.5 * r.rotor.polar_inertia_kg_m2 * y(L.spin()) * y(L.spin()) +
             r.gravity_m_s2 * m.weight_share.dot(qy);
  for (int t = 0; t < 2; ++t) {
    const TdbRig& tdb = r.tdbs[t];
    e += 0.5 * tdb.race_inertia_kg_m2 * y(L.race(t)) * y(L.race(t));
    const int h = L.housing(t);
    const bool mounted = tdb.four_dof.enabled;
    const auto p = AtStation(y, tdb.position_m);
    const double dx = p[0] - tdb.misalignment_m[0] - (mounted ? y(h + 0) : 0.0);
    const double dy = p[1] - tdb.misalignment_m[1] - (mounted ? y(h + 1) : 0.0);
    const double penetration = std::sqrt(dx * dx + dy * dy) - tdb.clearance_m;
    if (penetration > 0.0) {
      const double n = tdb.contact_law == ContactLaw::kLinear ? 1.0 : tdb.contact_exponent;
      e += tdb.contact_stiffness * std::pow(penetration, n + 1.0) / (n + 1.0);
    }
    if (mounted) {
      // The races' kinetic and gravity energy, the bearing's and the Kelvin-Voigt ribbon's.
      const FourDofMountRig& m = tdb.four_dof;
      const int o = L.outer_race(t);
      const auto square = [](double a, double b) { return a * a + b * b; };
      e += 0.5 * m.inner_race_mass_kg * square(y(h + 2), y(h + 3)) +
           0.5 * m.outer_race_mass_kg * square(y(o + 2), y(o + 3)) +
           r.gravity_m_s2 * (m.inner_race_mass_kg * y(h + 1) + m.outer_race_mass_kg * y(o + 1)) +
           0.5 * m.bearing_stiffness_N_per_m * square(y(h + 0) - y(o + 0), y(h + 1) - y(o + 1)) +
           0.5 * m.ribbon_stiffness_N_per_m * square(y(o + 0), y(o + 1));
    }
  }
  return e;
}

}  // namespace ambdrop_truth
