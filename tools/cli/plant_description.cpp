#include "tools/cli/plant_description.hpp"

#include <cmath>
#include <limits>

#include "controller_if/loop/hil_session.hpp"
#include "io/files/json_writer.hpp"
#include "rt_core/amb_force.hpp"

namespace ambdrop {
namespace {

const char* LawName(AmbForceLaw law) {
  switch (law) {
    case AmbForceLaw::kEquivalent:
      return "equivalent";
    case AmbForceLaw::kLinearisedCurrents:
      return "linearised_currents";
    case AmbForceLaw::kElectromagnet:
      break;
  }
  return "electromagnet";
}

const char* PowerLossName(const FluxDecayParams& d) {
  if (!d.enabled) return "instant";
  switch (d.current_law) {
    case PowerLossCurrentLaw::kExponential:
      return "exponential";
    case PowerLossCurrentLaw::kHoldThenExponential:
      return "hold_then_exponential";
    case PowerLossCurrentLaw::kSlewLimitedRamp:
      break;
  }
  return "slew_limited_ramp";
}

// JSON has no infinity: an unlimited value is null.
void NumberOrNull(JsonWriter& json, double v) {
  if (std::isfinite(v)) {
    json.Number(v);
  } else {
    json.Null();
  }
}

// ki, ks at the centre with the full bias: the linearised law's own, the electromagnet law's
// 4 k I0 / g0^2 and 4 k I0^2 / g0^3 (seed 003, Eq. (2) linearised).
std::pair<double, double> Gains(const AmbParams& a) {
  switch (a.law) {
    case AmbForceLaw::kLinearisedCurrents:
      return {a.current_gain_N_per_A, a.position_gain_N_per_m};
    case AmbForceLaw::kElectromagnet:
      return {ElectromagnetCurrentGain(a.electromagnet),
              ElectromagnetPositionGain(a.electromagnet)};
    case AmbForceLaw::kEquivalent:
      break;
  }
  return {std::numeric_limits<double>::quiet_NaN(), -a.stiffness_N_per_m};
}

}  // namespace

std::string PlantDescriptionJson(const Model& model, const std::string& config_path) {
  const ModelParams& p = model.params;
  const ControlInput static_load = StaticLoadInput(model);
  JsonWriter json;
  json.BeginObject();
  json.Key("schema_version").Integer(kPlantDescriptionVersion);
  json.Key("config").String(config_path);
  json.Key("name").String(p.name);
  json.Key("conventions").BeginObject();
  json.Key("units").String("SI throughout: m, A, N, s, rad/s");
  json.Key("frame").String(
      "x horizontal, y vertical up, z along the shaft (gravity along -y, spin positive about "
      "+z)");
  json.Key("current_sign")
      .String(
          "a positive control current on an axis pulls the rotor toward +x / +y: f = ki i + ks u "
          "at the centre");
  json.Key("index_order")
      .String(
          "AMBs, sensors and TDBs are indexed in the order listed here (their names sorted); the "
          "LCM arrays and the CAN frame map use these indices");
  json.Key("lock_step")
      .String(
          "one sensors message per controller period, carrying its step; a currents message "
          "answers "
          "it and applies from the next period");
  json.EndObject();
  json.Key("rates").BeginObject();
  json.Key("step_s").Number(p.simulation.step_s);
  json.Key("controller_rate_Hz").Number(p.controller.rate_Hz);
  json.Key("sensor_period_s").Number(1.0 / p.controller.rate_Hz);
  json.Key("output_interval_s").Number(p.simulation.output_interval_s);
  json.EndObject();
  json.Key("rotor").BeginObject();
  json.Key("mass_kg").Number(model.rotor.mass_kg);
  json.Key("polar_inertia_kg_m2").Number(model.rotor.polar_inertia_kg_m2);
  json.Key("spin_speed_rad_s").Number(p.simulation.spin_speed_rad_s);
  json.Key("gravity_m_s2").Number(p.gravity.enabled ? p.gravity.acceleration_m_s2 : 0.0);
  json.EndObject();

  json.Key("ambs").BeginArray();
  for (std::size_t a = 0; a < p.ambs.size(); ++a) {
    const AmbParams& amb = p.ambs[a];
    const auto [ki, ks] = Gains(amb);
    json.BeginObject();
    json.Key("index").Integer(static_cast<std::int64_t>(a));
    json.Key("name").String(amb.name);
    json.Key("position_m").Number(amb.position_m);
    json.Key("sensor").String(amb.sensor.empty() ? amb.name : amb.sensor);
    json.Key("law").String(LawName(amb.law));
    json.Key("bias_source")
        .String(amb.bias_source == AmbBiasSource::kPermanentMagnet ? "permanent_magnet"
                                                                   : "electromagnet");
    // What holds the rotor with zero deflection at the AMB planes (gravity's share here).
    json.Key("static_force_N")
        .NumberArray({model.amb_bias_force_N[a][0], model.amb_bias_force_N[a][1]});
    json.Key("static_current_A")
        .NumberArray({static_load.amb[a].current_A[0], static_load.amb[a].current_A[1]});
    json.Key("current_gain_ki_N_per_A");
    NumberOrNull(json, ki);
    json.Key("position_gain_ks_N_per_m");
    NumberOrNull(json, ks);
    json.Key("control_current_limit_A");
    NumberOrNull(json,
                 amb.law == AmbForceLaw::kEquivalent ? std::nan("") : ControlCurrentLimit(amb));
    if (amb.law == AmbForceLaw::kElectromagnet) {
      const ElectromagnetParams& e = amb.electromagnet;
      json.Key("electromagnet").BeginObject();
      json.Key("constant_k_N_m2_per_A2").Number(ElectromagnetConstant(e));
      json.Key("bias_current_A").Number(e.bias_current_A);
      json.Key("nominal_gap_m").Number(e.nominal_gap_m);
      json.Key("saturated_coil_force_N");
      NumberOrNull(json, SaturatedCoilForce(e));
      json.EndObject();
    }
    if (amb.law == AmbForceLaw::kEquivalent) {
      json.Key("stiffness_N_per_m").Number(amb.stiffness_N_per_m);
      json.Key("damping_N_s_per_m").Number(amb.damping_N_s_per_m);
    }
    json.Key("power_loss").BeginObject();
    json.Key("current_law").String(PowerLossName(amb.flux_decay));
    if (amb.flux_decay.enabled) {
      json.Key("time_constant_s").Number(amb.flux_decay.time_constant_s);
      json.Key("hold_time_s").Number(amb.flux_decay.hold_time_s);
      json.Key("slew_rate_A_per_s").Number(amb.flux_decay.slew_rate_A_per_s);
    }
    json.EndObject();
    json.EndObject();
  }
  json.EndArray();

  json.Key("sensors").BeginArray();
  for (std::size_t s = 0; s < p.sensors.size(); ++s) {
    const SensorParams& sensor = p.sensors[s];
    json.BeginObject();
    json.Key("index").Integer(static_cast<std::int64_t>(s));
    json.Key("name").String(sensor.name);
    json.Key("position_m").Number(sensor.position_m);
    json.Key("gain").NumberArray({sensor.AxisGain(0), sensor.AxisGain(1)});
    json.Key("offset_m").NumberArray({sensor.AxisOffset_m(0), sensor.AxisOffset_m(1)});
    json.Key("quantisation_m").Number(sensor.quantisation_m);
    json.Key("noise_sigma_m").Number(sensor.noise.enabled ? sensor.noise.std_dev_m : 0.0);
    json.EndObject();
  }
  json.EndArray();

  json.Key("tdbs").BeginArray();
  for (std::size_t t = 0; t < p.tdbs.size(); ++t) {
    json.BeginObject();
    json.Key("index").Integer(static_cast<std::int64_t>(t));
    json.Key("name").String(p.tdbs[t].name);
    json.Key("position_m").Number(p.tdbs[t].position_m);
    json.Key("clearance_m").Number(p.tdbs[t].clearance_m);
    json.EndObject();
  }
  json.EndArray();

  // The in-process reference controller, for comparison: its PID in A/m and A/(m/s).
  json.Key("reference_controller").BeginObject();
  const bool pid = p.controller.kind == ControllerKind::kInternalPid &&
                   p.controller.form == ControllerForm::kPid;
  json.Key("kind").String(p.controller.kind == ControllerKind::kNone ? "none"
                          : pid                                      ? "pid"
                                                                     : "linear");
  if (pid) {
    const PidParams& c = p.controller.pid;
    const double gain = c.sensor_gain_V_per_m * c.amplifier_gain_A_per_V;
    json.Key("law").String(
        "i = i_static - Ga Gs (kp r + ki_per_s integral(r) + kd_s dr/dt), r the reading (m)");
    json.Key("proportional_A_per_m").Number(gain * c.kp);
    json.Key("integral_A_per_m_s").Number(gain * c.ki_per_s);
    json.Key("derivative_A_s_per_m").Number(gain * c.kd_s);
    json.Key("derivative_filter_s").Number(c.derivative_filter_s);
    json.Key("gravity_feedforward").Bool(c.gravity_feedforward);
  }
  json.Key("delay_samples").Integer(p.controller.delay_samples);
  json.EndObject();
  json.EndObject();
  return json.str();
}

}  // namespace ambdrop
