#include <cmath>
#include <numbers>
#include <stdexcept>

#include "json_reader.hpp"
#include "rig.hpp"

namespace ambdrop_truth {

namespace {

constexpr double kRadPerSPerRpm = 2.0 * std::numbers::pi / 60.0;

int SensorIndex(const JsonValue& amb, const std::array<SensorRig, 2>& sensors) {
  const std::string name = amb.String("sensor");
  for (int s = 0; s < 2; ++s) {
    if (sensors[s].name == name) return s;
  }
  throw std::runtime_error(amb.At("sensor").path() + ": no sensor named '" + name + "'");
}

TdbRig ReadTdb(const JsonValue& t) {
  TdbRig tdb;
  tdb.name = t.String("name");
  tdb.position_m = t.Number("position_m");
  tdb.journal_radius_m = t.Number("journal_radius_m");
  tdb.clearance_m = t.Number("clearance_m");
  tdb.inner_race_radius_m = t.Number("inner_race_radius_m", tdb.journal_radius_m);
  const JsonValue& contact = t.At("contact");
  const std::string law = contact.String("law");
  if (law == "linear") {
    tdb.contact_law = ContactLaw::kLinear;
    tdb.contact_stiffness = contact.Number("stiffness_N_per_m");
    tdb.contact_damping = contact.Number("damping_N_s_per_m");
  } else if (law == "hunt_crossley") {
    tdb.contact_law = ContactLaw::kHuntCrossley;
    tdb.contact_stiffness = contact.Number("stiffness_N_per_m_n");
    tdb.contact_exponent = contact.Number("exponent");
    tdb.contact_damping = contact.Number("damping_s_per_m");
  } else {
    throw std::runtime_error(contact.At("law").path() + ": expected \"linear\" or " +
                             "\"hunt_crossley\", found \"" + law + "\"");
  }
  const JsonValue& friction = t.At("friction");
  tdb.friction_coefficient = friction.Number("coefficient");
  tdb.slip_regularisation_m_s = friction.Number("slip_regularisation_m_s");
  const JsonValue& race = t.At("race");
  tdb.race_inertia_kg_m2 = race.Number("inertia_kg_m2");
  tdb.race_viscous_drag_N_m_s = race.Number("viscous_drag_N_m_s", 0.0);
  tdb.race_drag_torque_N_m = race.Number("drag_torque_N_m", 0.0);
  return tdb;
}

void Positive(double value, const std::string& what) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    throw std::runtime_error(what + ": expected a positive number, found " + std::to_string(value));
  }
}

}  // namespace

