#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "json_reader.hpp"
#include "rig.hpp"
#include "rotor_modes.hpp"

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
  if (const JsonValue* mount = t.Find("four_dof")) {
    const JsonValue& m = *mount;
    tdb.four_dof.enabled = true;
    tdb.four_dof.inner_race_mass_kg = m.Number("inner_race_mass_kg");
    tdb.four_dof.outer_race_mass_kg = m.Number("outer_race_mass_kg");
    const JsonValue& bearing = m.At("bearing");
    tdb.four_dof.bearing_stiffness_N_per_m = bearing.Number("stiffness_N_per_m");
    tdb.four_dof.bearing_damping_N_s_per_m = bearing.Number("damping_N_s_per_m");
    const JsonValue& ribbon = m.At("ribbon");
    tdb.four_dof.ribbon_stiffness_N_per_m = ribbon.Number("stiffness_N_per_m");
    tdb.four_dof.ribbon_damping_N_s_per_m = ribbon.Number("damping_N_s_per_m");
  }
  return tdb;
}

FlexibleShaftRig ReadShaft(const JsonValue& j) {
  FlexibleShaftRig shaft;
  shaft.enabled = true;
  shaft.start_m = j.Number("start_m", 0.0);
  shaft.youngs_modulus_Pa = j.Number("youngs_modulus_Pa");
  shaft.density_kg_m3 = j.Number("density_kg_m3");
  const double modes = j.Number("bending_modes");
  if (!(modes >= 0.0 && modes <= 40.0) || modes != std::floor(modes)) {
    throw std::runtime_error(j.At("bending_modes").path() + ": expected a whole number 0..40");
  }
  shaft.bending_modes = static_cast<int>(modes);
  shaft.modal_damping_ratio = j.Number("modal_damping_ratio", 0.0);
  for (const JsonValue& s : j.At("segments").Items()) {
    ShaftSegmentRig seg;
    seg.length_m = s.Number("length_m");
    seg.outer_diameter_m = s.Number("outer_diameter_m");
    seg.inner_diameter_m = s.Number("inner_diameter_m", 0.0);
    const double elements = s.Number("elements");
    if (!(elements >= 1.0 && elements <= 200.0) || elements != std::floor(elements)) {
      throw std::runtime_error(s.At("elements").path() + ": expected a whole number 1..200");
    }
    seg.elements = static_cast<int>(elements);
    shaft.segments.push_back(seg);
  }
  if (const JsonValue* discs = j.Find("discs")) {
    for (const JsonValue& d : discs->Items()) {
      shaft.discs.push_back({d.Number("position_m"), d.Number("mass_kg"),
                             d.Number("transverse_inertia_kg_m2"),
                             d.Number("polar_inertia_kg_m2")});
    }
  }
  return shaft;
}

