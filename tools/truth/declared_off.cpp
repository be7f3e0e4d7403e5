#include "declared_off.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "drop_run.hpp"
#include "noise.hpp"
#include "plant.hpp"
#include "rotor_modes.hpp"

namespace ambdrop_truth {

namespace {

// The TDB must catch the rotor before the AMB's poles do: clearance <= 0.8 of the air gap.
constexpr double kClearanceOverGapMax = 0.8;
// Levitated: held without power loss for the trigger time and at least kLevitationHorizon_s,
// the rotor's motion at the sensors about its set point stays small and does not grow (an
// unstable loop's oscillation grows out of the noise; a slow one would still look levitated
// at a 0.1 s trigger).
constexpr double kLevitationHorizon_s = 0.3;
constexpr double kMaxLevitatedMotion_m = 5e-6;  // rms over the last quarter
constexpr double kMaxLevitatedGrowth = 2.0;     // rms of the last quarter over the second's

/// The shortest text that reads back as the same double.
std::string Shortest(double v) {
  return fmt::format("{}", v);
}

/// A value rounded to 5 significant digits, so that the generator runs the very number the
/// truth's --set line gives.
double Rounded(double v) {
  return std::stod(fmt::format("{:.5g}", v));
}

/// The distance from z to the nearest other station (a station at z itself is z's own).
double NearestOtherStation(const Rig& rig, double z) {
  double nearest = std::numeric_limits<double>::infinity();
  for (const double s : HardwareStations(rig)) {
    const double d = std::abs(s - z);
    if (d > 0.0) nearest = std::min(nearest, d);
  }
  return nearest;
}

double MaxClearance(const Rig& rig) {
  return std::max(rig.tdbs[0].clearance_m, rig.tdbs[1].clearance_m);
}

double MinGap(const Rig& rig) {
  return std::min(rig.ambs[0].nominal_gap_m, rig.ambs[1].nominal_gap_m);
}

}  // namespace

std::vector<DeclaredEntry> DeclaredOffEntries(const Rig& rig) {
  std::vector<DeclaredEntry> out;
  out.reserve(96);  // `add` returns a reference to the entry it added: no reallocation
  using K = OffKind;
  // One entry: its generator name, how it is drawn, its ambdrop key, the rig field.
  const auto add = [&](std::string name, OffKind kind, std::string key,
                       std::function<double*(Rig*)> field) -> DeclaredEntry& {
    DeclaredEntry e;
    e.name = std::move(name);
    e.kind = kind;
    e.ambdrop_key = std::move(key);
    e.field = std::move(field);
    e.ambdrop_value = [](const Rig&, double v) { return Shortest(v); };
    out.push_back(std::move(e));
    return out.back();
  };

  if (!rig.shaft.enabled) {
    const std::string rotor = "rotor.rigid.";
    add("rotor.mass_kg", K::kFactor, rotor + "mass_kg", [](Rig* r) { return &r->rotor.mass_kg; });
    add("rotor.transverse_inertia_kg_m2", K::kFactor, rotor + "transverse_inertia_kg_m2",
        [](Rig* r) { return &r->rotor.transverse_inertia_kg_m2; });
    add("rotor.polar_inertia_kg_m2", K::kFactor, rotor + "polar_inertia_kg_m2",
        [](Rig* r) { return &r->rotor.polar_inertia_kg_m2; });
    add("rotor.centre_of_mass_m", K::kStation, rotor + "centre_of_mass_m",
        [](Rig* r) { return &r->rotor.centre_of_mass_m; });
  } else {
    // A flexible shaft's rigid-body numbers follow from its segments and discs.
    const auto derive = [](Rig* r) { r->rotor = ShaftInertia(r->shaft); };
    const std::string shaft = "rotor.shaft.";
    add(shaft + "youngs_modulus_Pa", K::kFactor, "rotor.materials.steel.youngs_modulus_Pa",
        [](Rig* r) { return &r->shaft.youngs_modulus_Pa; })
        .follow = derive;
    add(shaft + "density_kg_m3", K::kFactor, "rotor.materials.steel.density_kg_m3", [](Rig* r) {
      return &r->shaft.density_kg_m3;
    }).follow = derive;
    for (std::size_t i = 0; i < rig.shaft.segments.size(); ++i) {
      add(fmt::format("{}segments[{}].outer_diameter_m", shaft, i), K::kFactor,
          fmt::format("rotor.sections[{}].outer_diameter_m", i),
          [i](Rig* r) { return &r->shaft.segments[i].outer_diameter_m; })
          .follow = derive;
    }
    for (std::size_t i = 0; i < rig.shaft.discs.size(); ++i) {
      const std::string g = fmt::format("{}discs[{}].", shaft, i);
      const std::string k = fmt::format("rotor.discs[{}].", i);
      const auto number = [&](const std::string& name, OffKind kind, double DiscRig::*member) {
        add(g + name, kind, k + name, [i, member](Rig* r) {
          return &(r->shaft.discs[i].*member);
        }).follow = derive;
      };
      number("position_m", K::kStation, &DiscRig::position_m);
      number("mass_kg", K::kFactor, &DiscRig::mass_kg);
      number("transverse_inertia_kg_m2", K::kFactor, &DiscRig::transverse_inertia_kg_m2);
      number("polar_inertia_kg_m2", K::kFactor, &DiscRig::polar_inertia_kg_m2);
    }
  }
  if (rig.coast_down.viscous_N_m_s > 0.0) {
    add("coast_down.viscous_N_m_s", K::kFactor, "rotor.coast_down.viscous_N_m_s",
        [](Rig* r) { return &r->coast_down.viscous_N_m_s; });
  }
  if (rig.coast_down.windage_N_m_s2 > 0.0) {
    add("coast_down.windage_N_m_s2", K::kFactor, "rotor.coast_down.windage_N_m_s2",
        [](Rig* r) { return &r->coast_down.windage_N_m_s2; });
  }
  if (rig.power_loss.form == FluxDecayForm::kRamp) {
    DeclaredEntry& slew = add("power_loss.slew_rate_A_per_s", K::kFactor,
                              "amb." + rig.ambs[0].name + ".flux_decay.slew_rate_A_per_s",
                              [](Rig* r) { return &r->power_loss.slew_rate_A_per_s; });
    slew.also_ambdrop_keys = {"amb." + rig.ambs[1].name + ".flux_decay.slew_rate_A_per_s"};
  }
  if (rig.power_loss.form == FluxDecayForm::kFormA ||
      rig.power_loss.form == FluxDecayForm::kFormB) {
    const std::string amb0 = "amb." + rig.ambs[0].name + ".flux_decay.";
    const std::string amb1 = "amb." + rig.ambs[1].name + ".flux_decay.";
    DeclaredEntry& tau = add("power_loss.time_constant_s", K::kFactor, amb0 + "time_constant_s",
                             [](Rig* r) { return &r->power_loss.time_constant_s; });
    tau.also_ambdrop_keys = {amb1 + "time_constant_s"};
    if (rig.power_loss.form == FluxDecayForm::kFormB) {
      // Form b's tau is the force's; ambdrop's is the currents' (the force goes as their square).
      tau.ambdrop_value = [](const Rig&, double v) { return Shortest(2.0 * v); };
      DeclaredEntry& hold = add("power_loss.hold_time_s", K::kFactor, amb0 + "hold_time_s",
                                [](Rig* r) { return &r->power_loss.hold_time_s; });
      hold.also_ambdrop_keys = {amb1 + "hold_time_s"};
    }
  }

  for (int i = 0; i < 2; ++i) {
    const std::string g = "ambs." + rig.ambs[i].name + ".";
    const std::string k = "amb." + rig.ambs[i].name + ".";
    add(g + "electromagnet_constant_N_m2_per_A2", K::kFactor,
        k + "electromagnet.constant_N_m2_per_A2",
        [i](Rig* r) { return &r->ambs[i].electromagnet_constant_N_m2_per_A2; });
    add(g + "bias_current_A", K::kFactor, k + "electromagnet.bias_current_A",
        [i](Rig* r) { return &r->ambs[i].bias_current_A; });
    add(g + "nominal_gap_m", K::kFactor, k + "electromagnet.nominal_gap_m",
        [i](Rig* r) { return &r->ambs[i].nominal_gap_m; });
    add(g + "position_m", K::kStation, k + "position_m",
        [i](Rig* r) { return &r->ambs[i].position_m; });
  }

  for (int i = 0; i < 2; ++i) {
    const std::string g = "sensors." + rig.sensors[i].name + ".";
    const std::string k = "sensor." + rig.sensors[i].name + ".";
    add(g + "position_m", K::kStation, k + "position_m",
        [i](Rig* r) { return &r->sensors[i].position_m; });
    add(g + "gain_x", K::kFactor, k + "gain_x", [i](Rig* r) { return &r->sensors[i].gain[0]; });
    add(g + "gain_y", K::kFactor, k + "gain_y", [i](Rig* r) { return &r->sensors[i].gain[1]; });
    add(g + "offset_x_m", K::kOffset, k + "offset_x_m",
        [i](Rig* r) { return &r->sensors[i].offset_m[0]; });
    add(g + "offset_y_m", K::kOffset, k + "offset_y_m",
        [i](Rig* r) { return &r->sensors[i].offset_m[1]; });
  }

  const std::string linear = "controller.linear.";
  if (!rig.controller.firmware) {
    const std::string pid = linear + "sections[0].";
    add("controller.kp", K::kFactor, pid + "kp", [](Rig* r) { return &r->controller.kp; });
    add("controller.ki_per_s", K::kFactor, pid + "ki_per_s",
        [](Rig* r) { return &r->controller.ki_per_s; });
    add("controller.kd_s", K::kFactor, pid + "kd_s", [](Rig* r) { return &r->controller.kd_s; });
    add("controller.derivative_filter_s", K::kFactor, pid + "derivative_filter_s",
        [](Rig* r) { return &r->controller.derivative_filter_s; });
  } else {
    // The firmware's sections in the translation's order (tests/truth/flexible_pm_b.toml).
    for (std::size_t i = 0; i < rig.controller.sections.size(); ++i) {
      const std::string g = fmt::format("controller.sections[{}].", i);
      const std::string k = fmt::format("{}sections[{}].", linear, i);
      const auto number = [&](const std::string& name, double FirmwareSectionRig::*member) {
        add(g + name, K::kFactor, k + name,
            [i, member](Rig* r) { return &(r->controller.sections[i].*member); });
      };
      switch (rig.controller.sections[i].kind) {
        case FirmwareSectionRig::Kind::kPd:
          number("kp", &FirmwareSectionRig::kp);
          number("kd_s", &FirmwareSectionRig::kd_s);
          number("derivative_filter_s", &FirmwareSectionRig::derivative_filter_s);
          break;
        case FirmwareSectionRig::Kind::kLead:
          number("zero_Hz", &FirmwareSectionRig::zero_Hz);
          number("pole_Hz", &FirmwareSectionRig::pole_Hz);
          break;
        case FirmwareSectionRig::Kind::kNotch:
          number("frequency_Hz", &FirmwareSectionRig::frequency_Hz);
          number("pole_damping", &FirmwareSectionRig::pole_damping);
          if (rig.controller.sections[i].zero_damping > 0.0) {
            number("zero_damping", &FirmwareSectionRig::zero_damping);
          }
          break;
      }
    }
  }
  if (rig.controller.amplifier.enabled) {
    add("controller.amplifier.bandwidth_Hz", K::kFactor, "controller.amplifier.bandwidth_Hz",
        [](Rig* r) { return &r->controller.amplifier.bandwidth_Hz; });
    if (rig.controller.amplifier.slew_rate_A_per_s > 0.0) {
      add("controller.amplifier.slew_rate_A_per_s", K::kFactor,
          "controller.amplifier.slew_rate_A_per_s",
          [](Rig* r) { return &r->controller.amplifier.slew_rate_A_per_s; });
    }
  }
  add("controller.amplifier_gain_A_per_V", K::kFactor, linear + "amplifier_gain_A_per_V",
      [](Rig* r) { return &r->controller.amplifier_gain_A_per_V; });
  add("controller.sensor_gain_V_per_m", K::kFactor, linear + "sensor_gain_V_per_m",
      [](Rig* r) { return &r->controller.sensor_gain_V_per_m; });
  // ambdrop delays by whole controller samples; the draw is whole periods, so this is exact.
  DeclaredEntry& delay =
      add("controller.computation_delay_s", K::kDelay, "controller.delay_samples",
          [](Rig* r) { return &r->controller.computation_delay_s; });
  delay.ambdrop_value = [](const Rig& r, double v) {
    return fmt::format("{}", std::lround(v * r.controller.rate_Hz));
  };

  const char* race_radius_note =
      "ambdrop's inner-race radius follows it (journal radius + clearance: the translation "
      "declares no inner_race_radius_m); the generator's stays the journal radius, as in the "
      "clean record";
  for (int i = 0; i < 2; ++i) {
    const std::string g = "tdbs." + rig.tdbs[i].name + ".";
    const std::string k = "tdb." + rig.tdbs[i].name + ".";
    add(g + "position_m", K::kStation, k + "position_m",
        [i](Rig* r) { return &r->tdbs[i].position_m; });
    DeclaredEntry& clearance = add(g + "clearance_m", K::kFactor, k + "clearance_m",
                                   [i](Rig* r) { return &r->tdbs[i].clearance_m; });
    DeclaredEntry& journal = add(g + "journal_radius_m", K::kFactor, k + "journal_radius_m",
                                 [i](Rig* r) { return &r->tdbs[i].journal_radius_m; });
    // The sheet gives no inner-race radius: the generator takes the journal radius for it, so
    // the two move together, and the translation leaves ambdrop's at its default.
    if (rig.tdbs[i].inner_race_radius_m == rig.tdbs[i].journal_radius_m) {
      clearance.mapping = "approximate";
      clearance.mapping_note = race_radius_note;
      journal.mapping = "approximate";
      journal.mapping_note = race_radius_note;
      journal.follow = [i](Rig* r) {
        r->tdbs[i].inner_race_radius_m = r->tdbs[i].journal_radius_m;
      };
    } else {
      // Given apart, the two radii keep their order: each is drawn as its gap to the other.
      journal.kind = K::kGapTo;
      journal.partner = [i](const Rig& r) { return r.tdbs[i].inner_race_radius_m; };
      add(g + "inner_race_radius_m", K::kGapTo, k + "inner_race_radius_m", [i](Rig* r) {
        return &r->tdbs[i].inner_race_radius_m;
      }).partner = [i](const Rig& r) { return r.tdbs[i].journal_radius_m; };
    }
    add(g + "friction.coefficient", K::kFactor, k + "friction.coefficient",
        [i](Rig* r) { return &r->tdbs[i].friction_coefficient; });
    add(g + "race.inertia_kg_m2", K::kFactor, k + "spin.inertia_kg_m2",
        [i](Rig* r) { return &r->tdbs[i].race_inertia_kg_m2; });
    add(g + "race.viscous_drag_N_m_s", K::kFactor, k + "spin.rotational_damping_N_m_s",
        [i](Rig* r) { return &r->tdbs[i].race_viscous_drag_N_m_s; });
    if (!rig.tdbs[i].four_dof.enabled && rig.tdbs[i].contact_law == ContactLaw::kHuntCrossley) {
      // A rigid race met by Hunt-Crossley's law: ambdrop's contact-law TDB with that normal law.
      const std::string h = k + "contact_law.hunt_crossley.";
      add(g + "contact.stiffness_N_per_m_n", K::kFactor, h + "stiffness_N_per_m_n",
          [i](Rig* r) { return &r->tdbs[i].contact_stiffness; });
      add(g + "contact.damping_s_per_m", K::kFactor, h + "damping_s_per_m",
          [i](Rig* r) { return &r->tdbs[i].contact_damping; });
      continue;
    }
    if (!rig.tdbs[i].four_dof.enabled) {
      add(g + "contact.stiffness_N_per_m", K::kFactor, k + "contact_law.bearing_stiffness_N_per_m",
          [i](Rig* r) { return &r->tdbs[i].contact_stiffness; });
      add(g + "contact.damping_N_s_per_m", K::kFactor, k + "contact_law.bearing_damping_N_s_per_m",
          [i](Rig* r) { return &r->tdbs[i].contact_damping; });
      continue;
    }
    // A 4-DOF TDB (Jarroux 2019 model #2): Hunt-Crossley journal / inner race, the races'
    // masses, a linear bearing and a Kelvin-Voigt ribbon.
    const std::string f = k + "four_dof.";
    add(g + "contact.stiffness_N_per_m_n", K::kFactor, f + "inner_contact.stiffness_N_per_m_n",
        [i](Rig* r) { return &r->tdbs[i].contact_stiffness; });
    add(g + "contact.damping_s_per_m", K::kFactor, f + "inner_contact.damping_s_per_m",
        [i](Rig* r) { return &r->tdbs[i].contact_damping; });
    add(g + "four_dof.inner_race_mass_kg", K::kFactor, f + "inner_race_mass_kg",
        [i](Rig* r) { return &r->tdbs[i].four_dof.inner_race_mass_kg; });
    add(g + "four_dof.outer_race_mass_kg", K::kFactor, f + "outer_race_mass_kg",
        [i](Rig* r) { return &r->tdbs[i].four_dof.outer_race_mass_kg; });
    add(g + "four_dof.bearing.stiffness_N_per_m", K::kFactor, f + "bearing.stiffness_N_per_m",
        [i](Rig* r) { return &r->tdbs[i].four_dof.bearing_stiffness_N_per_m; });
    add(g + "four_dof.bearing.damping_N_s_per_m", K::kFactor, f + "bearing.damping_N_s_per_m",
        [i](Rig* r) { return &r->tdbs[i].four_dof.bearing_damping_N_s_per_m; });
    add(g + "four_dof.ribbon.stiffness_N_per_m", K::kFactor, f + "kelvin_voigt.stiffness_N_per_m",
        [i](Rig* r) { return &r->tdbs[i].four_dof.ribbon_stiffness_N_per_m; });
    add(g + "four_dof.ribbon.damping_N_s_per_m", K::kFactor, f + "kelvin_voigt.damping_N_s_per_m",
        [i](Rig* r) { return &r->tdbs[i].four_dof.ribbon_damping_N_s_per_m; });
  }
  return out;
}

DeclaredOffDraw DrawDeclaredOff(const Rig& declared, const std::vector<DeclaredEntry>& entries,
                                int entry, std::uint64_t seed, int attempt) {
  // A stream of its own per attempt, apart from the noise's (streams 0..23) and the other
  // kinds' draws (1000).
  GaussianNoise u(seed, 2000 + static_cast<std::uint64_t>(attempt));
  const auto between = [&](double lo, double hi) { return lo + (hi - lo) * u.Uniform(); };
  DeclaredOffDraw d;
  if (entry < 0) {
    d.entry = std::min(entries.size() - 1,
                       static_cast<std::size_t>(u.Uniform() * static_cast<double>(entries.size())));
  } else {
    d.entry = static_cast<std::size_t>(entry);
  }
  const DeclaredEntry& e = entries.at(d.entry);
  Rig copy = declared;
  d.declared = *e.field(&copy);
  const double sign = u.Uniform() < 0.5 ? -1.0 : 1.0;
  const double size = between(0.15, 0.4);
  switch (e.kind) {
    case OffKind::kFactor:
      d.value = d.declared * (1.0 + sign * size);
      break;
    case OffKind::kOffset:
      d.value = d.declared + sign * between(5e-6, 30e-6);
      break;
    case OffKind::kStation:
      // size < 1: strictly inside the nearest neighbour on either side.
      d.value = d.declared + sign * size * NearestOtherStation(declared, d.declared);
      break;
    case OffKind::kDelay:
      d.value = d.declared + 1.0 / declared.controller.rate_Hz;
      break;
    case OffKind::kGapTo: {
      const double partner = e.partner(declared);
      d.value = partner + (d.declared - partner) * (1.0 + sign * size);
      break;
    }
  }
  if (e.kind != OffKind::kDelay) d.value = Rounded(d.value);
  // What stays physical: a TDB clearance inside the AMBs' air gap, and the air gap outside it.
  if (e.name.ends_with(".clearance_m")) {
    d.value = std::min(d.value, kClearanceOverGapMax * MinGap(declared));
  } else if (e.name.ends_with(".nominal_gap_m")) {
    d.value = std::max(d.value, MaxClearance(declared) / kClearanceOverGapMax);
  }
  return d;
}

bool Levitates(const Rig& rig, std::uint64_t seed) {
  Rig r = rig;
  const double horizon = std::max(rig.acquisition.trigger_time_s, kLevitationHorizon_s);
  r.acquisition.trigger_time_s = 2.0 * horizon;  // no power loss
  r.acquisition.record_length_s = horizon;
  const Plant plant(r);
  std::array<std::array<double, 2>, 2> held{};
  const PlantState start = EquilibriumState(r, &held);
  std::array<std::array<double, 2>, 2> set_point{};
  for (int s = 0; s < 2; ++s) set_point[s] = plant.AtStation(start, r.sensors[s].position_m);
  bool clear = true;
  // The rotor's motion about its set point at the sensors, mean square, in the second and the
  // last quarter of the horizon.
  std::array<double, 2> sum_sq{};
  std::array<long, 2> count{};
  RunOptions options;
  options.on_step = [&](double t, const PlantState& y) {
    for (const TdbRig& tdb : r.tdbs) {
      const auto p = plant.AtStation(y, tdb.position_m);
      if (std::hypot(p[0], p[1]) > 0.5 * tdb.clearance_m) clear = false;
    }
    const int w = t >= 0.75 * horizon ? 1 : (t >= 0.25 * horizon && t < 0.5 * horizon ? 0 : -1);
    if (w < 0) return;
    for (int s = 0; s < 2; ++s) {
      const auto p = plant.AtStation(y, r.sensors[s].position_m);
      for (int axis = 0; axis < 2; ++axis) {
        const double u = p[axis] - set_point[s][axis];
        sum_sq[w] += u * u;
        ++count[w];
      }
    }
  };
  const RunResult run = RunDrop(r, seed, options);
  if (!run.finite || !clear || count[0] == 0 || count[1] == 0) return false;
  const double second = std::sqrt(sum_sq[0] / static_cast<double>(count[0]));
  const double last = std::sqrt(sum_sq[1] / static_cast<double>(count[1]));
  return last < kMaxLevitatedMotion_m && last <= kMaxLevitatedGrowth * second;
}

Truth ApplyDraw(const std::vector<DeclaredEntry>& entries, const DeclaredOffDraw& d, int attempt,
                Rig* rig) {
  const DeclaredEntry& e = entries.at(d.entry);
  *e.field(rig) = d.value;
  if (e.follow) e.follow(rig);
  Truth t;
  t.effect = "declared_off";
  t.entry = e.name;
  const std::string change =
      d.declared != 0.0
          ? fmt::format(", {:+.1f} %", 100.0 * (d.value - d.declared) / std::abs(d.declared))
          : "";
  const std::string redrawn =
      attempt > 0 ? fmt::format("; draw {} (the earlier ones did not levitate)", attempt + 1) : "";
  t.description = fmt::format("declared number off: {} is {} (declared {}{}){}", e.name,
                              Shortest(d.value), Shortest(d.declared), change, redrawn);
  t.mapping = e.mapping;
  t.mapping_note = e.mapping_note;
  t.generator_parameters.emplace_back(e.name, d.value);
  t.ambdrop_keys.emplace_back(e.ambdrop_key, e.ambdrop_value(*rig, d.value));
  for (const std::string& key : e.also_ambdrop_keys) {
    t.ambdrop_keys.emplace_back(key, e.ambdrop_value(*rig, d.value));
  }
  return t;
}

Truth ApplyDeclaredOff(const std::string& entry_name, std::uint64_t seed, Rig* rig) {
  const std::vector<DeclaredEntry> entries = DeclaredOffEntries(*rig);
  int entry = -1;
  if (!entry_name.empty()) {
    for (std::size_t i = 0; i < entries.size(); ++i) {
      if (entries[i].name == entry_name) entry = static_cast<int>(i);
    }
    if (entry < 0) {
      throw std::invalid_argument("unknown declared_off entry '" + entry_name +
                                  "' (ambdrop_truth --list names them)");
    }
  }
  for (int attempt = 0; attempt < kMaxLevitationDraws; ++attempt) {
    Rig actual = *rig;
    const Truth t =
        ApplyDraw(entries, DrawDeclaredOff(*rig, entries, entry, seed, attempt), attempt, &actual);
    CheckRig(actual);
    if (!Levitates(actual, seed)) continue;
    *rig = actual;
    return t;
  }
  throw std::runtime_error(
      fmt::format("declared_off (seed {}): no draw in {} levitates", seed, kMaxLevitationDraws));
}

}  // namespace ambdrop_truth
