#include "io/config/config_measurement.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string_view>
#include <utility>

#include "io/config/toml_reader.hpp"

namespace ambdrop {
namespace {

using config_detail::NonNegative;
using config_detail::NumberRule;
using config_detail::TableReader;

constexpr std::array<std::pair<std::string_view, MeasuredQuantity>, 7> kQuantities = {{
    {"displacement", MeasuredQuantity::kDisplacement},
    {"current", MeasuredQuantity::kCurrent},
    {"controller_command", MeasuredQuantity::kControllerCommand},
    {"tdb_normal_force", MeasuredQuantity::kTdbNormalForce},
    {"tdb_support_force", MeasuredQuantity::kTdbSupportForce},
    {"tdb_speed", MeasuredQuantity::kTdbSpeed},
    {"rotor_speed", MeasuredQuantity::kRotorSpeed},
}};

bool TakesSensor(MeasuredQuantity q) {
  return q == MeasuredQuantity::kDisplacement;
}
bool TakesAmb(MeasuredQuantity q) {
  return q == MeasuredQuantity::kCurrent || q == MeasuredQuantity::kControllerCommand;
}
bool TakesTdb(MeasuredQuantity q) {
  return q == MeasuredQuantity::kTdbNormalForce || q == MeasuredQuantity::kTdbSpeed ||
         q == MeasuredQuantity::kTdbSupportForce;
}
bool TakesAxis(MeasuredQuantity q) {
  return q == MeasuredQuantity::kDisplacement || q == MeasuredQuantity::kCurrent ||
         q == MeasuredQuantity::kControllerCommand || q == MeasuredQuantity::kTdbSupportForce;
}

/// "current and controller_command": the quantities that take a key, for messages.
template <typename Predicate>
std::string QuantitiesThat(Predicate takes) {
  std::vector<std::string_view> names;
  for (const auto& [name, q] : kQuantities) {
    if (takes(q)) names.push_back(name);
  }
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) out += i + 1 == names.size() ? " and " : ", ";
    out += names[i];
  }
  return out;
}

std::string TakeVerb(std::size_t count) {
  return count == 1 ? "takes" : "take";
}

enum class Dimension { kLength, kCurrent, kForce, kSpeed };

Dimension DimensionOf(MeasuredQuantity q) {
  switch (q) {
    case MeasuredQuantity::kDisplacement:
      return Dimension::kLength;
    case MeasuredQuantity::kCurrent:
    case MeasuredQuantity::kControllerCommand:
      return Dimension::kCurrent;
    case MeasuredQuantity::kTdbNormalForce:
    case MeasuredQuantity::kTdbSupportForce:
      return Dimension::kForce;
    case MeasuredQuantity::kTdbSpeed:
    case MeasuredQuantity::kRotorSpeed:
      break;
  }
  return Dimension::kSpeed;
}

struct UnitSpelling {
  std::string_view name;
  Dimension dimension;
  double si_per_unit;
};

// A small fixed table: what loggers and rig sheets write. A spelling outside it is an error,
// never a guess.
constexpr double kRevolution_rad = 2.0 * std::numbers::pi;
constexpr std::array<UnitSpelling, 12> kUnits = {{
    {"m", Dimension::kLength, 1.0},
    {"mm", Dimension::kLength, 1e-3},
    {"um", Dimension::kLength, 1e-6},
    {"\xC2\xB5m", Dimension::kLength, 1e-6},  // µm in UTF-8
    {"A", Dimension::kCurrent, 1.0},
    {"mA", Dimension::kCurrent, 1e-3},
    {"N", Dimension::kForce, 1.0},
    {"kN", Dimension::kForce, 1e3},
    {"rad/s", Dimension::kSpeed, 1.0},
    {"rpm", Dimension::kSpeed, kRevolution_rad / 60.0},
    {"Hz", Dimension::kSpeed, kRevolution_rad},
    {"rev/s", Dimension::kSpeed, kRevolution_rad},
}};

std::string_view DimensionName(Dimension d) {
  switch (d) {
    case Dimension::kLength:
      return "length";
    case Dimension::kCurrent:
      return "current";
    case Dimension::kForce:
      return "force";
    case Dimension::kSpeed:
      break;
  }
  return "speed";
}

std::string SpellingsOf(Dimension d) {
  std::string out;
  for (const UnitSpelling& u : kUnits) {
    if (u.dimension != d) continue;
    out += fmt::format("{}{:?}", out.empty() ? "" : ", ", u.name);
  }
  return out;
}

