#include "io/config_measurement.hpp"

#include <fmt/format.h>

#include <array>
#include <string_view>
#include <utility>

#include "io/toml_reader.hpp"

namespace ambdrop {
namespace {

using config_detail::NonNegative;
using config_detail::NumberRule;
using config_detail::TableReader;

constexpr std::array<std::pair<std::string_view, MeasuredQuantity>, 5> kQuantities = {{
    {"displacement", MeasuredQuantity::kDisplacement},
    {"current", MeasuredQuantity::kCurrent},
    {"tdb_normal_force", MeasuredQuantity::kTdbNormalForce},
    {"tdb_speed", MeasuredQuantity::kTdbSpeed},
    {"rotor_speed", MeasuredQuantity::kRotorSpeed},
}};

bool TakesSensor(MeasuredQuantity q) {
  return q == MeasuredQuantity::kDisplacement;
}
bool TakesAmb(MeasuredQuantity q) {
  return q == MeasuredQuantity::kCurrent;
}
bool TakesTdb(MeasuredQuantity q) {
  return q == MeasuredQuantity::kTdbNormalForce || q == MeasuredQuantity::kTdbSpeed;
}
bool TakesAxis(MeasuredQuantity q) {
  return q == MeasuredQuantity::kDisplacement || q == MeasuredQuantity::kCurrent;
}

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
void RejectForeignKeys(const TableReader& t, MeasuredQuantity q) {
  const std::string_view name = MeasuredQuantityName(q);
  if (!TakesSensor(q)) {
    t.Reject("sensor", fmt::format("no sensor for {} (only displacement takes sensor)", name));
  }
  if (!TakesAmb(q)) t.Reject("amb", fmt::format("no amb for {} (only current takes amb)", name));
  if (!TakesTdb(q)) {
    t.Reject("tdb",
             fmt::format("no tdb for {} (only tdb_normal_force and tdb_speed take tdb)", name));
  }
  if (!TakesAxis(q)) {
    t.Reject("axis", fmt::format("no axis for {} (only displacement and current take axis)", name));
  }
}

MeasurementChannel ReadChannel(const TableReader& t, const ModelParams& params) {
  t.AllowOnly({"column", "quantity", "sensor", "amb", "tdb", "axis"});
  MeasurementChannel channel;
  channel.column = t.String("column");
  if (channel.column.empty()) t.Fail("column", "a non-empty CSV column name");
  // t is the record's time column (io/measured_csv.hpp), never a channel.
  if (channel.column == "t") t.Fail("column", "a column other than \"t\" (the record's time)");
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

namespace config_detail {

MeasurementParams ReadMeasurement(const TableReader& table, const ModelParams& params) {
  table.AllowOnly({"sample_rate_Hz", "trigger_time_s", "trigger", "channel"});
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
  const std::string at_least_one = fmt::format("at least one [[{}]]", table.KeyPath("channel"));
  if (!table.Has("channel")) table.FailMissing("channel", at_least_one);
  const std::vector<TableReader> channels = table.TableArray("channel");
  if (channels.empty()) table.Fail("channel", at_least_one);
  for (const TableReader& t : channels) {
    MeasurementChannel channel = ReadChannel(t, params);
    for (std::size_t i = 0; i < m.channels.size(); ++i) {
      if (m.channels[i].column != channel.column) continue;
      t.Fail("column", fmt::format("a column no other channel reads ({}[{}] reads it)",
                                   table.KeyPath("channel"), i));
    }
    m.channels.push_back(std::move(channel));
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
