#include "io/config_readers.hpp"

namespace ambdrop::config_detail {

ControllerParams ReadController(const TableReader& root) {
  ControllerParams c;
  const auto table = root.OptionalTable("controller");
  if (!table) return c;
  table->AllowOnly({"kind", "rate_Hz", "pid"});
  const std::string kind = table->Choice("kind", {"none", "internal_pid"}, "none");
  c.kind = kind == "internal_pid" ? ControllerKind::kInternalPid : ControllerKind::kNone;
  c.rate_Hz = table->Number("rate_Hz", Positive(), c.rate_Hz);
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