constexpr std::array<std::pair<std::string_view, double>, 3> kTimeUnits = {{
    {"s", 1.0},
    {"ms", 1e-3},
    {"us", 1e-6},
}};

/// The index of the component `key` names, in the model's order.
template <typename Component>
int ReadComponent(const TableReader& t, std::string_view key, const std::vector<Component>& list,
                  std::string_view noun) {
  std::string names;
  for (const Component& c : list) names += fmt::format("{}{:?}", names.empty() ? "" : ", ", c.name);
  const std::string expected =
      fmt::format("the name of one of the rig's {} ({})", noun, names.empty() ? "none" : names);
  const toml::node* node = t.Find(key);
  if (node == nullptr) t.FailMissing(key, expected);
  if (node->is_string()) {
    for (std::size_t i = 0; i < list.size(); ++i) {
      if (list[i].name == node->as_string()->get()) return static_cast<int>(i);
    }
  }
  t.Fail(key, expected);
}

// A misplaced name is usually a copy-paste slip between channels, so the message says which
// quantity the key belongs to rather than only that it is unknown here.
void RejectForeignKey(const TableReader& t, MeasuredQuantity q, std::string_view key,
                      bool (*takes)(MeasuredQuantity)) {
  if (takes(q)) return;
  std::size_t count = 0;
  for (const auto& [name, other] : kQuantities) count += takes(other) ? 1 : 0;
  t.Reject(key, fmt::format("no {} for {} (only {} {} {})", key, MeasuredQuantityName(q),
                            QuantitiesThat(takes), TakeVerb(count), key));
}

void RejectForeignKeys(const TableReader& t, MeasuredQuantity q) {
  RejectForeignKey(t, q, "sensor", TakesSensor);
  RejectForeignKey(t, q, "amb", TakesAmb);
  RejectForeignKey(t, q, "tdb", TakesTdb);
  RejectForeignKey(t, q, "axis", TakesAxis);
}

// `unit` (a spelling of the quantity's dimension) or `scale` (SI per record unit), not both.
void ReadUnit(const TableReader& t, MeasurementChannel* channel) {
  const Dimension dimension = DimensionOf(channel->quantity);
  if (t.Has("unit") && t.Has("scale")) {
    t.Fail("scale", "no scale with unit (give one or the other)");
  }
  if (t.Has("unit")) {
    const std::string expected =
        fmt::format("a unit of {} for {} (one of {})", DimensionName(dimension),
                    MeasuredQuantityName(channel->quantity), SpellingsOf(dimension));
    const toml::node* node = t.Find("unit");
    if (!node->is_string()) t.Fail("unit", expected);
    const std::string unit = node->as_string()->get();
    for (const UnitSpelling& u : kUnits) {
      if (u.name != unit) continue;
      if (u.dimension != dimension) {
        t.Fail("unit", expected,
               fmt::format("{:?} (a unit of {})", unit, DimensionName(u.dimension)));
      }
      channel->scale = u.si_per_unit;
      channel->unit = unit;
      return;
    }
    t.Fail("unit", expected);
  }
  if (t.Has("scale")) {
    const std::string what = fmt::format("a finite, non-zero number ({} per record unit)",
                                         MeasuredQuantitySiUnit(channel->quantity));
    const double scale = t.Number("scale", NumberRule{.what = what});
    if (scale == 0.0) t.Fail("scale", what, "0");
    channel->scale = scale;
  }
}

void ReadWindow(const TableReader& t, MeasurementChannel* channel) {
  const std::string window = t.Choice("window", {"all", "before_trigger", "after_trigger"}, "all");
  channel->window = window == "before_trigger"  ? ChannelWindow::kBeforeTrigger
                    : window == "after_trigger" ? ChannelWindow::kAfterTrigger
                                                : ChannelWindow::kAll;
  const NumberRule seconds{.what = "a number of seconds relative to the trigger"};
  channel->from_s = t.OptionalNumber("from_s", seconds);
  channel->to_s = t.OptionalNumber("to_s", seconds);
  if (channel->from_s && channel->to_s && !(*channel->from_s < *channel->to_s)) {
    t.Fail("to_s", fmt::format("a time after from_s ({} s)", *channel->from_s),
           fmt::format("{}", *channel->to_s));
  }
  // A window that cannot hold a sample whatever the record: after_trigger ending before it,
  // before_trigger starting after it.
  const bool empty =
      (channel->window == ChannelWindow::kAfterTrigger && channel->to_s && *channel->to_s <= 0) ||
      (channel->window == ChannelWindow::kBeforeTrigger && channel->from_s &&
       *channel->from_s >= 0);
  if (empty) {
    t.Fail(channel->to_s && channel->window == ChannelWindow::kAfterTrigger ? "to_s" : "from_s",
           fmt::format("a bound that leaves the window \"{}\" some time", window));
  }
}

