#include "plant.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ambdrop_truth {

double AmbAxisForce(const AmbRig& a, double coil_plus_A, double coil_minus_A, double u_m) {
  const double g0 = a.nominal_gap_m;
  // The TDBs stop the rotor long before the poles; the law is singular there.
  const double u = std::clamp(u_m, -0.95 * g0, 0.95 * g0);
  const double k = a.electromagnet_constant_N_m2_per_A2;
  return k * (coil_plus_A * coil_plus_A / ((g0 - u) * (g0 - u)) -
              coil_minus_A * coil_minus_A / ((g0 + u) * (g0 + u)));
}

Plant::Plant(const Rig& rig) : rig_(rig) {
  k1_.setZero();
  k2_.setZero();
  k3_.setZero();
  k4_.setZero();
  stage_.setZero();
}

std::array<double, 2> Plant::AtStation(const PlantState& y, double z_m) const {
  const double d = z_m - rig_.rotor.centre_of_mass_m;
  return {y(kX) + d * y(kThy), y(kY) - d * y(kThx)};
}

std::array<double, 2> Plant::VelocityAtStation(const PlantState& y, double z_m) const {
  const double d = z_m - rig_.rotor.centre_of_mass_m;
  return {y(kVx) + d * y(kWy), y(kVy) - d * y(kWx)};
}

void Plant::Derivative(const PlantState& y, const PlantInput& in, PlantState* rate,
                       PlantOutputs* out) const {
  const Rig& r = rig_;
  const double zc = r.rotor.centre_of_mass_m;
  rate->setZero();
  double fx = 0.0, fy = 0.0, mx = 0.0, my = 0.0;
  const auto apply = [&](double z, double f_x, double f_y) {
    const double d = z - zc;
    fx += f_x;
    fy += f_y;
    mx += -d * f_y;
    my += d * f_x;
  };

  // AMBs: seed 003 Eq. (2) per axis.
  for (int a = 0; a < 2; ++a) {
    const AmbRig& amb = r.ambs[a];
    const auto u = AtStation(y, amb.position_m);
    for (int axis = 0; axis < 2; ++axis) {
      out->amb_force_N[a][axis] =
          AmbAxisForce(amb, in.coil_A[a][axis][0], in.coil_A[a][axis][1], u[axis]);
    }
    apply(amb.position_m, out->amb_force_N[a][0], out->amb_force_N[a][1]);
  }

  // TDBs: the journal relative to the TDB centre (misalignment plus the housing's deflection).
  const double spin = y(kSpin);
  double spin_torque = 0.0;
  for (int t = 0; t < 2; ++t) {
    const TdbRig& tdb = r.tdbs[t];
    const int h = kHousing + 6 * t;
    const auto p = AtStation(y, tdb.position_m);
    const auto v = VelocityAtStation(y, tdb.position_m);
    JournalAtTdb j;
    j.x_m = p[0] - tdb.misalignment_m[0] - y(h + 0);
    j.y_m = p[1] - tdb.misalignment_m[1] - y(h + 1);
    j.vx_m_s = v[0] - y(h + 2);
    j.vy_m_s = v[1] - y(h + 3);
    j.spin_rad_s = spin;
    const ContactForces c = EvaluateContact(tdb, j, y(kRace + t));
    out->tdb[t] = c;
    apply(tdb.position_m, c.fx_N, c.fy_N);
    spin_torque += c.spin_torque_N_m;
    (*rate)(kRace + t) = c.race_acceleration_rad_s2;
    if (tdb.dahl.enabled) {
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
  const double spin_rate = in.motor_on ? 0.0 : spin_torque / r.rotor.polar_inertia_kg_m2;
  (*rate)(kSpinAngle) = spin;
  (*rate)(kSpin) = spin_rate;

  // Unbalance: static at the centre of mass, couple in two planes half a turn apart.
  const auto unbalance = [&](double me, double phase, double z) {
    const double angle = y(kSpinAngle) + phase;
    const double c = std::cos(angle), s = std::sin(angle);
    apply(z, me * (spin * spin * c + spin_rate * s), me * (spin * spin * s - spin_rate * c));
  };
  const UnbalanceRig& u = r.unbalance;
  if (u.static_kg_m != 0.0) unbalance(u.static_kg_m, u.static_phase_rad, zc);
  if (u.couple_kg_m != 0.0) {
    unbalance(u.couple_kg_m, u.couple_phase_rad, u.couple_planes_m[0]);
    unbalance(u.couple_kg_m, u.couple_phase_rad + std::numbers::pi, u.couple_planes_m[1]);
  }
  apply(r.side_pull.position_m, r.side_pull.force_N[0], r.side_pull.force_N[1]);

  // Rigid rotor with gyroscopic moments.
  const double m = r.rotor.mass_kg;
  const double it = r.rotor.transverse_inertia_kg_m2;
  const double ip = r.rotor.polar_inertia_kg_m2;
  (*rate)(kX) = y(kVx);
  (*rate)(kY) = y(kVy);
  (*rate)(kThx) = y(kWx);
  (*rate)(kThy) = y(kWy);
  (*rate)(kVx) = fx / m;
  (*rate)(kVy) = fy / m - r.gravity_m_s2;
  (*rate)(kWx) = (mx - ip * (spin_rate * y(kThy) + spin * y(kWy))) / it;
  (*rate)(kWy) = (my + ip * (spin_rate * y(kThx) + spin * y(kWx))) / it;

  // The acquisition chain's first-order low-pass on every sensor axis.
  const double tau = r.acquisition.lag_time_constant_s;
  for (int s = 0; s < 2; ++s) {
    const auto disp = AtStation(y, r.sensors[s].position_m);
    out->sensor_displacement_m[s] = disp;
    if (tau > 0.0) {
      for (int axis = 0; axis < 2; ++axis) {
        (*rate)(kLag + 2 * s + axis) = (disp[axis] - y(kLag + 2 * s + axis)) / tau;
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
  double e = 0.5 * r.rotor.mass_kg * (y(kVx) * y(kVx) + y(kVy) * y(kVy)) +
             0.5 * r.rotor.transverse_inertia_kg_m2 * (y(kWx) * y(kWx) + y(kWy) * y(kWy)) +
             0.5 * r.rotor.polar_inertia_kg_m2 * y(kSpin) * y(kSpin) +
             r.rotor.mass_kg * r.gravity_m_s2 * y(kY);
  for (int t = 0; t < 2; ++t) {
    const TdbRig& tdb = r.tdbs[t];
    e += 0.5 * tdb.race_inertia_kg_m2 * y(kRace + t) * y(kRace + t);
    const auto p = AtStation(y, tdb.position_m);
    const double dx = p[0] - tdb.misalignment_m[0];
    const double dy = p[1] - tdb.misalignment_m[1];
    const double penetration = std::sqrt(dx * dx + dy * dy) - tdb.clearance_m;
    if (penetration > 0.0 && tdb.contact_law == ContactLaw::kLinear) {
      e += 0.5 * tdb.contact_stiffness * penetration * penetration;
    }
  }
  return e;
}

}  // namespace ambdrop_truth