Rig ReadRig(const std::string& path) {
  const JsonValue root = ReadJsonFile(path);
  Rig rig;
  rig.name = root.String("name");
  rig.spin_speed_rad_s = root.Number("spin_speed_rpm") * kRadPerSPerRpm;
  rig.gravity_m_s2 = root.Number("gravity_m_s2", 9.81);
  rig.step_s = root.Number("integration_step_s", 1e-6);

  const JsonValue& rotor = root.At("rotor");
  rig.rotor.mass_kg = rotor.Number("mass_kg");
  rig.rotor.transverse_inertia_kg_m2 = rotor.Number("transverse_inertia_kg_m2");
  rig.rotor.polar_inertia_kg_m2 = rotor.Number("polar_inertia_kg_m2");
  rig.rotor.centre_of_mass_m = rotor.Number("centre_of_mass_m");

  const auto& sensors = root.At("sensors").Items();
  const auto& ambs = root.At("ambs").Items();
  const auto& tdbs = root.At("tdbs").Items();
  if (sensors.size() != 2 || ambs.size() != 2 || tdbs.size() != 2) {
    throw std::runtime_error(path + ": a rig has two sensor planes, two AMBs and two TDBs");
  }
  for (int i = 0; i < 2; ++i) {
    rig.sensors[i].name = sensors[i].String("name");
    rig.sensors[i].position_m = sensors[i].Number("position_m");
  }
  for (int i = 0; i < 2; ++i) {
    AmbRig& a = rig.ambs[i];
    a.name = ambs[i].String("name");
    a.position_m = ambs[i].Number("position_m");
    a.electromagnet_constant_N_m2_per_A2 = ambs[i].Number("electromagnet_constant_N_m2_per_A2");
    a.nominal_gap_m = ambs[i].Number("nominal_gap_m");
    a.bias_current_A = ambs[i].Number("bias_current_A");
    a.coil_current_limit_A = ambs[i].Number("coil_current_limit_A");
    a.sensor = SensorIndex(ambs[i], rig.sensors);
    rig.tdbs[i] = ReadTdb(tdbs[i]);
  }

  const JsonValue& c = root.At("controller");
  rig.controller.rate_Hz = c.Number("rate_Hz");
  rig.controller.computation_delay_s = c.Number("computation_delay_s");
  rig.controller.sensor_gain_V_per_m = c.Number("sensor_gain_V_per_m");
  rig.controller.amplifier_gain_A_per_V = c.Number("amplifier_gain_A_per_V");
  rig.controller.kp = c.Number("kp");
  rig.controller.ki_per_s = c.Number("ki_per_s");
  rig.controller.kd_s = c.Number("kd_s");
  rig.controller.derivative_filter_s = c.Number("derivative_filter_s");

  const JsonValue& q = root.At("acquisition");
  rig.acquisition.sample_rate_Hz = q.Number("sample_rate_Hz");
  rig.acquisition.record_length_s = q.Number("record_length_s");
  rig.acquisition.trigger_time_s = q.Number("trigger_time_s");
  rig.acquisition.sensor_noise_m = q.Number("sensor_noise_sigma_m");
  rig.acquisition.sensor_quantisation_m = q.Number("sensor_quantisation_m", 0.0);
  rig.acquisition.current_noise_A = q.Number("current_noise_sigma_A", 0.0);
  rig.acquisition.speed_noise_rpm = q.Number("speed_noise_sigma_rpm", 0.0);
  rig.acquisition.force_noise_N = q.Number("force_noise_sigma_N", 0.0);

  if (const JsonValue* p = root.Find("power_loss")) {
    const std::string form = p->String("form");
    if (form == "instant") {
      rig.power_loss.form = FluxDecayForm::kInstant;
    } else if (form == "a") {
      rig.power_loss.form = FluxDecayForm::kFormA;
      rig.power_loss.time_constant_s = p->Number("time_constant_s");
    } else if (form == "b") {
      rig.power_loss.form = FluxDecayForm::kFormB;
      rig.power_loss.time_constant_s = p->Number("time_constant_s");
      rig.power_loss.hold_time_s = p->Number("hold_time_s");
    } else {
      throw std::runtime_error(p->At("form").path() + ": expected \"instant\", \"a\" or \"b\"");
    }
  }
  CheckRig(rig);
  return rig;
}

void CheckRig(const Rig& rig) {
  Positive(rig.step_s, "integration_step_s");
  Positive(rig.rotor.mass_kg, "rotor.mass_kg");
  Positive(rig.rotor.transverse_inertia_kg_m2, "rotor.transverse_inertia_kg_m2");
  Positive(rig.rotor.polar_inertia_kg_m2, "rotor.polar_inertia_kg_m2");
  for (const AmbRig& a : rig.ambs) {
    Positive(a.electromagnet_constant_N_m2_per_A2, "amb " + a.name + " electromagnet constant");
    Positive(a.nominal_gap_m, "amb " + a.name + " nominal_gap_m");
    Positive(a.bias_current_A, "amb " + a.name + " bias_current_A");
    if (!(a.coil_current_limit_A > a.bias_current_A)) {
      throw std::runtime_error("amb " + a.name + ": coil_current_limit_A must exceed the bias");
    }
  }
  for (const TdbRig& t : rig.tdbs) {
    Positive(t.journal_radius_m, "tdb " + t.name + " journal_radius_m");
    Positive(t.inner_race_radius_m, "tdb " + t.name + " inner_race_radius_m");
    Positive(t.clearance_m, "tdb " + t.name + " clearance_m");
    Positive(t.contact_stiffness, "tdb " + t.name + " contact stiffness");
    Positive(t.slip_regularisation_m_s, "tdb " + t.name + " slip_regularisation_m_s");
    Positive(t.race_inertia_kg_m2, "tdb " + t.name + " race inertia_kg_m2");
    if (t.dahl.enabled) Positive(t.dahl.housing_mass_kg, "tdb " + t.name + " housing mass");
  }
  Positive(rig.controller.rate_Hz, "controller.rate_Hz");
  Positive(rig.acquisition.sample_rate_Hz, "acquisition.sample_rate_Hz");
  Positive(rig.acquisition.record_length_s, "acquisition.record_length_s");
  if (rig.controller.computation_delay_s < 0.0 ||
      rig.controller.computation_delay_s > 4.0 / rig.controller.rate_Hz + 1e-12) {
    throw std::runtime_error("controller.computation_delay_s: expected 0 to four periods");
  }
  if (rig.power_loss.form != FluxDecayForm::kInstant) {
    Positive(rig.power_loss.time_constant_s, "power_loss.time_constant_s");
  }
}

}  // namespace ambdrop_truth