MeasurementChannel ReadChannel(const TableReader& t, const ModelParams& params,
                               const std::string& time_column) {
  t.AllowOnly({"column", "quantity", "sensor", "amb", "tdb", "axis", "unit", "scale", "window",
               "from_s", "to_s"});
  MeasurementChannel channel;
  channel.column = t.String("column");
  if (channel.column.empty()) t.Fail("column", "a non-empty CSV column name");
  // The time column (io/files/measured_csv.hpp) is never a channel.
  if (channel.column == time_column) {
    t.Fail("column", fmt::format("a column other than {:?} (the record's time)", time_column));
  }
  std::vector<std::string_view> names;
  for (const auto& [name, q] : kQuantities) names.push_back(name);
  const std::string quantity = t.Choice("quantity", names);
  for (const auto& [name, q] : kQuantities) {
    if (name == quantity) channel.quantity = q;
  }
  RejectForeignKeys(t, channel.quantity);
  if (TakesSensor(channel.quantity)) {
    channel.index = ReadComponent(t, "sensor", params.sensors, "sensors");
  }
  if (TakesAmb(channel.quantity)) channel.index = ReadComponent(t, "amb", params.ambs, "AMBs");
  if (TakesTdb(channel.quantity)) channel.index = ReadComponent(t, "tdb", params.tdbs, "TDBs");
  if (TakesAxis(channel.quantity)) channel.axis = t.Choice("axis", {"x", "y"}) == "x" ? 0 : 1;
  ReadUnit(t, &channel);
  ReadWindow(t, &channel);
  return channel;
}

}  // namespace

std::string MeasurementChannel::Describe(const ModelParams& params) const {
  std::string out(MeasuredQuantityName(quantity));
  // A channel checked against other params than its own must not read past their lists.
  const auto append_name = [this, &out](const auto& list) {
    out += ' ';
    if (index >= 0 && static_cast<std::size_t>(index) < list.size()) {
      out += list[static_cast<std::size_t>(index)].name;
    } else {
      out += fmt::format("#{}", index);
    }
  };
  if (TakesSensor(quantity)) append_name(params.sensors);
  if (TakesAmb(quantity)) append_name(params.ambs);
  if (TakesTdb(quantity)) append_name(params.tdbs);
  if (TakesAxis(quantity)) out += axis == 0 ? " x" : axis == 1 ? " y" : " ?";
  return out;
}

bool MeasurementChannel::InWindow(double t_s, double trigger_s) const {
  if (window == ChannelWindow::kBeforeTrigger && !(t_s < trigger_s)) return false;
  if (window == ChannelWindow::kAfterTrigger && !(t_s >= trigger_s)) return false;
  if (from_s && t_s < trigger_s + *from_s) return false;
  if (to_s && !(t_s < trigger_s + *to_s)) return false;
  return true;
}

std::string MeasurementChannel::DescribeWindow() const {
  std::string out = window == ChannelWindow::kBeforeTrigger  ? "before the trigger"
                    : window == ChannelWindow::kAfterTrigger ? "after the trigger"
                                                             : "the whole record";
  if (from_s) out += fmt::format(", from {} s", *from_s);
  if (to_s) out += fmt::format(", to {} s", *to_s);
  if (from_s || to_s) out += " relative to the trigger";
  return out;
}

std::string_view MeasuredQuantitySiUnit(MeasuredQuantity quantity) {
  switch (DimensionOf(quantity)) {
    case Dimension::kLength:
      return "m";
    case Dimension::kCurrent:
      return "A";
    case Dimension::kForce:
      return "N";
    case Dimension::kSpeed:
      break;
  }
  return "rad/s";
}

std::optional<double> MeasurementUnitScale(MeasuredQuantity quantity, std::string_view unit) {
  for (const UnitSpelling& u : kUnits) {
    if (u.name == unit && u.dimension == DimensionOf(quantity)) return u.si_per_unit;
  }
  return std::nullopt;
}

std::optional<double> TimeUnitScale(std::string_view unit) {
  for (const auto& [name, scale] : kTimeUnits) {
    if (name == unit) return scale;
  }
  return std::nullopt;
}

