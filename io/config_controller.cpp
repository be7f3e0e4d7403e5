#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "io/config_readers.hpp"

namespace ambdrop::config_detail {

ControllerParams ReadController(const TableReader& root, double step_s) {
  ControllerParams c;
  const auto table = root.OptionalTable("controller");
  if (!table) return c;
  table->AllowOnly({"kind", "rate_Hz", "pid"});
  const std::string kind = table->Choice("kind", {"none", "internal_pid"}, "none");
  c.kind = kind == "internal_pid" ? ControllerKind::kInternalPid : ControllerKind::kNone;
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
  } else if (c.kind == ControllerKind::kInternalPid) {
    table->Table("pid");  // reports the missing table
  }
  return c;
}

}  // namespace ambdrop::config_detail
