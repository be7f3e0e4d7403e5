#include "drop_run.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <numbers>

#include <fmt/core.h>

#include "firmware_controller.hpp"
#include "noise.hpp"
#include "pid_axis.hpp"

namespace ambdrop_truth {

namespace {

/// The control current that makes an AMB axis pull `force_N` at displacement u (Newton on
/// seed 003 Eq. (2), which is quadratic in it).
double CurrentForForce(const AmbRig& a, double force_N, double u_m) {
  const double g0 = a.nominal_gap_m;
  const double i0 = a.bias_current_A;
  double i = force_N * g0 * g0 / (4.0 * a.electromagnet_constant_N_m2_per_A2 * i0);
  for (int n = 0; n < 50; ++n) {
    const double f = AmbAxisForce(a, i0 + i, i0 - i, u_m) - force_N;
    const double h = 1e-6;
    const double slope = (AmbAxisForce(a, i0 + i + h, i0 - i - h, u_m) -
                          AmbAxisForce(a, i0 + i - h, i0 - i + h, u_m)) /
                         (2.0 * h);
    i -= f / slope;
  }
  return i;
}

long Steps(double seconds, double step_s) {
  return std::lround(seconds / step_s);
}

double Quantised(double value, double q) {
  return q > 0.0 ? std::round(value / q) * q : value;
}

}  // namespace

double ControlCurrentLimit(const AmbRig& a) {
  if (a.permanent_magnet_bias) return std::min(a.bias_current_A, a.coil_current_limit_A);
  return std::min(a.bias_current_A, a.coil_current_limit_A - a.bias_current_A);
}

std::array<std::array<double, 2>, 2> StaticAmbForces(const Rig& rig) {
  // Sum of forces and sum of moments about the centre of mass zero, per axis.
  const double zc = rig.rotor.centre_of_mass_m;
  std::array<double, 2> load{rig.side_pull.force_N[0],
                             rig.side_pull.force_N[1] - rig.rotor.mass_kg * rig.gravity_m_s2};
  std::array<double, 2> load_moment{(rig.side_pull.position_m - zc) * rig.side_pull.force_N[0],
                                    (rig.side_pull.position_m - zc) * rig.side_pull.force_N[1]};
  const double a1 = rig.ambs[0].position_m - zc;
  const double a2 = rig.ambs[1].position_m - zc;
  std::array<std::array<double, 2>, 2> force{};
  for (int axis = 0; axis < 2; ++axis) {
    force[0][axis] = (-load_moment[axis] + a2 * load[axis]) / (a1 - a2);
    force[1][axis] = -load[axis] - force[0][axis];
  }
  return force;
}

PlantState EquilibriumState(const Rig& rig, std::array<std::array<double, 2>, 2>* held_A) {
  const Plant plant(rig);
  const StateLayout& L = plant.layout();
  PlantState y = plant.ZeroState();
  y(L.spin()) = rig.spin_speed_rad_s;
  for (int t = 0; t < 2; ++t) {
    const TdbRig& tdb = rig.tdbs[t];
    if (tdb.four_dof.enabled) {
      // The races sag on the bearing and the ribbon under their weight; a Dahl ribbon starts
      // undeflected, carrying it.
      const FourDofMountRig& m = tdb.four_dof;
      const double weight_N = (m.inner_race_mass_kg + m.outer_race_mass_kg) * rig.gravity_m_s2;
      const double outer_y = tdb.dahl.enabled ? 0.0 : -weight_N / m.ribbon_stiffness_N_per_m;
      y(L.outer_race(t) + 1) = outer_y;
      y(L.housing(t) + 1) =
          outer_y - m.inner_race_mass_kg * rig.gravity_m_s2 / m.bearing_stiffness_N_per_m;
      if (tdb.dahl.enabled) y(L.housing(t) + 5) = -weight_N;
    } else if (tdb.dahl.enabled) {
      // The ribbon holds the housing's weight.
      y(L.housing(t) + 5) = -tdb.dahl.housing_mass_kg * rig.gravity_m_s2;
    }
  }
  if (!rig.shaft.enabled) {
    // The set point: each sensor reads zero, so its plane sits at -offset/gain. The rigid
    // coordinates per plane are the displacement at the centre of mass and the slope.
    const double zc = rig.rotor.centre_of_mass_m;
    const double d1 = rig.sensors[0].position_m - zc;
    const double d2 = rig.sensors[1].position_m - zc;
    for (int axis = 0; axis < 2; ++axis) {
      std::array<double, 2> at{};
      for (int s = 0; s < 2; ++s) {
        at[s] = -rig.sensors[s].offset_m[axis] / rig.sensors[s].gain[axis];
        y(L.lag(s, axis)) = at[s];
      }
      const double slope = (at[0] - at[1]) / (d1 - d2);
      const int q = axis == 0 ? L.qx(0) : L.qy(0);
      y(q + 1) = slope;
      y(q) = at[0] - d1 * slope;
    }
  }
  // A flexible rotor starts centred and undeformed; its run settles it (acquisition.settle_s).
  const auto force = StaticAmbForces(rig);
  for (int a = 0; a < 2; ++a) {
    for (int axis = 0; axis < 2; ++axis) {
      const double u = plant.AtStation(y, rig.ambs[a].position_m)[axis];
      (*held_A)[a][axis] = CurrentForForce(rig.ambs[a], force[a][axis], u);
      y(L.coil(a, axis)) = (*held_A)[a][axis];
    }
  }
  return y;
}

namespace {

/// The coil currents (plus, minus) and the control current of an AMB axis `since` seconds
/// after its power failed, from the control current c0 it carried then.
struct CoilCurrents {
  double plus = 0.0, minus = 0.0, control = 0.0;
};
CoilCurrents AfterPowerLoss(const AmbRig& amb, const PowerLossRig& p, double c0, double since) {
  const double i0 = amb.bias_current_A;
  const auto ramp = [&](double c) {
    return std::copysign(std::max(std::abs(c) - p.slew_rate_A_per_s * since, 0.0), c);
  };
  double scale = 1.0;
  switch (p.form) {
    case FluxDecayForm::kInstant:
      scale = 0.0;
      break;
    case FluxDecayForm::kFormA:
      scale = std::exp(-since / p.time_constant_s);
      break;
    case FluxDecayForm::kFormB:
      // Force as exp(-t/tau): the currents fall at half that rate.
      scale = since < p.hold_time_s
                  ? 1.0
                  : std::exp(-(since - p.hold_time_s) / (2.0 * p.time_constant_s));
      break;
    case FluxDecayForm::kRamp:
      if (amb.permanent_magnet_bias) {
        const double c = ramp(c0);
        return {i0 + c, i0 - c, c};
      } else {
        const double plus = ramp(i0 + c0), minus = ramp(i0 - c0);
        return {plus, minus, 0.5 * (plus - minus)};
      }
  }
  if (amb.permanent_magnet_bias) return {i0 + c0 * scale, i0 - c0 * scale, c0 * scale};
  return {(i0 + c0) * scale, (i0 - c0) * scale, c0 * scale};
}

}  // namespace

RunResult RunDrop(const Rig& rig, std::uint64_t seed, const RunOptions& options) {
  const double h = rig.step_s;
  const long total = Steps(rig.acquisition.record_length_s, h);
  const long control_every = std::max(1L, Steps(1.0 / rig.controller.rate_Hz, h));
  const long sample_every = std::max(1L, Steps(1.0 / rig.acquisition.sample_rate_Hz, h));
  const long compute_delay = Steps(rig.controller.computation_delay_s, h);
  const long lag_delay = Steps(rig.acquisition.lag_delay_s, h);
  const long trigger = Steps(rig.acquisition.trigger_time_s, h);
  const bool lagged = rig.acquisition.lag_time_constant_s > 0.0;
  const bool amplifier = rig.controller.amplifier.enabled;
  // The settling runs whole controller and acquisition periods before the record's t = 0.
  const long period = control_every * sample_every;
  const long settle = (Steps(rig.acquisition.settle_s, h) + period - 1) / period * period;

  Plant plant(rig);
  const StateLayout& L = plant.layout();
  std::array<std::array<double, 2>, 2> held_A{};
  PlantState y = EquilibriumState(rig, &held_A);
  if (!options.start_at_equilibrium) {
    y.head(4 * L.n).setZero();
    for (int s = 0; s < 2; ++s) {
      for (int axis = 0; axis < 2; ++axis) y(L.lag(s, axis)) = 0.0;
    }
    held_A = {};
  }

  // The firmware's feedforward: the current that carries the static load with the rotor
  // centred, f = 4 k I0 i / g0^2 (seed 003 Eq. (2) at u = 0).
  const auto static_force = StaticAmbForces(rig);
  std::array<std::array<PidAxis, 2>, 2> pid;
  std::array<std::array<FirmwareAxis, 2>, 2> firmware;
  for (int a = 0; a < 2; ++a) {
    const AmbRig& amb = rig.ambs[a];
    for (int axis = 0; axis < 2; ++axis) {
      if (rig.controller.firmware) {
        const double ff = static_force[a][axis] * amb.nominal_gap_m * amb.nominal_gap_m /
                          (4.0 * amb.electromagnet_constant_N_m2_per_A2 * amb.bias_current_A);
        firmware[a][axis] = FirmwareAxis(rig.controller, ControlCurrentLimit(amb), ff);
        if (options.start_at_equilibrium) held_A[a][axis] = ff;
      } else {
        pid[a][axis] = PidAxis(rig.controller, ControlCurrentLimit(amb), held_A[a][axis]);
      }
      y(L.coil(a, axis)) = held_A[a][axis];
    }
  }
  // Noise: one stream per channel, so adding a channel does not move the others.
  std::vector<GaussianNoise> noise;
  for (std::uint64_t stream = 0; stream < 24; ++stream) noise.emplace_back(seed, stream);
  // Displacement noise (streams 0..7: the controller's reads, then the record's) may pass the
  // sensor's first-order bandwidth: an AR(1) sequence at each stream's own read period, scaled
  // to keep sigma, started from its stationary law.
  std::array<double, 8> coloured{};
  std::array<bool, 8> coloured_started{};
  const double bandwidth_Hz = rig.acquisition.sensor_noise_bandwidth_Hz;
  const auto draw = [&](int stream, double sigma) {
    if (!options.add_noise || !(sigma > 0.0)) return 0.0;
    if (!(bandwidth_Hz > 0.0) || stream >= 8) return sigma * noise[stream].Normal();
    const double period_s = static_cast<double>(stream < 4 ? control_every : sample_every) * h;
    const double a = std::exp(-2.0 * std::numbers::pi * bandwidth_Hz * period_s);
    double& n = coloured[static_cast<std::size_t>(stream)];
    const double w = noise[stream].Normal();
    n = coloured_started[static_cast<std::size_t>(stream)] ? a * n + std::sqrt(1.0 - a * a) * w : w;
    coloured_started[static_cast<std::size_t>(stream)] = true;
    return sigma * n;
  };

  // The acquisition chain's delay: the (low-passed) sensor signal over the last lag_delay
  // steps; before the start, the start's.
  std::deque<std::array<std::array<double, 2>, 2>> chain;
  std::array<std::array<double, 2>, 2> applied_A = held_A;
  std::deque<std::pair<long, std::array<std::array<double, 2>, 2>>> pending;
  std::array<std::array<double, 2>, 2> current_at_trigger{};

  RunResult result;
  result.rows.reserve(static_cast<std::size_t>(total / sample_every + 1));
  PlantOutputs outputs;
  PlantState rate = plant.ZeroState();
  PlantInput input;
  for (long k = -settle; k <= total; ++k) {
    const double t = static_cast<double>(k) * h;
    // The sensor signal now, and as the chain delivers it.
    std::array<std::array<double, 2>, 2> signal{};
    for (int s = 0; s < 2; ++s) {
      const auto disp = plant.AtStation(y, rig.sensors[s].position_m);
      for (int axis = 0; axis < 2; ++axis) {
        signal[s][axis] = lagged ? y(L.lag(s, axis)) : disp[axis];
      }
    }
    chain.push_back(signal);
    while (static_cast<long>(chain.size()) > lag_delay + 1) chain.pop_front();
    const auto& delivered = chain.front();
    const auto reading = [&](int s, int axis, int stream) {
      const SensorRig& sensor = rig.sensors[s];
      const double v = sensor.gain[axis] * delivered[s][axis] + sensor.offset_m[axis] +
                       draw(stream, rig.acquisition.sensor_noise_m);
      return Quantised(v, rig.acquisition.sensor_quantisation_m);
    };
    // What the record's channels carry: the controller's noise streams (0..3) stay.
    const auto recorded = [&](int stream, double sigma) {
      const double n = draw(stream, sigma);
      return options.exact_record ? 0.0 : n;
    };
    const auto recorded_reading = [&](int s, int axis, int stream) {
      if (!options.exact_record) return reading(s, axis, stream);
      const SensorRig& sensor = rig.sensors[s];
      return sensor.gain[axis] * delivered[s][axis] + sensor.offset_m[axis];
    };

    // The controller keeps running after the power fails (its own supply); its commands reach
    // the coils only while the amplifiers are powered.
    while (!pending.empty() && pending.front().first <= k) {
      applied_A = pending.front().second;
      pending.pop_front();
    }
    if ((k + settle) % control_every == 0) {
      std::array<std::array<double, 2>, 2> command{};
      for (int a = 0; a < 2; ++a) {
        for (int axis = 0; axis < 2; ++axis) {
          const double r = reading(rig.ambs[a].sensor, axis, 2 * a + axis);
          command[a][axis] =
              rig.controller.firmware ? firmware[a][axis].Update(r) : pid[a][axis].Update(r);
        }
      }
      if (compute_delay == 0) {
        applied_A = command;
      } else {
        pending.emplace_back(k + compute_delay, command);
      }
    }

    // Coil currents: the amplifier (or the command) while powered, the power-loss law after.
    const bool powered = k < trigger;
    if (k == trigger) {
      for (int a = 0; a < 2; ++a) {
        for (int axis = 0; axis < 2; ++axis) {
          current_at_trigger[a][axis] = amplifier ? y(L.coil(a, axis)) : applied_A[a][axis];
        }
      }
    }
    std::array<std::array<double, 2>, 2> coil_control{};
    input.amplifier_on = powered && amplifier;
    input.command_A = applied_A;
    for (int a = 0; a < 2; ++a) {
      const AmbRig& amb = rig.ambs[a];
      for (int axis = 0; axis < 2; ++axis) {
        CoilCurrents c;
        if (powered) {
          c.control = amplifier ? y(L.coil(a, axis)) : applied_A[a][axis];
          c.plus = amb.bias_current_A + c.control;
          c.minus = amb.bias_current_A - c.control;
        } else {
          const double since = static_cast<double>(k - trigger) * h;
          c = AfterPowerLoss(amb, rig.power_loss, current_at_trigger[a][axis], since);
        }
        input.coil_A[a][axis] = {c.plus, c.minus};
        coil_control[a][axis] = c.control;
      }
    }
    input.motor_on = powered;

    if (k >= 0 && k % sample_every == 0) {
      plant.Derivative(y, input, &rate, &outputs);
      RecordRow row;
      row.t_s = t;
      for (int s = 0; s < 2; ++s) {
        for (int axis = 0; axis < 2; ++axis) {
          row.displacement_m[s][axis] = recorded_reading(s, axis, 4 + 2 * s + axis);
          row.current_A[s][axis] =
              coil_control[s][axis] + recorded(8 + 2 * s + axis, rig.acquisition.current_noise_A);
          row.command_A[s][axis] = applied_A[s][axis];
        }
      }
      for (int tdb = 0; tdb < 2; ++tdb) {
        row.race_speed_rad_s[tdb] =
            y(L.race(tdb)) + recorded(12 + tdb, rig.acquisition.speed_noise_rpm / kRpmPerRadPerS);
        row.normal_force_N[tdb] =
            outputs.tdb[tdb].normal_N + recorded(15 + tdb, rig.acquisition.force_noise_N);
        // The load cell under the housing reads the force on it, its tare (the races' weight
        // on a 4-DOF mount) removed.
        const FourDofMountRig& mount = rig.tdbs[tdb].four_dof;
        const double tare_y =
            mount.enabled
                ? -(mount.inner_race_mass_kg + mount.outer_race_mass_kg) * rig.gravity_m_s2
                : 0.0;
        row.support_force_N[tdb][0] =
            outputs.support_N[tdb][0] + recorded(17 + 2 * tdb, rig.acquisition.force_noise_N);
        row.support_force_N[tdb][1] = outputs.support_N[tdb][1] - tare_y +
                                      recorded(18 + 2 * tdb, rig.acquisition.force_noise_N);
      }
      row.rotor_speed_rad_s =
          y(L.spin()) + recorded(14, rig.acquisition.speed_noise_rpm / kRpmPerRadPerS);
      result.rows.push_back(row);
      for (int a = 0; a < 2 && result.left_physics.empty(); ++a) {
        const double gap_m = rig.ambs[a].nominal_gap_m;
        const std::array<double, 2>& u = outputs.amb_displacement_m[a];
        if (std::max(std::abs(u[0]), std::abs(u[1])) > kAmbLawGapFraction * gap_m) {
          result.left_physics = fmt::format(
              "the rotor reached AMB {}'s poles at {:.4f} s ({:.0f} um on x, {:.0f} um on y; air "
              "gap {:.0f} um): its law holds only inside the gap and no pole strike is modelled, "
              "so this is no drop onto the TDBs",
              rig.ambs[a].name, t, 1e6 * u[0], 1e6 * u[1], 1e6 * gap_m);
        }
      }
    }
    if (k == total) break;
    plant.Step(&y, input);
    if (options.on_step && k >= 0) options.on_step(t + h, y);
    if (!y.allFinite()) {
      result.finite = false;
      break;
    }
  }
  return result;
}

}  // namespace ambdrop_truth
