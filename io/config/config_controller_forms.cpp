#include "io/config/config_controller_forms.hpp"

#include <fmt/format.h>

#include <string>

namespace ambdrop::config_detail {
namespace {

Discretisation ReadDiscretisation(const TableReader& t, Discretisation fallback) {
  const char* names[] = {"tustin", "zoh", "backward_euler"};
  const std::string name = t.Choice("discretisation", {"tustin", "zoh", "backward_euler"},
                                    names[static_cast<int>(fallback)]);
  if (name == "zoh") return Discretisation::kZeroOrderHold;
  if (name == "backward_euler") return Discretisation::kBackwardEuler;
  return Discretisation::kTustin;
}

double ReadPrewarp(const TableReader& t, double rate_Hz, double fallback) {
  const double nyquist = rate_Hz / 2.0;
  return t.Number("prewarp_Hz",
                  NonNegativeBelow(nyquist, fmt::format("a frequency in [0, {:.6g}) (0: none; "
                                                        "below the Nyquist frequency rate_Hz / 2)",
                                                        nyquist)),
                  fallback);
}

std::array<double, 3> ReadTriple(const TableReader& t, std::string_view key,
                                 std::string_view expected) {
  const toml::array* array = t.OptionalArray(key, expected);
  if (array == nullptr) t.FailMissing(key, expected);
  if (array->size() != 3) t.Fail(key, expected);
  std::array<double, 3> out{};
  for (std::size_t i = 0; i < 3; ++i) {
    out[i] = ReadNumber((*array)[i], t.source_name(), fmt::format("{}[{}]", t.KeyPath(key), i),
                        AnyNumber(), expected);
  }
  return out;
}

int Degree(const std::array<double, 3>& s_coefficients) {
  if (s_coefficients[0] != 0.0) return 2;
  if (s_coefficients[1] != 0.0) return 1;
  return 0;
}

ControllerSectionParams ReadSection(const TableReader& t, double rate_Hz,
                                    Discretisation discretisation, double prewarp_Hz) {
  ControllerSectionParams s;
  const std::string kind =
      t.Choice("kind", {"gain", "pid", "lead_lag", "notch", "low_pass", "s_biquad", "z_biquad"});
  const auto allow = [&](std::vector<std::string_view> keys) {
    keys.push_back("kind");
    if (kind != "z_biquad") {
      keys.push_back("discretisation");
      keys.push_back("prewarp_Hz");
    }
    t.AllowOnly(keys);
  };
  if (kind == "gain") {
    allow({"gain"});
    s.kind = SectionKind::kGain;
    s.gain = t.Number("gain", AnyNumber());
  } else if (kind == "pid") {
    allow({"kp", "ki_per_s", "kd_s", "derivative_filter_s"});
    s.kind = SectionKind::kPid;
    s.kp = t.Number("kp", NonNegative(), 0.0);
    s.ki_per_s = t.Number("ki_per_s", NonNegative(), 0.0);
    s.kd_s = t.Number("kd_s", NonNegative(), 0.0);
    s.derivative_filter_s = t.Number("derivative_filter_s", NonNegative(), 0.0);
  } else if (kind == "lead_lag") {
    allow({"zero_Hz", "pole_Hz", "gain"});
    s.kind = SectionKind::kLeadLag;
    s.zero_Hz = t.Number("zero_Hz", Positive());
    s.pole_Hz = t.Number("pole_Hz", Positive());
    s.gain = t.Number("gain", AnyNumber(), 1.0);
  } else if (kind == "notch") {
    allow({"frequency_Hz", "zero_damping", "pole_damping"});
    s.kind = SectionKind::kNotch;
    s.frequency_Hz = t.Number("frequency_Hz", Positive());
    s.pole_damping = t.Number("pole_damping", Positive());
    s.zero_damping = t.Number("zero_damping", NonNegative(), 0.0);
  } else if (kind == "low_pass") {
    allow({"cutoff_Hz", "order", "damping_ratio"});
    s.kind = SectionKind::kLowPass;
    s.cutoff_Hz = t.Number("cutoff_Hz", Positive());
    s.order = t.Integer("order", 1, 2, 1);
    if (s.order == 2) s.damping_ratio = t.Number("damping_ratio", Positive(), s.damping_ratio);
    if (s.order == 1) t.Reject("damping_ratio", "no damping_ratio for a first-order low-pass");
  } else if (kind == "s_biquad" || kind == "z_biquad") {
    allow({"numerator", "denominator"});
    const bool z = kind == "z_biquad";
    s.kind = z ? SectionKind::kZBiquad : SectionKind::kSBiquad;
    const std::string_view powers = z ? "of 1, z^-1, z^-2" : "of s^2, s, 1";
    s.numerator = ReadTriple(t, "numerator", fmt::format("3 finite numbers, {}", powers));
    s.denominator = ReadTriple(t, "denominator", fmt::format("3 finite numbers, {}", powers));
    if (z && s.denominator[0] == 0.0) {
      t.Fail("denominator", "a first coefficient (of 1) other than 0");
    }
    if (!z && s.denominator == std::array<double, 3>{}) {
      t.Fail("denominator", "a denominator other than 0");
    }
  }
  s.discretisation = ReadDiscretisation(t, discretisation);
  s.prewarp_Hz = ReadPrewarp(t, rate_Hz, prewarp_Hz);
  // More zeros than poles: only backward Euler gives a causal section.
  if (s.discretisation != Discretisation::kBackwardEuler) {
    if (s.kind == SectionKind::kPid && s.kd_s > 0.0 && s.derivative_filter_s == 0.0) {
      t.Fail("derivative_filter_s",
             "a derivative filter > 0 s (an unfiltered derivative is improper: only "
             "discretisation = \"backward_euler\" can take it)");
    }
    if (s.kind == SectionKind::kSBiquad && Degree(s.numerator) > Degree(s.denominator)) {
      t.Fail("numerator",
             "a numerator of degree <= the denominator's (an improper section needs "
             "discretisation = \"backward_euler\")");
    }
  }
  return s;
}

bool Integrates(const ControllerSectionParams& s) {
  switch (s.kind) {
    case SectionKind::kPid:
      return s.ki_per_s > 0.0;
    case SectionKind::kSBiquad:
      return s.denominator[2] == 0.0;
    case SectionKind::kZBiquad:
      return s.denominator[0] + s.denominator[1] + s.denominator[2] == 0.0;
    default:
      return false;
  }
}

}  // namespace

LinearControllerParams ReadLinearController(const TableReader& t, double rate_Hz) {
  t.AllowOnly({"sensor_gain_V_per_m", "amplifier_gain_A_per_V", "gravity_feedforward",
               "discretisation", "prewarp_Hz", "anti_windup", "back_calculation_time_s",
               "sections"});
  LinearControllerParams p;
  p.sensor_gain_V_per_m = t.Number("sensor_gain_V_per_m", Positive(), p.sensor_gain_V_per_m);
  p.amplifier_gain_A_per_V =
      t.Number("amplifier_gain_A_per_V", Positive(), p.amplifier_gain_A_per_V);
  p.gravity_feedforward = t.Bool("gravity_feedforward", p.gravity_feedforward);
  const Discretisation discretisation = ReadDiscretisation(t, Discretisation::kTustin);
  const double prewarp_Hz = ReadPrewarp(t, rate_Hz, 0.0);
  const std::string anti_windup =
      t.Choice("anti_windup", {"conditional", "back_calculation", "none"}, "conditional");
  const std::vector<TableReader> sections = t.TableArray("sections");
  if (sections.empty()) {
    const std::string expected = "at least one section ([[controller.linear.sections]])";
    if (t.Has("sections")) t.Fail("sections", expected);
    t.FailMissing("sections", expected);
  }
  t.CheckCount("sections", sections.size(), kMaxControllerSections, "sections");
  for (const TableReader& section : sections) {
    p.sections.push_back(ReadSection(section, rate_Hz, discretisation, prewarp_Hz));
  }
  if (anti_windup == "back_calculation") {
    p.anti_windup = AntiWindup::kBackCalculation;
    p.back_calculation_time_s = t.Number("back_calculation_time_s", Positive());
    bool integrates = false;
    for (const ControllerSectionParams& s : p.sections) integrates = integrates || Integrates(s);
    if (!integrates) {
      t.Fail("anti_windup",
             "\"back_calculation\" only with a section that integrates (a pid with ki_per_s > 0)");
    }
  } else {
    p.anti_windup = anti_windup == "none" ? AntiWindup::kNone : AntiWindup::kConditional;
    t.Reject("back_calculation_time_s",
             "no back_calculation_time_s (read only with anti_windup = \"back_calculation\")");
  }
  return p;
}

AmplifierParams ReadAmplifier(const TableReader& t) {
  t.AllowOnly({"enabled", "order", "bandwidth_Hz", "damping_ratio", "slew_rate_A_per_s"});
  AmplifierParams a;
  a.enabled = t.Bool("enabled", a.enabled);
  // A disabled loop does not demand its numbers; given, they are still checked.
  a.order = t.Integer("order", 1, 2, a.order);
  a.bandwidth_Hz = a.enabled ? t.Number("bandwidth_Hz", Positive())
                             : t.Number("bandwidth_Hz", Positive(), a.bandwidth_Hz);
  if (a.order == 2) {
    a.damping_ratio = t.Number("damping_ratio", Positive(), a.damping_ratio);
  } else {
    t.Reject("damping_ratio", "no damping_ratio for a first-order loop (order = 1)");
  }
  a.slew_rate_A_per_s = t.Number("slew_rate_A_per_s", Positive(), a.slew_rate_A_per_s);
  return a;
}

}  // namespace ambdrop::config_detail