namespace config_detail {
namespace {

// from_record needs coil currents to drive with, and AMBs whose force a coil current sets.
void CheckFromRecord(const TableReader& table, const ModelParams& params,
                     const MeasurementParams& m) {
  bool any = false;
  for (const MeasurementChannel& ch : m.channels) {
    if (!m.Drives(ch)) continue;
    any = true;
    const AmbParams& a = params.ambs[static_cast<std::size_t>(ch.index)];
    if (a.law == AmbForceLaw::kEquivalent) {
      table.Fail("power_loss",
                 fmt::format("\"declared\" for AMB {}: its law \"equivalent\" takes no coil "
                             "current (column '{}')",
                             a.name, ch.column));
    }
    if (a.bias_source == AmbBiasSource::kElectromagnet && !a.flux_decay.enabled) {
      table.Fail("power_loss",
                 fmt::format("\"declared\", or amb.{0}.flux_decay enabled: with an electromagnet "
                             "bias the record's control current ('{1}') rides on a bias current "
                             "that the record does not carry, and without a declared decay that "
                             "bias (and every force of AMB {0}) is gone at the trigger",
                             a.name, ch.column));
    }
  }
  if (!any) {
    table.Fail("power_loss",
               "\"declared\", or at least one channel with quantity = \"current\" (the coil "
               "currents that drive the AMBs)");
  }
}

}  // namespace

MeasurementParams ReadMeasurement(const TableReader& table, const ModelParams& params) {
  table.AllowOnly({"sample_rate_Hz", "trigger_time_s", "trigger", "time_column", "time_unit",
                   "power_loss", "trigger_state", "channel"});
  MeasurementParams m;
  // The unit goes in the message unless the shared reader already derives it from the key.
  const bool unit_known = !UnitOfKey("sample_rate_Hz").empty();
  m.sample_rate_Hz =
      table.Number("sample_rate_Hz",
                   NumberRule{.lower = 0.0,
                              .lower_inclusive = false,
                              .what = unit_known ? "a positive number" : "a positive number (Hz)"});
  if (table.Has("trigger") && table.Has("trigger_time_s")) {
    table.Fail("trigger", "no trigger with trigger_time_s (give one or the other)");
  }
  if (table.Has("trigger")) {
    m.detect_trigger = table.Choice("trigger", {"detect"}) == "detect";
  } else if (table.Has("trigger_time_s")) {
    m.trigger_time_s = table.Number("trigger_time_s", NonNegative());
  } else {
    table.FailMissing("trigger_time_s", "a non-negative number (s), or trigger = \"detect\"");
  }
  m.time_column = table.String("time_column", "t");
  if (m.time_column.empty()) table.Fail("time_column", "a non-empty CSV column name");
  std::vector<std::string_view> time_units;
  for (const auto& [name, scale] : kTimeUnits) time_units.push_back(name);
  m.time_unit = table.Choice("time_unit", time_units, "s");
  m.time_scale_s = *TimeUnitScale(m.time_unit);
  const std::string at_least_one = fmt::format("at least one [[{}]]", table.KeyPath("channel"));
  if (!table.Has("channel")) table.FailMissing("channel", at_least_one);
  const std::vector<TableReader> channels = table.TableArray("channel");
  if (channels.empty()) table.Fail("channel", at_least_one);
  for (const TableReader& t : channels) {
    MeasurementChannel channel = ReadChannel(t, params, m.time_column);
    for (std::size_t i = 0; i < m.channels.size(); ++i) {
      if (m.channels[i].column != channel.column) continue;
      t.Fail("column", fmt::format("a column no other channel reads ({}[{}] reads it)",
                                   table.KeyPath("channel"), i));
    }
    m.channels.push_back(std::move(channel));
  }
  if (table.Choice("power_loss", {"declared", "from_record"}, "declared") == "from_record") {
    m.power_loss = PowerLossSource::kFromRecord;
    CheckFromRecord(table, params, m);
  }
  const std::string trigger_state =
      table.Choice("trigger_state", {"model", "record", "record_start"}, "model");
  if (trigger_state != "model") {
    m.trigger_state_from_record = trigger_state == "record";
    m.trigger_state_for_start = trigger_state == "record_start";
    if (std::none_of(m.channels.begin(), m.channels.end(), [](const MeasurementChannel& ch) {
          return ch.quantity == MeasuredQuantity::kDisplacement;
        })) {
      table.Fail("trigger_state",
                 "\"model\", or a channel with quantity = \"displacement\" (the state at the "
                 "trigger is read from them)");
    }
  }
  return m;
}

}  // namespace config_detail
std::string_view MeasuredQuantityName(MeasuredQuantity quantity) {
  for (const auto& [name, q] : kQuantities) {
    if (q == quantity) return name;
  }
  return "unknown";
}

}  // namespace ambdrop