FirmwareSectionRig ReadSection(const JsonValue& s) {
  FirmwareSectionRig f;
  const std::string kind = s.String("kind");
  f.prewarp_Hz = s.Number("prewarp_Hz", 0.0);
  if (kind == "pd") {
    f.kind = FirmwareSectionRig::Kind::kPd;
    f.kp = s.Number("kp");
    f.kd_s = s.Number("kd_s");
    f.derivative_filter_s = s.Number("derivative_filter_s");
  } else if (kind == "lead") {
    f.kind = FirmwareSectionRig::Kind::kLead;
    f.zero_Hz = s.Number("zero_Hz");
    f.pole_Hz = s.Number("pole_Hz");
  } else if (kind == "notch") {
    f.kind = FirmwareSectionRig::Kind::kNotch;
    f.frequency_Hz = s.Number("frequency_Hz");
    f.pole_damping = s.Number("pole_damping");
    f.zero_damping = s.Number("zero_damping", 0.0);
  } else {
    throw std::runtime_error(s.At("kind").path() + ": expected \"pd\", \"lead\" or \"notch\"");
  }
  return f;
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
  if (const JsonValue* shaft = rotor.Find("shaft")) {
    rig.shaft = ReadShaft(*shaft);
    rig.rotor = ShaftInertia(rig.shaft);
  } else {
    rig.rotor.mass_kg = rotor.Number("mass_kg");
    rig.rotor.transverse_inertia_kg_m2 = rotor.Number("transverse_inertia_kg_m2");
    rig.rotor.polar_inertia_kg_m2 = rotor.Number("polar_inertia_kg_m2");
    rig.rotor.centre_of_mass_m = rotor.Number("centre_of_mass_m");
  }
  if (const JsonValue* cd = root.Find("coast_down")) {
    rig.coast_down.viscous_N_m_s = cd->Number("viscous_N_m_s", 0.0);
    rig.coast_down.windage_N_m_s2 = cd->Number("windage_N_m_s2", 0.0);
  }

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
    const std::string bias = ambs[i].String("bias", "electromagnet");
    if (bias != "electromagnet" && bias != "permanent_magnet") {
      throw std::runtime_error(ambs[i].At("bias").path() +
                               ": expected \"electromagnet\" or \"permanent_magnet\"");
    }
    a.permanent_magnet_bias = bias == "permanent_magnet";
    rig.tdbs[i] = ReadTdb(tdbs[i]);
  }

  const JsonValue& c = root.At("controller");
  rig.controller.rate_Hz = c.Number("rate_Hz");
  rig.controller.computation_delay_s = c.Number("computation_delay_s");
  rig.controller.sensor_gain_V_per_m = c.Number("sensor_gain_V_per_m");
  rig.controller.amplifier_gain_A_per_V = c.Number("amplifier_gain_A_per_V");
  const std::string form = c.String("form", "pid");
  if (form == "firmware") {
    rig.controller.firmware = true;
    for (const JsonValue& s : c.At("sections").Items()) {
      rig.controller.sections.push_back(ReadSection(s));
    }
  } else if (form == "pid") {
    rig.controller.kp = c.Number("kp");
    rig.controller.ki_per_s = c.Number("ki_per_s");
    rig.controller.kd_s = c.Number("kd_s");
    rig.controller.derivative_filter_s = c.Number("derivative_filter_s");
  } else {
    throw std::runtime_error(c.At("form").path() + ": expected \"pid\" or \"firmware\"");
  }
  if (const JsonValue* amp = c.Find("amplifier")) {
    rig.controller.amplifier.enabled = true;
    rig.controller.amplifier.bandwidth_Hz = amp->Number("bandwidth_Hz");
    rig.controller.amplifier.slew_rate_A_per_s = amp->Number("slew_rate_A_per_s", 0.0);
  }

  const JsonValue& q = root.At("acquisition");
  rig.acquisition.sample_rate_Hz = q.Number("sample_rate_Hz");
  rig.acquisition.record_length_s = q.Number("record_length_s");
  rig.acquisition.trigger_time_s = q.Number("trigger_time_s");
  rig.acquisition.sensor_noise_m = q.Number("sensor_noise_sigma_m");
  rig.acquisition.sensor_quantisation_m = q.Number("sensor_quantisation_m", 0.0);
  rig.acquisition.sensor_noise_bandwidth_Hz = q.Number("sensor_noise_bandwidth_Hz", 0.0);
  if (!(std::isfinite(rig.acquisition.sensor_noise_bandwidth_Hz) &&
        rig.acquisition.sensor_noise_bandwidth_Hz >= 0.0)) {
    throw std::runtime_error(q.At("sensor_noise_bandwidth_Hz").path() +
                             ": expected a finite bandwidth >= 0 Hz (0: white noise)");
  }
  rig.acquisition.current_noise_A = q.Number("current_noise_sigma_A", 0.0);
  rig.acquisition.speed_noise_rpm = q.Number("speed_noise_sigma_rpm", 0.0);
  rig.acquisition.force_noise_N = q.Number("force_noise_sigma_N", 0.0);
  rig.acquisition.settle_s = q.Number("settle_s", 0.0);

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
    } else if (form == "ramp") {
      rig.power_loss.form = FluxDecayForm::kRamp;
      rig.power_loss.slew_rate_A_per_s = p->Number("slew_rate_A_per_s");
    } else {
      throw std::runtime_error(p->At("form").path() +
                               ": expected \"instant\", \"a\", \"b\" or \"ramp\"");
    }
  }
  CheckRig(rig);
  return rig;
}

std::vector<double> HardwareStations(const Rig& rig) {
  std::vector<double> z;
  for (const AmbRig& a : rig.ambs) z.push_back(a.position_m);
  for (const SensorRig& s : rig.sensors) z.push_back(s.position_m);
  for (const TdbRig& t : rig.tdbs) z.push_back(t.position_m);
  return z;
}

