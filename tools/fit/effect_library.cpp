#include "tools/fit/effect_library.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <optional>
#include <tuple>
#include <utility>

#include "io/config/config_variants.hpp"
#include "rt_core/limits.hpp"
#include "rt_core/model.hpp"
#include "rt_core/tdb_common.hpp"
#include "tools/fit/key_effects.hpp"
#include "tools/fit/registry_candidates.hpp"

namespace ambdrop {
namespace {

constexpr double kPi = 3.14159265358979323846;
using Q = MeasuredQuantity;

// One `--set` line: "path=value", the value as TOML reads it back to the same double.
std::string Set(const std::string& path, double value) {
  return path + "=" + OverrideNumber(value);
}
std::string SetText(const std::string& path, const std::string& value) {
  return path + "=\"" + value + "\"";
}
std::string SetTrue(const std::string& path) {
  return path + "=true";
}

// Whether a TDB's model uses a friction coefficient between journal and inner race: contact-law,
// 4-DOF and catcher-bearing TDBs the regularised Coulomb law's, the ball-bearing TDB (Chen 2019)
// its own static/kinetic law's; none under a frictionless law.
bool HasFriction(const TdbParams& t) {
  if (t.model() == TdbModelKind::kBallBearing) {
    return t.ball_bearing().friction.law != SlipFrictionLaw::kNone;
  }
  return t.friction.law != FrictionLaw::kNone;
}

// The coefficient the journal slides on the race with. For the ball-bearing TDB that is the
// kinetic one: a drop's spin-up is all slip, and the static one only bounds the force inside
// the narrow stick band (rt_core/slip_friction.hpp).
double SlidingCoefficient(const TdbParams& t) {
  return t.model() == TdbModelKind::kBallBearing ? t.ball_bearing().friction.kinetic_coefficient
                                                 : t.friction.coefficient;
}

// The ball-bearing TDB's static coefficient for a kinetic `mu`: in the declared proportion, as
// the record cannot tell the two apart.
double StaticCoefficient(const SlipFrictionParams& declared, double mu) {
  return declared.kinetic_coefficient > 0.0
             ? declared.static_coefficient * mu / declared.kinetic_coefficient
             : std::max(declared.static_coefficient, mu);
}

// The keys of the coefficient a TDB slides with (the ball-bearing TDB's static one in
// proportion to the declared pair).
void SetSlidingCoefficient(const TdbParams& t, double mu, std::vector<std::string>* out) {
  if (t.model() == TdbModelKind::kBallBearing) {
    const std::string table = "tdb." + t.name + ".ball_bearing_tdb.friction.";
    out->push_back(
        Set(table + "static_coefficient", StaticCoefficient(t.ball_bearing().friction, mu)));
    out->push_back(Set(table + "kinetic_coefficient", mu));
  } else {
    out->push_back(Set("tdb." + t.name + ".friction.coefficient", mu));
  }
}

// The inner race's drag torque enters its spin equation (rt_core/tdb_common.hpp
// RaceAcceleration) for every model but the catcher bearing, whose races' moments are its
// bearings' own (rt_core/catcher_bearing_tdb.cpp; its config rejects a [spin] table).
bool HasDragTorque(const TdbParams& t) {
  return t.spin.enabled && t.model() != TdbModelKind::kCatcherBearing;
}

// Start values without repeats, in order (a declared value first).
std::vector<double> Distinct(std::initializer_list<double> values) {
  std::vector<double> out;
  for (const double v : values) {
    if (std::find(out.begin(), out.end(), v) == out.end()) out.push_back(v);
  }
  return out;
}

double SmallestClearance(const ModelParams& p) {
  double c = 1e-3;
  for (const TdbParams& t : p.tdbs) c = std::min(c, t.clearance_m);
  return c;
}

Effect TdbMisalignment(const TdbParams& t) {
  const std::string name = t.name;
  const double c = t.clearance_m;
  Effect e;
  e.name = "tdb_misalignment:" + name;
  e.family = "tdb_misalignment";
  e.description = fmt::format("TDB {} centre offset from the magnetic centre (x, y)", name);
  // Declared or not, the search starts at what is declared (0 when off).
  const MisalignmentParams& m = t.misalignment;
  const double x0 = m.enabled ? m.x_m : 0.0, y0 = m.enabled ? m.y_m : 0.0;
  e.parameters = {{"x_m", -0.8 * c, 0.8 * c, Distinct({x0, 0.0, 0.3 * c, -0.3 * c})},
                  {"y_m", -0.8 * c, 0.8 * c, Distinct({y0, 0.0, 0.3 * c, -0.3 * c})}};
  e.parameters[0].declared = x0;
  e.parameters[1].declared = y0;
  if (m.enabled) {
    e.description = fmt::format(
        "TDB {} centre offset from the magnetic centre (x, y; declared {:.4g}, {:.4g} m)", name,
        m.x_m, m.y_m);
  }
  e.revealed_by = {Q::kDisplacement, Q::kTdbNormalForce, Q::kTdbSupportForce,
                   Q::kControllerCommand};
  e.probe = {0.5 * c, -0.5 * c};
  const std::string table = "tdb." + name + ".misalignment.";
  e.overrides = [table](const std::vector<double>& v) {
    return std::vector<std::string>{SetTrue(table + "enabled"), Set(table + "x_m", v[0]),
                                    Set(table + "y_m", v[1])};
  };
  return e;
}

// A TDB whose radial clearance is not the declared one: wear, or a drawing's tolerance. In a
// drop that stays in the vertical plane a larger clearance and a lower TDB look alike; the
// selection reports such equivalent effects rather than picking one as if it were certain.
Effect TdbClearance(const TdbParams& t) {
  const std::string name = t.name;
  const double c = t.clearance_m;
  Effect e;
  e.name = "tdb_clearance:" + name;
  e.family = "tdb_clearance";
  e.description = fmt::format("radial clearance of TDB {} (declared {:.4g} m)", name, c);
  e.parameters = {{"clearance_m", 0.5 * c, 2.0 * c, {c, 1.3 * c, 0.8 * c}}};
  e.parameters[0].declared = c;
  e.revealed_by = {Q::kDisplacement, Q::kTdbNormalForce, Q::kTdbSupportForce,
                   Q::kControllerCommand};
  e.probe = {1.5 * c};
  e.overrides = [name](const std::vector<double>& v) {
    return std::vector<std::string>{Set("tdb." + name + ".clearance_m", v[0])};
  };
  return e;
}

// One coefficient for the given TDBs (those with friction), common or of one TDB.
Effect FrictionCoefficientOf(const std::vector<TdbParams>& tdbs, std::string name,
                             std::string description) {
  double mu = 0.2;
  std::vector<TdbParams> rubbing;
  for (const TdbParams& t : tdbs) {
    if (!HasFriction(t)) continue;
    mu = SlidingCoefficient(t);
    rubbing.push_back(t);
  }
  Effect e;
  e.name = std::move(name);
  e.family = "friction_coefficient";
  e.description = std::move(description);
  e.parameters = {{"coefficient", 0.01, 0.8, {mu, 0.5 * mu, std::min(0.8, 2.0 * mu)}}};
  // One declared coefficient for all of them, or none to return to.
  bool alike = true;
  for (const TdbParams& t : rubbing) alike = alike && SlidingCoefficient(t) == mu;
  if (!rubbing.empty() && alike) e.parameters[0].declared = mu;
  e.revealed_by = {Q::kDisplacement, Q::kTdbSpeed,        Q::kTdbNormalForce,
                   Q::kRotorSpeed,   Q::kTdbSupportForce, Q::kControllerCommand};
  e.probe = {mu < 0.4 ? 2.0 * mu : 0.5 * mu};
  e.overrides = [rubbing](const std::vector<double>& v) {
    std::vector<std::string> out;
    for (const TdbParams& t : rubbing) SetSlidingCoefficient(t, v[0], &out);
    return out;
  };
  return e;
}

Effect FrictionCoefficient(const ModelParams& declared) {
  return FrictionCoefficientOf(
      declared.tdbs, "friction_coefficient",
      "rotor / TDB friction coefficient (every TDB; ball-bearing TDBs: the kinetic one, the "
      "static one in proportion)");
}

// The coefficient of one TDB only: the TDBs of a rig wear, and are lubricated, each its own way.
Effect FrictionCoefficientAt(const TdbParams& t) {
  return FrictionCoefficientOf({t}, "friction_coefficient:" + t.name,
                               fmt::format("friction coefficient of TDB {} alone", t.name));
}

// Mass x eccentricity and phase, of a static or a couple unbalance.
std::vector<EffectParameter> UnbalanceParameters() {
  EffectParameter size{"mass_eccentricity_kg_m", 0.0, 0.05, {0.0, 1e-4, 1e-3}};
  size.magnitude = true;
  return {size, {"phase_rad", -kPi, kPi, {0.0, 0.5 * kPi, kPi, -0.5 * kPi}, true}};
}

// The axial span of the TDBs: the planes the unbalance effects put their masses in.
std::pair<double, double> TdbSpan(const ModelParams& declared) {
  double lo = 0.0, hi = 0.0;
  if (!declared.tdbs.empty()) {
    lo = hi = declared.tdbs.front().position_m;
    for (const TdbParams& t : declared.tdbs) {
      lo = std::min(lo, t.position_m);
      hi = std::max(hi, t.position_m);
    }
  }
  return {lo, hi};
}

// One mass x eccentricity and phase, in one or more planes: each plane's unbalance (named,
// at its position) turned by its own phase offset.
struct UnbalancePlane {
  const char* name;
  double position_m;
  double phase_offset_rad;
};

Effect UnbalanceIn(std::vector<UnbalancePlane> planes, std::string name, std::string description) {
  Effect e;
  e.name = std::move(name);
  e.family = "unbalance";
  e.description = std::move(description);
  e.parameters = UnbalanceParameters();
  e.revealed_by = {Q::kDisplacement, Q::kTdbNormalForce, Q::kTdbSupportForce,
                   Q::kControllerCommand};
  e.probe = {1e-3, 0.0};
  // A unit mass: the fitted size is its eccentricity, mass x eccentricity in one number.
  e.overrides = [planes](const std::vector<double>& v) {
    std::vector<std::string> out;
    for (const UnbalancePlane& plane : planes) {
      const std::string table = std::string("unbalance.") + plane.name + ".";
      out.push_back(Set(table + "position_m", plane.position_m));
      out.push_back(Set(table + "mass_kg", 1.0));
      out.push_back(Set(table + "eccentricity_m", v[0]));
      out.push_back(
          Set(table + "phase_rad", std::remainder(v[1] + plane.phase_offset_rad, 2 * kPi)));
    }
    return out;
  };
  return e;
}

Effect Unbalance(double centre_of_mass_m) {
  // One plane through the rotor's centre of mass: a static unbalance, the principal axis moved
  // parallel to itself. Its moment is the couple unbalance's (below); together, as a pair, they
  // make any unbalance of a rigid rotor. Midway between the TDBs instead, as it was, it carried
  // a moment wherever the centre of mass is not there: on the 4-DOF truth rig (TDBs at 0.03 and
  // 0.68 m, centre of mass at 0.46 m) the static unbalance of seed 206 fitted the levitated
  // orbit to 0.0066 at half its size (limit 0.0055; the truth's own keys 0.0030).
  const double position = centre_of_mass_m;
  return UnbalanceIn(
      {{"fitted", position, 0.0}}, "unbalance",
      fmt::format("static unbalance at {:.4g} m (mass x eccentricity, phase)", position));
}

// A couple unbalance: equal masses in the outermost TDB planes, half a turn apart (the rotor's
// principal axis tilted through its centre). What a static unbalance leaves of an unbalance
// that sits off the middle.
Effect CoupleUnbalance(const ModelParams& declared) {
  const auto [lo, hi] = TdbSpan(declared);
  return UnbalanceIn(
      {{"fitted_couple_a", lo, 0.0}, {"fitted_couple_b", hi, kPi}}, "couple_unbalance",
      fmt::format(
          "couple unbalance: mass x eccentricity at {:.4g} m and, half a turn on, at {:.4g} m", lo,
          hi));
}

// The force of the given AMBs fading after power loss, with one time constant.
// With a slew-limited ramp declared, a time constant means nothing: the effect is then the
// exponential law in its place (the config leaves the file's slew rate unused once --set
// switches the law).
Effect FluxDecayOf(const std::vector<const AmbParams*>& of, std::string name,
                   std::string description, double declared_tau_s = 0.0) {
  // name, law switched to exponential (a declared ramp or hold-then-exponential: refitting
  // only the time constant of a declared hold would be the hold candidate with its hold fixed)
  std::vector<std::pair<std::string, bool>> ambs;
  for (const AmbParams* a : of) {
    ambs.emplace_back(a->name, a->flux_decay.current_law != PowerLossCurrentLaw::kExponential);
  }
  Effect e;
  e.name = std::move(name);
  e.family = "amb_flux_decay";
  e.description = std::move(description);
  std::vector<double> starts = {1e-4, 2e-3, 1e-2};
  if (declared_tau_s >= 1e-4 && declared_tau_s <= 0.1) {
    starts = Distinct({declared_tau_s, 0.5 * declared_tau_s, 2.0 * declared_tau_s, 2e-3});
    std::erase_if(starts, [](double t) { return t < 1e-4 || t > 0.1; });
  }
  e.parameters = {{"time_constant_s", 1e-4, 0.1, starts}};
  // Not the controller's command: it goes on commanding whatever the coils do.
  e.revealed_by = {Q::kDisplacement, Q::kCurrent, Q::kTdbNormalForce, Q::kTdbSupportForce};
  e.probe = {2e-2};  // long: the declared model's loss is instant
  e.overrides = [ambs](const std::vector<double>& v) {
    std::vector<std::string> out;
    for (const auto& [a, switched] : ambs) {
      out.push_back(SetTrue("amb." + a + ".flux_decay.enabled"));
      if (switched) out.push_back(SetText("amb." + a + ".flux_decay.current_law", "exponential"));
      out.push_back(Set("amb." + a + ".flux_decay.time_constant_s", v[0]));
    }
    return out;
  };
  return e;
}

// The declared decay's time constant (the first declared one), 0 if none is declared.
double DeclaredTau(const std::vector<AmbParams>& ambs) {
  for (const AmbParams& a : ambs) {
    if (a.flux_decay.enabled) return a.flux_decay.time_constant_s;
  }
  return 0.0;
}

Effect FluxDecay(const ModelParams& declared) {
  std::vector<const AmbParams*> ambs;
  for (const AmbParams& a : declared.ambs) ambs.push_back(&a);
  const double tau = DeclaredTau(declared.ambs);
  return FluxDecayOf(ambs, "amb_flux_decay",
                     tau > 0.0
                         ? fmt::format("AMB force fading after power loss, time constant "
                                       "refitted (every AMB; declared {:.4g} s)",
                                       tau)
                         : "AMB coil currents fading after power loss as exp(-t/tau) (every AMB; "
                           "current_law = exponential)",
                     tau);
}

// The hold-then-fall law the AMBs declare: the first one whose numbers the candidates' ranges
// hold (nullptr if none), whether every AMB that declares that law declares the same numbers
// (one supply), and those AMBs.
struct DeclaredHold {
  const FluxDecayParams* law = nullptr;
  bool alike = true;
  std::vector<std::string> ambs;
};
DeclaredHold DeclaredHoldLaw(const ModelParams& declared) {
  DeclaredHold h;
  const FluxDecayParams* first = nullptr;
  for (const AmbParams& a : declared.ambs) {
    const FluxDecayParams& f = a.flux_decay;
    if (!f.enabled || f.current_law != PowerLossCurrentLaw::kHoldThenExponential) continue;
    if (first == nullptr) first = &f;
    h.alike = h.alike && f.hold_time_s == first->hold_time_s &&
              f.time_constant_s == first->time_constant_s;
    if (h.law == nullptr && f.hold_time_s <= 1e-2 && f.time_constant_s >= 1e-4 &&
        f.time_constant_s <= 0.1) {
      h.law = &f;
    }
    h.ambs.push_back(a.name);
  }
  return h;
}

// The other current law a power loss shows (issue 24): the amplifiers hold the currents, and so
// the force law, for a while (their supply's capacitors), then the coils' L/R takes them. On
// every AMB together (one supply). Two parameters where the exponential has one, so it must pay
// for its hold by the selection's rule.
Effect FluxDecayHold(const ModelParams& declared) {
  std::vector<std::string> ambs;
  for (const AmbParams& a : declared.ambs) ambs.push_back(a.name);
  Effect e;
  e.name = "amb_flux_decay_hold";
  e.family = "amb_flux_decay";
  e.description =
      "AMB currents held after power loss, then fading as exp(-t/tau) (every AMB; "
      "current_law = hold_then_exponential)";
  std::vector<double> hold_starts = {5e-4, 2e-3};
  std::vector<double> tau_starts = {2e-3, 8e-3};
  // A declared hold is refitted from where it was declared too (issue 23: a declared law's
  // numbers are suspects, starting from their declared values).
  const DeclaredHold declared_hold = DeclaredHoldLaw(declared);
  if (const FluxDecayParams* f = declared_hold.law) {
    hold_starts = Distinct({f->hold_time_s, 5e-4, 2e-3});
    tau_starts = Distinct({f->time_constant_s, 2e-3, 8e-3});
  }
  e.parameters = {{"hold_time_s", 0.0, 1e-2, hold_starts},
                  {"time_constant_s", 1e-4, 0.1, tau_starts}};
  // Every AMB's law as one declared hold: each number can return to it.
  if (declared_hold.law != nullptr && declared_hold.alike) {
    e.parameters[0].declared = declared_hold.law->hold_time_s;
    e.parameters[1].declared = declared_hold.law->time_constant_s;
  }
  e.revealed_by = {Q::kDisplacement, Q::kCurrent, Q::kTdbNormalForce, Q::kTdbSupportForce};
  e.probe = {2e-3, 2e-2};
  e.overrides = [ambs](const std::vector<double>& v) {
    std::vector<std::string> out;
    for (const std::string& a : ambs) {
      const std::string table = "amb." + a + ".flux_decay.";
      out.push_back(SetTrue(table + "enabled"));
      out.push_back(SetText(table + "current_law", "hold_then_exponential"));
      out.push_back(Set(table + "hold_time_s", std::max(0.0, v[0])));
      out.push_back(Set(table + "time_constant_s", v[1]));
    }
    return out;
  };
  return e;
}

// A declared hold-then-fall power loss with one of its two numbers off: the hold alone (the
// supply's capacitors), or the coils' time constant alone, the other as declared. The pair
// (FluxDecayHold) trades one for the other on a drop's start: on the 4-DOF truth rig's record of
// seed 409 (the hold 1.71 ms against 1 ms declared, the time constant as declared) it moved the
// time constant 8 % and left the hold 23 % of its change off. One number where two would fit no
// better is the simpler look-alike, named first (judged_part_selection.cpp).
std::optional<Effect> FluxDecayHoldPart(const ModelParams& declared, bool hold) {
  // One supply: a hold or time constant moved together where every AMB declares the same.
  const DeclaredHold declared_hold = DeclaredHoldLaw(declared);
  if (declared_hold.law == nullptr || !declared_hold.alike) return std::nullopt;
  const FluxDecayParams* law = declared_hold.law;
  const std::vector<std::string>& ambs = declared_hold.ambs;
  Effect e;
  e.family = "amb_flux_decay";
  e.revealed_by = {Q::kDisplacement, Q::kCurrent, Q::kTdbNormalForce, Q::kTdbSupportForce};
  const std::string key = hold ? "hold_time_s" : "time_constant_s";
  if (hold) {
    e.name = "amb_flux_decay_hold_time";
    e.description = fmt::format(
        "AMB currents held after power loss for another time than the declared {:.4g} s, then "
        "fading as declared (every AMB)",
        law->hold_time_s);
    e.parameters = {{key, 0.0, 1e-2, Distinct({law->hold_time_s, 5e-4, 2e-3})}};
    e.parameters[0].declared = law->hold_time_s;
    e.probe = {law->hold_time_s > 1e-3 ? 0.25 * law->hold_time_s : 2e-3 + law->hold_time_s};
  } else {
    e.name = "amb_flux_decay_hold_tau";
    e.description = fmt::format(
        "AMB currents held after power loss as declared, then fading with another time constant "
        "than the declared {:.4g} s (every AMB)",
        law->time_constant_s);
    e.parameters = {{key, 1e-4, 0.1, Distinct({law->time_constant_s, 2e-3, 8e-3})}};
    e.parameters[0].declared = law->time_constant_s;
    e.probe = {law->time_constant_s > 2e-3 ? 0.25 * law->time_constant_s
                                           : 4.0 * law->time_constant_s};
  }
  e.overrides = [ambs, key](const std::vector<double>& v) {
    std::vector<std::string> out;
    for (const std::string& a : ambs) {
      out.push_back(Set("amb." + a + ".flux_decay." + key, std::max(0.0, v[0])));
    }
    return out;
  };
  return e;
}

// The force of one AMB alone fading: each AMB has its own coils and amplifier.
Effect FluxDecayAt(const AmbParams& a) {
  const double tau = a.flux_decay.enabled ? a.flux_decay.time_constant_s : 0.0;
  return FluxDecayOf(
      {&a}, "amb_flux_decay:" + a.name,
      tau > 0.0 ? fmt::format("AMB {}'s decay time constant alone (declared {:.4g} s)", a.name, tau)
                : fmt::format("AMB {}'s coil currents alone fading after power loss as exp(-t/tau)",
                              a.name),
      tau);
}

// One harmonic of a sensor's synchronous runout: 1X, an eccentric target; 2X, an oval one
// (ground or worn out of round). The other harmonic stays as it is, so the two can pair.
Effect SensorRunoutHarmonic(const SensorParams& s, double clearance, int order) {
  const std::string name = s.name;
  const std::string x = order == 1 ? "1x" : "2x";
  Effect e;
  e.name = (order == 1 ? "sensor_runout:" : "sensor_runout_2x:") + name;
  e.family = "sensor_runout";
  e.description = order == 1
                      ? fmt::format("synchronous (1X) runout of sensor {}", name)
                      : fmt::format("synchronous 2X runout (oval target) of sensor {}", name);
  // A declared harmonic is refitted from its declared amplitude and phase.
  const SensorRunoutParams& r = s.runout;
  const double a0 = r.enabled ? (order == 1 ? r.amplitude_1x_m : r.amplitude_2x_m) : 0.0;
  const double p0 = r.enabled ? (order == 1 ? r.phase_1x_rad : r.phase_2x_rad) : 0.0;
  e.parameters = {
      {"amplitude_" + x + "_m", 0.0, std::max(0.3 * clearance, 2.0 * a0),
       Distinct({a0, 0.0, 0.02 * clearance})},
      {"phase_" + x + "_rad", -kPi, kPi, Distinct({p0, 0.0, 0.5 * kPi, kPi, -0.5 * kPi}), true}};
  e.parameters[0].declared = a0;
  if (a0 > 0.0) e.description += fmt::format(" (declared {:.4g} m)", a0);
  // The controller acts on the readings: its command shows them too.
  e.revealed_by = {Q::kDisplacement, Q::kControllerCommand};
  e.probe = {0.1 * clearance, 0.0};
  const std::string table = "sensor." + name + ".runout.";
  const std::string other = order == 1 ? "2x" : "1x";
  const bool declared = s.runout.enabled;
  e.overrides = [table, x, other, declared](const std::vector<double>& v) {
    std::vector<std::string> out{SetTrue(table + "enabled"),
                                 Set(table + "amplitude_" + x + "_m", std::abs(v[0])),
                                 Set(table + "phase_" + x + "_rad", std::remainder(v[1], 2 * kPi))};
    // A disabled table's numbers are not declared: the other harmonic stays off.
    if (!declared) out.push_back(Set(table + "amplitude_" + other + "_m", 0.0));
    return out;
  };
  return e;
}

Effect SensorGainOffset(const SensorParams& s, double clearance) {
  const std::string name = s.name;
  Effect e;
  e.name = "sensor_gain_offset:" + name;
  e.family = "sensor_gain_offset";
  e.description = fmt::format("scale error and offset of sensor {}", name);
  e.parameters = {{"gain", 0.7, 1.3, {s.gain}},
                  {"offset_m", -0.5 * clearance, 0.5 * clearance, {s.offset_m}}};
  e.parameters[0].declared = s.gain;
  e.parameters[1].declared = s.offset_m;
  // The controller acts on the readings: its command shows them too.
  e.revealed_by = {Q::kDisplacement, Q::kControllerCommand};
  e.probe = {1.2 * s.gain, s.offset_m + 0.1 * clearance};
  e.overrides = [name](const std::vector<double>& v) {
    return std::vector<std::string>{Set("sensor." + name + ".gain", v[0]),
                                    Set("sensor." + name + ".offset_m", v[1])};
  };
  return e;
}

// The lag of the given sensors, one delay and one filter for all of them (the declared values
// of the first): a sensor's own, or the acquisition chain's that every sensor goes through.
Effect SensorLagOf(const std::vector<const SensorParams*>& sensors, double sample_s,
                   std::string name, std::string description) {
  const SensorParams& s = *sensors.front();
  Effect e;
  e.name = std::move(name);
  e.family = "sensor_lag";
  e.description = std::move(description);
  // The filter as its time constant: 0 is no filter, and the cost is smooth through it.
  // The delay reads between the sensor's samples (controller_if/boundary/sensor_emulator.cpp), so
  // the cost is smooth in it; at most what its ring holds: a rig without a controller samples at
  // every step.
  const double longest = std::min(1e-3, (kMaxSensorDelaySamples - 2) * sample_s);
  // A declared lag is refitted from its declared delay and filter.
  const double d0 = s.lag.enabled ? std::min(s.lag.delay_s, longest) : 0.0;
  const double tau0 = s.lag.enabled && s.lag.cutoff_Hz > 0.0
                          ? std::min(1.0 / (2 * kPi * s.lag.cutoff_Hz), 1e-3)
                          : 0.0;
  e.parameters = {
      {"delay_s", 0.0, longest, Distinct({d0, 0.0, 2 * sample_s, 5 * sample_s})},
      {"filter_time_constant_s", 0.0, 1e-3,
       s.lag.enabled ? Distinct({tau0, 0.0, 2e-4}) : std::vector<double>{0.0, 2e-4, 0.0}}};
  // The declared lag where it is within the fit's bounds (none: 0 and 0).
  if (d0 == s.lag.delay_s || !s.lag.enabled) e.parameters[0].declared = d0;
  if (tau0 < 1e-3 || !s.lag.enabled) e.parameters[1].declared = tau0;
  if (s.lag.enabled) {
    e.description += fmt::format(" (declared {:.4g} s, {:.4g} Hz)", s.lag.delay_s, s.lag.cutoff_Hz);
  }
  // The controller acts on the readings: its command shows them too.
  e.revealed_by = {Q::kDisplacement, Q::kControllerCommand};
  // At the delay's bound: a lag shows only weakly in a drop.
  e.probe = {longest, 5e-4};
  // The filter's time constant becomes its cutoff; below 0.1 us it is no filter (0 Hz).
  std::vector<std::string> tables;
  for (const SensorParams* p : sensors) tables.push_back("sensor." + p->name + ".lag.");
  e.overrides = [tables](const std::vector<double>& v) {
    std::vector<std::string> out;
    for (const std::string& table : tables) {
      out.push_back(SetTrue(table + "enabled"));
      out.push_back(Set(table + "delay_s", std::max(0.0, v[0])));
      out.push_back(Set(table + "cutoff_Hz", v[1] > 1e-7 ? 1.0 / (2 * kPi * v[1]) : 0.0));
    }
    return out;
  };
  return e;
}

Effect SensorLag(const SensorParams& s, double sample_s) {
  return SensorLagOf({&s}, sample_s, "sensor_lag:" + s.name,
                     fmt::format("transport delay and first-order low-pass of sensor {}", s.name));
}

Effect TdbDrag(const TdbParams& t) {
  const std::string name = t.name;
  Effect e;
  e.name = "tdb_drag_torque:" + name;
  e.family = "tdb_drag_torque";
  e.description = fmt::format("constant drag torque on TDB {}'s inner race (seals, windage)", name);
  // A size from 0 over decades: the chaos guard's nudge is a thousandth of the value, not of the
  // 5 N m range (that nudge, 5 mN m, was five times a fitted 0.92 mN m drag).
  e.parameters = {{"drag_torque_N_m", 0.0, 5.0, {0.0, 0.05, 0.5}, false, 0.0, true}};
  e.parameters[0].declared = t.spin.drag_torque_N_m;
  e.revealed_by = {Q::kTdbSpeed, Q::kDisplacement, Q::kRotorSpeed, Q::kTdbSupportForce,
                   Q::kControllerCommand};
  e.probe = {2.0};
  e.overrides = [name](const std::vector<double>& v) {
    return std::vector<std::string>{
        Set("tdb." + name + ".spin.drag_torque_N_m", std::max(0.0, v[0]))};
  };
  return e;
}

// The rotor's own losses once the drive stops (issue 24 item 3: windage, bearing seals, eddy
// currents), one law each, on a rig that declares none: constant T0, viscous c1 W, windage
// c2 W^2 (rotor.coast_down). Their sizes scale with the rotor's polar inertia Ip and its speed
// W0: each range reaches a loss of W0 in 50 ms, and the probe one of W0 in a second (a record
// of 0.1 s after the trigger then loses a tenth of its speed to it).
Effect RotorCoastDown(const char* law, const char* key, double scale) {
  Effect e;
  e.name = std::string("rotor_coast_down_") + law;
  e.family = "rotor_coast_down";
  e.description = fmt::format(
      "{} coast-down torque on the rotor once the drive stops "
      "(rotor.coast_down.{})",
      law, key);
  e.parameters = {{key, 0.0, 20.0 * scale, {0.01 * scale, 0.1 * scale, scale}, false, 0.0, true}};
  e.revealed_by = {Q::kRotorSpeed, Q::kTdbSpeed, Q::kDisplacement};
  e.probe = {scale};
  const std::string full = std::string("rotor.coast_down.") + key;
  e.overrides = [full](const std::vector<double>& v) {
    return std::vector<std::string>{SetTrue("rotor.coast_down.enabled"),
                                    Set(full, std::max(0.0, v[0]))};
  };
  return e;
}

void AddCoastDownEffects(const ModelParams& declared, const ReducedRotor* rotor,
                         std::vector<Effect>* effects) {
  // Declared, its keys are refitted as the registry's other numbers are.
  if (declared.rotor.coast_down.enabled) return;
  const double w0 = declared.simulation.spin_speed_rad_s;
  if (!(w0 > 0.0) || rotor == nullptr) return;
  const double ip = rotor->polar_inertia_kg_m2;
  if (!(ip > 0.0)) return;
  effects->push_back(RotorCoastDown("constant", "constant_torque_N_m", ip * w0));
  effects->push_back(RotorCoastDown("viscous", "viscous_N_m_s", ip));
  effects->push_back(RotorCoastDown("windage", "windage_N_m_s2", ip / w0));
}

// The rotor's weight (N), 0 where the declared model cannot be built (the fit reports that).
double RotorWeightN(const ModelParams& declared, const ReducedRotor* rotor) {
  if (!declared.gravity.enabled || rotor == nullptr) return 0.0;
  return rotor->mass_kg * declared.gravity.acceleration_m_s2;
}

// A TDB's declared linear ribbon: the 4-DOF TDB's Kelvin-Voigt one, or the contact-law TDB's
// bilinear law before crushing (keq, ceq). The ribbon laws replace it in its table.
struct LinearRibbon {
  std::string table;  ///< "tdb.NAME.four_dof." or "tdb.NAME.contact_law."
  double stiffness_N_per_m = 0.0;
  double damping_N_s_per_m = 0.0;
  /// No ribbon declared (a rigid race met by Hunt-Crossley's law): the stiffness is the
  /// contact's own where it carries the TDB's share of the weight, and the race that would ride
  /// a hidden ribbon has its own mass, race_mass_kg (a ribbon law writes it).
  bool derived = false;
  double race_mass_kg = 0.0;
};

// The linear ribbon a ribbon law could replace, if the TDB has one: a 4-DOF TDB with a
// Kelvin-Voigt ribbon, or a contact-law TDB with its bilinear law. In series with the contact
// a massless race needs the ribbon's damping positive; a declared outer_race_mass_kg does not
// (rt_core/contact_law_tdb.hpp).
std::optional<LinearRibbon> LinearRibbonOf(const TdbParams& t, double weight_share_N) {
  if (t.model() == TdbModelKind::kFourDof && t.four_dof().ribbon == RibbonLaw::kKelvinVoigt) {
    return LinearRibbon{"tdb." + t.name + ".four_dof.", t.four_dof().kelvin_voigt.stiffness_N_per_m,
                        t.four_dof().kelvin_voigt.damping_N_s_per_m};
  }
  if (t.model() != TdbModelKind::kContactLaw) return std::nullopt;
  const ContactLawParams& c = t.contact_law();
  if (c.ribbon == ContactLawRibbon::kBilinear && c.normal_law == ContactLawNormal::kHuntCrossley) {
    // A rigid race met by Hunt-Crossley's law declares no ribbon: a hidden one under it is
    // searched on the contact's own stiffness where it carries its share W of the weight,
    // n kn delta^(n-1) = n W / delta at delta = (W / kn)^(1/n) (Jarroux 2019 Eq. (10)), and
    // the race rides it with its own mass (as model #3's outer race, Sec. 4.1, no viscous part
    // beside the Dahl element), taken as a thin ring's, Ieq / Rir^2, from the declared race
    // inertia: the drop's start does not decide the mass beside the slipping stiffness (a
    // record of the independent rig g: 0.158 or 0.3 kg, both at the noise).
    const HuntCrossleyParams& h = c.hunt_crossley;
    const double radius = InnerRaceRadius(t);
    if (!(weight_share_N > 0.0) || !(h.stiffness_N_per_m_n > 0.0) || !t.spin.enabled ||
        !(t.spin.inertia_kg_m2 > 0.0) || !(radius > 0.0)) {
      return std::nullopt;
    }
    const double delta = std::pow(weight_share_N / h.stiffness_N_per_m_n, 1.0 / h.exponent);
    LinearRibbon r{"tdb." + t.name + ".contact_law.", h.exponent * weight_share_N / delta, 0.0};
    r.derived = true;
    r.race_mass_kg = t.spin.inertia_kg_m2 / (radius * radius);
    return r;
  }
  if (c.ribbon == ContactLawRibbon::kBilinear && c.normal_law == ContactLawNormal::kBilinear &&
      (c.ribbon_damping_N_s_per_m > 0.0 || c.outer_race_mass_kg > 0.0)) {
    return LinearRibbon{"tdb." + t.name + ".contact_law.", c.ribbon_stiffness_N_per_m,
                        c.ribbon_damping_N_s_per_m};
  }
  return std::nullopt;
}

// A ribbon law in place of a TDB's linear ribbon: what the ribbon effects share (the quantities
// that reveal them; the overrides the law writes for its values).
Effect RibbonLawEffect(const TdbParams& t, const std::string& family, std::string description,
                       std::vector<EffectParameter> parameters, std::vector<double> probe,
                       std::function<std::vector<std::string>(const std::vector<double>&)> law) {
  Effect e;
  e.name = family + ":" + t.name;
  e.family = family;
  e.description = std::move(description);
  e.parameters = std::move(parameters);
  e.revealed_by = {Q::kDisplacement, Q::kTdbNormalForce, Q::kTdbSupportForce,
                   Q::kControllerCommand};
  e.probe = std::move(probe);
  e.overrides = std::move(law);
  return e;
}

// A linear ribbon that is really a dry-friction one: the generalized Dahl law (Jarroux 2019
// Eq. (1)-(3)) in its place. Three numbers decide a drop on it and none is declared: the
// slipping threshold muFN (the force the housing's bumps hold before they slip), the slipping
// stiffness kslip left once they slip (the paper's reading of a manufacturer's stiffness; a
// ribbon whose bumps slip freely keeps far less, so it is searched over four decades below the
// declared one), and the travel after which the ribbon's stopped ends harden it. The travel is
// where the hardening adds as much as muFN, a exp(b u) = muFN, with the seed-000 rig's shape
// (configs/jarroux2019_industrial_model3.toml: a = 50 N of muFN = 1000 N, so b u = ln 20 = 3);
// beta is that rig's too: the drop barely moves with it. The threshold starts at the TDB's share
// of the rotor's weight (the seed rig's assumption) and three times it.
constexpr double kDahlHardeningShape = 3.0;

Effect RibbonDryFriction(const TdbParams& t, const LinearRibbon& kv, double weight_share_N) {
  const double share = weight_share_N > 0.0 ? weight_share_N : 500.0;
  const double c = t.clearance_m;
  const double k_lo = 1e-4 * kv.stiffness_N_per_m, k_hi = kv.stiffness_N_per_m;
  const double u_lo = 0.1 * c, u_hi = 4.0 * c;
  // A third and two thirds of the way through the decades.
  const auto third = [](double lo, double hi, double f) { return lo * std::pow(hi / lo, f); };
  // A ribbon holding under a twentieth of its static load has no friction worth the name, and
  // its hardening (tied to muFN) would vanish with it.
  EffectParameter threshold{
      "slipping_threshold_N", 0.05 * share, std::max(5000.0, 20.0 * share), {share, 3.0 * share}};
  EffectParameter stiffness{"slipping_stiffness_N_per_m",
                            k_lo,
                            k_hi,
                            {third(k_lo, k_hi, 1.0 / 3.0), third(k_lo, k_hi, 2.0 / 3.0)}};
  stiffness.log_scale = true;
  // A declared crushing capacity is the ribbon's travel before its ends stop it.
  const double crushing_m =
      t.model() == TdbModelKind::kContactLaw ? t.contact_law().ribbon_crushing_m : 0.0;
  EffectParameter travel{
      "hardening_travel_m", u_lo, u_hi,
      crushing_m > u_lo && crushing_m < u_hi
          ? std::vector<double>{0.5 * crushing_m, crushing_m}
          : std::vector<double>{third(u_lo, u_hi, 1.0 / 3.0), third(u_lo, u_hi, 2.0 / 3.0)}};
  travel.log_scale = true;
  // A race with mass declared on the contact-law TDB (outer_race_mass_kg, say a housing on its
  // ribbon) rides the Dahl element with no viscous part beside it, as model #3's outer race
  // (Jarroux 2019 Sec. 4.1): a massless race needs one only to have a rate, and it would add a
  // dissipation the slipping already is. Fitting the mass too was tried: the drop's start does
  // not decide it beside the slipping stiffness (docs/fit.md).
  const bool race_mass =
      t.model() == TdbModelKind::kContactLaw && t.contact_law().outer_race_mass_kg > 0.0;
  return RibbonLawEffect(
      t, "ribbon_dry_friction",
      fmt::format("dry friction in TDB {}'s ribbon: the generalized Dahl law (Jarroux 2019 Eq. "
                  "(1)-(3)) in place of its linear ribbon; slipping threshold, slipping stiffness "
                  "and the travel to its hardening fitted{}",
                  t.name, race_mass ? ", on the declared race mass" : ""),
      {threshold, stiffness, travel}, {3.0 * share, third(k_lo, k_hi, 1.0 / 3.0), c},
      [kv, race_mass](const std::vector<double>& v) {
        const std::string dahl = kv.table + "dahl.";
        const double mu_fn = v[0];
        const double rate_per_m = kDahlHardeningShape / v[2];
        const double hardening_N = mu_fn * std::exp(-kDahlHardeningShape);
        std::vector<std::string> lines{SetText(kv.table + "ribbon", "dahl"),
                                       Set(dahl + "slipping_threshold_N", mu_fn),
                                       Set(dahl + "threshold_scale", 1.0),
                                       Set(dahl + "slipping_stiffness_N_per_m", v[1]),
                                       Set(dahl + "beta_per_m", 1e6),
                                       Set(dahl + "upper_hardening_N", hardening_N),
                                       Set(dahl + "upper_hardening_rate_per_m", rate_per_m),
                                       Set(dahl + "lower_hardening_N", hardening_N),
                                       Set(dahl + "lower_hardening_rate_per_m", rate_per_m)};
        if (race_mass) lines.push_back(Set(kv.table + "ribbon_damping_N_s_per_m", 0.0));
        if (kv.derived) {
          lines.push_back(Set(kv.table + "outer_race_mass_kg", kv.race_mass_kg));
          lines.push_back(Set(kv.table + "ribbon_damping_N_s_per_m", 0.0));
        }
        return lines;
      });
}

// A ribbon whose stiffness is cross-coupled so as to oppose the outer race's whirl (Jarroux
// 2016, seed 001, Eq. (1)); its stiffness and damping are the declared Kelvin-Voigt ones.
Effect RibbonCrossCoupling(const TdbParams& t, const LinearRibbon& kv) {
  return RibbonLawEffect(
      t, "ribbon_cross_coupling",
      fmt::format("cross-coupled stiffness of TDB {}'s ribbon opposing the outer race's whirl "
                  "(Jarroux 2016 Eq. (1)), eta fitted",
                  t.name),
      {{"cross_coupling", 0.0, 2.0, {0.1, 0.5, 1.0}}}, {1.0}, [kv](const std::vector<double>& v) {
        const double eta = v[0];
        const std::string cc = kv.table + "cross_coupled.";
        return std::vector<std::string>{SetText(kv.table + "ribbon", "cross_coupled"),
                                        Set(cc + "stiffness_N_per_m", kv.stiffness_N_per_m),
                                        Set(cc + "damping_N_s_per_m", kv.damping_N_s_per_m),
                                        Set(cc + "cross_coupling", std::max(0.0, eta))};
      });
}

// The registry's entry for a key, or (a table the config leaves out, so no reader logged it) one
// made from the value in force, with the reader's lower bound.
ConfigKey KeyOr(const std::vector<ConfigKey>& keys, const std::string& path, double value,
                bool zero_allowed) {
  if (const ConfigKey* k = FindKey(keys, path)) return *k;
  ConfigKey k;
  k.path = path;
  k.unit = KeyUnit(path.substr(path.rfind('.') + 1));
  k.key_class = ClassOfKey(path);
  k.value = value;
  k.declared = false;
  k.lower = 0.0;
  k.lower_inclusive = zero_allowed;
  return k;
}

// The races' spin laws that a record's race speeds (and the journal's slip) reveal: the inertia
// and the viscous damping of each race (Jarroux 2019 Eq. (9): Ieq Omega' + Phi Omega = ...),
// per TDB and, where there are several, every race's together (one supplier, one grease).
// Their drag torque alone is hand-made (TdbDrag): a size from 0 with its own nudge.
void AddRaceSpinEffects(const LoadedConfig& config, std::vector<Effect>* effects) {
  const ModelParams& declared = config.params;
  std::vector<ConfigKey> inertias, dampings, drags;
  const std::vector<Q> spin_shows = {Q::kTdbSpeed, Q::kDisplacement, Q::kRotorSpeed,
                                     Q::kTdbSupportForce, Q::kControllerCommand};
  for (const TdbParams& t : declared.tdbs) {
    if (!HasDragTorque(t)) continue;
    const std::string table = "tdb." + t.name + ".spin.";
    inertias.push_back(KeyOr(config.keys, table + "inertia_kg_m2", t.spin.inertia_kg_m2, false));
    dampings.push_back(KeyOr(config.keys, table + "rotational_damping_N_m_s",
                             t.spin.rotational_damping_N_m_s, true));
    drags.push_back(KeyOr(config.keys, table + "drag_torque_N_m", t.spin.drag_torque_N_m, true));
    effects->push_back(DeclaredValueOff(
        inertias.back(),
        {"tdb_race_inertia:" + t.name, "tdb_race_inertia",
         fmt::format("polar inertia of TDB {}'s inner race (declared {:.4g} kg m^2)", t.name,
                     t.spin.inertia_kg_m2),
         spin_shows}));
    effects->push_back(DeclaredValueOff(
        dampings.back(),
        {"tdb_race_damping:" + t.name, "tdb_race_damping",
         fmt::format("viscous damping of TDB {}'s inner race spin (declared {:.4g} N m s)", t.name,
                     t.spin.rotational_damping_N_m_s),
         spin_shows}));
  }
  if (inertias.size() < 2) return;
  effects->push_back(DeclaredValuesTogether(
      inertias, {"tdb_race_inertia", "tdb_race_inertia",
                 "polar inertia of every TDB's inner race, scaled together", spin_shows}));
  effects->push_back(DeclaredValuesTogether(
      dampings, {"tdb_race_damping", "tdb_race_damping",
                 "viscous damping of every TDB's inner race spin, together", spin_shows}));
  Effect drag = DeclaredValuesTogether(
      drags, {"tdb_drag_torque", "tdb_drag_torque",
              "drag torque on every TDB's inner race, together (seals, windage)", spin_shows});
  if (drag.parameters.front().name != "scale") {
    // None declared: the per-TDB drag's range and starts, a size from 0 over decades.
    drag.parameters = {{"drag_torque_N_m", 0.0, 5.0, {0.0, 0.05, 0.5}, false, 0.0, true}};
    drag.parameters[0].declared = 0.0;
    drag.probe = {2.0};
  }
  effects->push_back(std::move(drag));
}

}  // namespace

std::vector<Effect> EffectLibrary(const ConfigVariants& variants, bool only_families) {
  const LoadedConfig& config = variants.declared();
  const ModelParams& declared = config.params;
  std::vector<Effect> effects;
  // The declared rotor, built once: its centre of mass, inertia and weight place and size
  // candidates below. None where the declared model cannot be built (the fit reports that).
  std::optional<ReducedRotor> built;
  try {
    built = BuildModel(declared).rotor;
  } catch (const std::exception&) {
  }
  const ReducedRotor* rotor = built ? &*built : nullptr;
  const double clearance = SmallestClearance(declared);
  for (const TdbParams& t : declared.tdbs) effects.push_back(TdbMisalignment(t));
  for (const TdbParams& t : declared.tdbs) effects.push_back(TdbClearance(t));
  if (std::any_of(declared.tdbs.begin(), declared.tdbs.end(), HasFriction)) {
    effects.push_back(FrictionCoefficient(declared));
    // Per TDB too where there are several: the common coefficient is the one a record of
    // equal TDBs names (one parameter, where a pair would take two).
    if (std::count_if(declared.tdbs.begin(), declared.tdbs.end(), HasFriction) > 1) {
      for (const TdbParams& t : declared.tdbs) {
        if (HasFriction(t)) effects.push_back(FrictionCoefficientAt(t));
      }
    }
  }
  const auto [lo, hi] = TdbSpan(declared);
  effects.push_back(Unbalance(rotor != nullptr ? rotor->centre_of_mass_m : 0.5 * (lo + hi)));
  // Only where the TDB planes are apart, and there is room for its two masses.
  if (hi > lo && declared.unbalances.size() + 3 <= static_cast<std::size_t>(kMaxUnbalances)) {
    effects.push_back(CoupleUnbalance(declared));
  }
  // Declared or not (issue 23: a declared decay at the wrong time constant must be refitted).
  if (!declared.ambs.empty()) {
    effects.push_back(FluxDecay(declared));
    effects.push_back(FluxDecayHold(declared));
    for (const bool hold : {true, false}) {
      if (std::optional<Effect> part = FluxDecayHoldPart(declared, hold)) {
        effects.push_back(std::move(*part));
      }
    }
    if (declared.ambs.size() > 1) {
      for (const AmbParams& a : declared.ambs) effects.push_back(FluxDecayAt(a));
    }
  }
  // The sensors are sampled at the controller's rate, or at every step without a controller.
  const double sensor_sample_s = declared.controller.kind == ControllerKind::kNone
                                     ? declared.simulation.step_s
                                     : 1.0 / declared.controller.rate_Hz;
  for (const SensorParams& s : declared.sensors) {
    effects.push_back(SensorRunoutHarmonic(s, clearance, 1));
    effects.push_back(SensorRunoutHarmonic(s, clearance, 2));
    effects.push_back(SensorGainOffset(s, clearance));
    effects.push_back(SensorLag(s, sensor_sample_s));
  }
  if (declared.sensors.size() > 1) {
    std::vector<const SensorParams*> all;
    for (const SensorParams& s : declared.sensors) all.push_back(&s);
    effects.push_back(SensorLagOf(
        all, sensor_sample_s, "sensor_lag",
        "one transport delay and first-order low-pass on every sensor (the acquisition chain)"));
  }
  for (const TdbParams& t : declared.tdbs) {
    if (HasDragTorque(t)) effects.push_back(TdbDrag(t));
  }
  AddRaceSpinEffects(config, &effects);
  AddCoastDownEffects(declared, rotor, &effects);
  // Ribbon laws replace a declared linear ribbon (issue 15: the contact-law TDB's too).
  const double share_N = RotorWeightN(declared, rotor) / static_cast<double>(declared.tdbs.size());
  for (const TdbParams& t : declared.tdbs) {
    const std::optional<LinearRibbon> ribbon = LinearRibbonOf(t, share_N);
    if (!ribbon) continue;
    effects.push_back(RibbonDryFriction(t, *ribbon, share_N));
    // Cross-coupling needs a declared ribbon's stiffness: it fits eta alone.
    if (!ribbon->derived) effects.push_back(RibbonCrossCoupling(t, *ribbon));
  }
  if (only_families) return effects;
  std::vector<Effect> keys = RegistryCandidates(variants, effects);
  std::move(keys.begin(), keys.end(), std::back_inserter(effects));
  return effects;
}

bool Decidable(const Effect& effect, const MeasurementParams& m) {
  for (const MeasurementChannel& ch : m.channels) {
    if (std::find(effect.revealed_by.begin(), effect.revealed_by.end(), ch.quantity) !=
        effect.revealed_by.end()) {
      return true;
    }
  }
  return false;
}

}  // namespace ambdrop
