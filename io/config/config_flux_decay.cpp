// [amb.NAME.flux_decay]: how the coil currents fall after power loss
// (rt_core/power_loss_drive.hpp).
#include <fmt/format.h>

#include <string>
#include <string_view>

#include "io/config/config_readers.hpp"

namespace ambdrop::config_detail {
namespace {

constexpr std::string_view kExponential = "exponential";
constexpr std::string_view kRamp = "slew_limited_ramp";
constexpr std::string_view kHold = "hold_then_exponential";

/// A key of another current law gets a message naming the law that owns it. Except where
/// --set switched the law and the key is the file's: the file's numbers of the law it replaced
/// are left unused, so that trying another law (a user's --set, a fit's candidate) needs no
/// way to delete them. In the file itself, and given by --set, such a key is still an error.
void RejectKeyOfOtherLaw(const TableReader& table, std::string_view key, std::string_view law,
                         std::string_view owner) {
  if (table.FromOverride("current_law") && table.Has(key) && !table.FromOverride(key)) return;
  table.Reject(key, fmt::format("no {} with current_law = \"{}\" (it belongs to current_law = {})",
                                key, law, owner));
}

}  // namespace

FluxDecayParams ReadFluxDecay(const TableReader& amb_table, const AmbParams& amb) {
  FluxDecayParams d;
  const std::optional<TableReader> table = amb_table.OptionalTable("flux_decay");
  if (!table) return d;
  table->AllowOnly({"enabled", "current_law", "time_constant_s", "slew_rate_A_per_s", "hold_time_s",
                    "bias_current_A"});
  d.enabled = table->Bool("enabled", false);
  const std::string law = table->Choice("current_law", {kExponential, kRamp, kHold}, kExponential);
  // A disabled table does not demand its numbers (a fit may switch it on with --set), but the
  // ones given are still checked.
  const auto number = [&](std::string_view key, const NumberRule& rule) {
    return d.enabled ? table->Number(key, rule) : table->Number(key, rule, 0.0);
  };
  if (law == kRamp) {
    if (amb.law == AmbForceLaw::kEquivalent) {
      table->Fail("current_law",
                  "\"exponential\" or \"hold_then_exponential\" with law = \"equivalent\" (a "
                  "slew-limited ramp needs coil currents: law = \"linearised_currents\" or "
                  "\"electromagnet\")",
                  "\"slew_limited_ramp\"");
    }
    RejectKeyOfOtherLaw(*table, "time_constant_s", law,
                        "\"exponential\" or \"hold_then_exponential\"");
    RejectKeyOfOtherLaw(*table, "hold_time_s", law, "\"hold_then_exponential\"");
    d.current_law = PowerLossCurrentLaw::kSlewLimitedRamp;
    d.slew_rate_A_per_s = number("slew_rate_A_per_s", Positive());
    // Only a linearised-law AMB with an electromagnet bias lacks the coils' I0 the ramp drains.
    if (amb.bias_source == AmbBiasSource::kPermanentMagnet) {
      table->Reject("bias_current_A",
                    "no bias_current_A with bias_source = \"permanent_magnet\" (the magnet's bias "
                    "does not ramp)");
    } else if (amb.law == AmbForceLaw::kElectromagnet) {
      table->Reject("bias_current_A",
                    "no bias_current_A with law = \"electromagnet\" (electromagnet.bias_current_A "
                    "is the coils' bias)");
    } else {
      d.bias_current_A = number("bias_current_A", Positive());
    }
    return d;
  }
  RejectKeyOfOtherLaw(*table, "slew_rate_A_per_s", law, "\"slew_limited_ramp\"");
  RejectKeyOfOtherLaw(*table, "bias_current_A", law, "\"slew_limited_ramp\"");
  d.time_constant_s = number("time_constant_s", Positive());
  if (law == kHold) {
    d.current_law = PowerLossCurrentLaw::kHoldThenExponential;
    d.hold_time_s = number("hold_time_s", NonNegative());
  } else {
    RejectKeyOfOtherLaw(*table, "hold_time_s", law, "\"hold_then_exponential\"");
  }
  return d;
}

}  // namespace ambdrop::config_detail
