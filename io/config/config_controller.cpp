#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "io/config/config_controller_forms.hpp"
#include "io/config/config_readers.hpp"

namespace ambdrop::config_detail {

ControllerParams ReadController(const TableReader& root, double step_s) {
  ControllerParams c;
  const auto table = root.OptionalTable("controller");
  if (!table) return c;
  table->AllowOnly({"kind", "rate_Hz", "pid", "linear", "delay_samples", "amplifier"});
  // The kind picks the one controller form; the other form's table, if a base file brings one,
  // is checked but not used.
  const std::string kind =
      table->Choice("kind", {"none", "internal_pid", "internal_linear"}, "none");
  c.kind = kind == "none" ? ControllerKind::kNone : ControllerKind::kInternalPid;
  c.form = kind == "internal_linear" ? ControllerForm::kLinear : ControllerForm::kPid;
  c.rate_Hz = table->Number("rate_Hz", Positive(), c.rate_Hz);
  // The loop runs whole steps per controller period (ControllerSubsteps, which says the same
  // without a file and line).
  const double steps = 1.0 / (c.rate_Hz * step_s);
  const double whole = std::round(steps);
  if (table->Has("rate_Hz") && (whole < 1.0 || std::abs(steps - whole) > 1e-6 * steps)) {
    const double nearest_Hz = 1.0 / (std::max(whole, 1.0) * step_s);
    table->Fail("rate_Hz",
                fmt::format("a rate whose period is a whole number of steps of simulation.step_s "
                            "= {:.6g} s (e.g. {:.6g} Hz)",
                            step_s, nearest_Hz),
                fmt::format("{:.6g} Hz, a period of {:.6g} steps", c.rate_Hz, steps));
  }
  if (const auto pid = table->OptionalTable("pid")) {
    pid->AllowOnly({"sensor_gain_V_per_m", "amplifier_gain_A_per_V", "kp", "ki_per_s", "kd_s",
                    "derivative_filter_s", "gravity_feedforward"});
    PidParams& p = c.pid;
    p.sensor_gain_V_per_m = pid->Number("sensor_gain_V_per_m", Positive(), p.sensor_gain_V_per_m);
    p.amplifier_gain_A_per_V =
        pid->Number("amplifier_gain_A_per_V", Positive(), p.amplifier_gain_A_per_V);
    p.kp = pid->Number("kp", NonNegative());
    p.ki_per_s = pid->Number("ki_per_s", NonNegative());
    p.kd_s = pid->Number("kd_s", NonNegative());
    p.derivative_filter_s = pid->Number("derivative_filter_s", NonNegative());
    p.gravity_feedforward = pid->Bool("gravity_feedforward", p.gravity_feedforward);
  } else if (kind == "internal_pid") {
    table->Table("pid");  // reports the missing table
  }
  if (const auto linear = table->OptionalTable("linear")) {
    c.linear = ReadLinearController(*linear, c.rate_Hz);
  } else if (kind == "internal_linear") {
    table->Table("linear");  // reports the missing table
  }
  c.delay_samples = table->Integer("delay_samples", 0, kMaxDelaySamples, c.delay_samples);
  if (const auto amplifier = table->OptionalTable("amplifier")) {
    c.amplifier = ReadAmplifier(*amplifier);
  }
  return c;
}

}  // namespace ambdrop::config_detail