void CheckRig(const Rig& rig) {
  Positive(rig.step_s, "integration_step_s");
  Positive(rig.rotor.mass_kg, "rotor.mass_kg");
  Positive(rig.rotor.transverse_inertia_kg_m2, "rotor.transverse_inertia_kg_m2");
  Positive(rig.rotor.polar_inertia_kg_m2, "rotor.polar_inertia_kg_m2");
  for (const AmbRig& a : rig.ambs) {
    if (a.permanent_magnet_bias) Positive(a.coil_current_limit_A, "amb " + a.name + " limit");
  }
  for (const AmbRig& a : rig.ambs) {
    Positive(a.electromagnet_constant_N_m2_per_A2, "amb " + a.name + " electromagnet constant");
    Positive(a.nominal_gap_m, "amb " + a.name + " nominal_gap_m");
    Positive(a.bias_current_A, "amb " + a.name + " bias_current_A");
    if (!a.permanent_magnet_bias && !(a.coil_current_limit_A > a.bias_current_A)) {
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
    if (t.four_dof.enabled) {
      const FourDofMountRig& m = t.four_dof;
      Positive(m.inner_race_mass_kg, "tdb " + t.name + " four_dof.inner_race_mass_kg");
      Positive(m.outer_race_mass_kg, "tdb " + t.name + " four_dof.outer_race_mass_kg");
      Positive(m.bearing_stiffness_N_per_m, "tdb " + t.name + " four_dof.bearing stiffness");
      Positive(m.ribbon_stiffness_N_per_m, "tdb " + t.name + " four_dof.ribbon stiffness");
      for (const auto& [damping, what] :
           {std::pair{m.bearing_damping_N_s_per_m, " four_dof.bearing damping"},
            std::pair{m.ribbon_damping_N_s_per_m, " four_dof.ribbon damping"}}) {
        if (!(damping >= 0.0) || !std::isfinite(damping)) {
          throw std::runtime_error("tdb " + t.name + what + ": expected a number >= 0, found " +
                                   std::to_string(damping));
        }
      }
    }
  }
  Positive(rig.controller.rate_Hz, "controller.rate_Hz");
  Positive(rig.acquisition.sample_rate_Hz, "acquisition.sample_rate_Hz");
  Positive(rig.acquisition.record_length_s, "acquisition.record_length_s");
  if (rig.controller.computation_delay_s < 0.0 ||
      rig.controller.computation_delay_s > 4.0 / rig.controller.rate_Hz + 1e-12) {
    throw std::runtime_error("controller.computation_delay_s: expected 0 to four periods");
  }
  if (rig.power_loss.form == FluxDecayForm::kFormA ||
      rig.power_loss.form == FluxDecayForm::kFormB) {
    Positive(rig.power_loss.time_constant_s, "power_loss.time_constant_s");
  }
  if (rig.power_loss.form == FluxDecayForm::kRamp) {
    Positive(rig.power_loss.slew_rate_A_per_s, "power_loss.slew_rate_A_per_s");
  }
  if (rig.controller.amplifier.enabled) {
    Positive(rig.controller.amplifier.bandwidth_Hz, "controller.amplifier.bandwidth_Hz");
  }
  for (const DiscRig& d : rig.shaft.discs) {
    Positive(d.mass_kg, "rotor.shaft.discs mass_kg");
    Positive(d.transverse_inertia_kg_m2, "rotor.shaft.discs transverse_inertia_kg_m2");
    Positive(d.polar_inertia_kg_m2, "rotor.shaft.discs polar_inertia_kg_m2");
  }
  if (rig.shaft.enabled &&
      !(rig.shaft.modal_damping_ratio >= 0.0 && rig.shaft.modal_damping_ratio < 1.0)) {
    throw std::runtime_error("rotor.shaft.modal_damping_ratio: expected 0 <= zeta < 1");
  }
  const double nyquist_Hz = 0.5 * rig.controller.rate_Hz;
  for (const FirmwareSectionRig& f : rig.controller.sections) {
    using K = FirmwareSectionRig::Kind;
    if (f.kind == K::kPd) {
      for (const double v : {f.kp, f.kd_s, f.derivative_filter_s}) {
        if (!(std::isfinite(v) && v >= 0.0)) {
          throw std::runtime_error("controller.sections pd: kp, kd_s, derivative_filter_s >= 0");
        }
      }
    } else if (f.kind == K::kLead) {
      Positive(f.zero_Hz, "controller.sections lead zero_Hz");
      Positive(f.pole_Hz, "controller.sections lead pole_Hz");
    } else {
      Positive(f.frequency_Hz, "controller.sections notch frequency_Hz");
      Positive(f.pole_damping, "controller.sections notch pole_damping");
      if (!(std::isfinite(f.zero_damping) && f.zero_damping >= 0.0)) {
        throw std::runtime_error("controller.sections notch zero_damping: expected >= 0");
      }
    }
    if (!(std::isfinite(f.prewarp_Hz) && f.prewarp_Hz >= 0.0 && f.prewarp_Hz < nyquist_Hz)) {
      throw std::runtime_error(
          "controller.sections prewarp_Hz: expected 0 (none) or below half "
          "the controller rate");
    }
  }
  for (const double v : {rig.controller.amplifier.slew_rate_A_per_s, rig.coast_down.viscous_N_m_s,
                         rig.coast_down.windage_N_m_s2}) {
    if (!(std::isfinite(v) && v >= 0.0)) {
      throw std::runtime_error(
          "controller.amplifier.slew_rate_A_per_s, coast_down.*: expected finite, >= 0");
    }
  }
  if (rig.controller.firmware && rig.controller.sections.empty()) {
    throw std::runtime_error("controller.sections: a firmware controller needs a section");
  }
  if (!(rig.acquisition.settle_s >= 0.0 && rig.acquisition.settle_s <= 10.0)) {
    throw std::runtime_error("acquisition.settle_s: expected 0 to 10 s");
  }
}

}  // namespace ambdrop_truth
