#include "io/config/config_can.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <optional>
#include <sstream>
#include <string_view>

#include "io/config/config_loader.hpp"
#include "io/config/toml_reader.hpp"

namespace ambdrop {
namespace {

using config_detail::NodeLocation;
using config_detail::NumberRule;
using config_detail::TableReader;

constexpr std::string_view kLittle = "little";
constexpr std::string_view kBig = "big";

const std::vector<std::string_view> kLayoutKeys = {"id",          "extended", "byte_offset",
                                                   "width_bytes", "signed",   "byte_order"};

/// What every signal of one [can] table shares.
struct Defaults {
  bool fd = false;
  std::string byte_order;
  std::string source_name;
};

std::vector<std::string_view> With(std::vector<std::string_view> keys,
                                   std::initializer_list<std::string_view> more) {
  keys.insert(keys.end(), more);
  return keys;
}

int RequiredInteger(const TableReader& table, std::string_view key, int lower, int upper) {
  if (!table.Has(key)) {
    table.FailMissing(key, fmt::format("an integer in [{}, {}]", lower, upper));
  }
  return table.Integer(key, lower, upper, lower);
}

/// An integer in [lower, upper] that may exceed int (ids, masks); hex in the message.
std::uint32_t ReadUnsigned(const TableReader& table, std::string_view key, std::uint32_t lower,
                           std::uint32_t upper, std::string_view what,
                           std::optional<std::uint32_t> fallback) {
  const std::string expected = fmt::format("{} in [{:#x}, {:#x}]", what, lower, upper);
  const toml::node* node = table.Find(key);
  if (node == nullptr) {
    if (fallback) return *fallback;
    table.FailMissing(key, expected);
  }
  const auto* integer = node->as_integer();
  if (integer == nullptr || integer->get() < static_cast<std::int64_t>(lower) ||
      integer->get() > static_cast<std::int64_t>(upper)) {
    table.Fail(key, expected);
  }
  return static_cast<std::uint32_t>(integer->get());
}

CanSignalLayout ReadLayout(const TableReader& table, const Defaults& defaults, bool bytes_used) {
  CanSignalLayout layout;
  layout.extended = table.Bool("extended", false);
  layout.id = ReadUnsigned(table, "id", 0, layout.extended ? kCanEffMaxId : kCanSffMaxId,
                           layout.extended ? "a 29-bit identifier (extended = true)"
                                           : "an 11-bit identifier (extended = false)",
                           std::nullopt);
  if (!bytes_used) return layout;
  const int max_len = defaults.fd ? kCanFdMaxLen : kCanMaxLen;
  layout.width_bytes = RequiredInteger(table, "width_bytes", 1, 4);
  if (layout.width_bytes == 3) table.Fail("width_bytes", "1, 2 or 4");
  layout.byte_offset = RequiredInteger(table, "byte_offset", 0, max_len - 1);
  if (layout.end() > max_len) {
    table.Fail("byte_offset",
               fmt::format("an offset at most {} (width_bytes = {}, {} bytes of {} payload)",
                           max_len - layout.width_bytes, layout.width_bytes, max_len,
                           defaults.fd ? "a CAN FD" : "a classic CAN"));
  }
  layout.is_signed = table.Bool("signed", false);
  layout.byte_order = table.Choice("byte_order", {kLittle, kBig}, defaults.byte_order) == kLittle
                          ? CanByteOrder::kLittle
                          : CanByteOrder::kBig;
  return layout;
}

// The scale's unit ("A/count") comes from its key's name, as every number's does.
CanScaling ReadScaling(const TableReader& table, std::string_view scale_key,
                       std::string_view offset_key) {
  const std::string what = "a non-zero finite number";
  CanScaling scaling;
  scaling.scale = table.Number(scale_key, NumberRule{.what = what});
  if (scaling.scale == 0.0) table.Fail(scale_key, config_detail::ExpectedWithUnit(what, scale_key));
  scaling.offset = table.Number(offset_key, config_detail::AnyNumber(), 0.0);
  return scaling;
}

CanSignalSpec StartSignal(const TableReader& table, const Defaults& defaults, CanSignalRole role) {
  CanSignalSpec signal;
  signal.role = role;
  signal.name = table.path();
  signal.location = NodeLocation(table.table(), defaults.source_name);
  return signal;
}

/// The index of `name` among `known` (the model's names), or, without them, among the names
/// found so far (appended).
int ResolveName(const TableReader& table, const std::string& name,
                const std::vector<std::string>* known, std::vector<std::string>* found,
                std::string_view noun) {
  if (known != nullptr) {
    const auto it = std::find(known->begin(), known->end(), name);
    if (it == known->end()) {
      std::string list;
      for (const std::string& each : *known) list += (list.empty() ? "" : ", ") + each;
      config_detail::ThrowBadValue(
          table.table(), table.source_name(), table.path(),
          fmt::format("the name of a{} {} of the model ({})", noun == "AMB" ? "n" : "", noun,
                      list.empty() ? "there are none" : list),
          fmt::format("{:?}", name));
    }
    return static_cast<int>(it - known->begin());
  }
  const auto it = std::find(found->begin(), found->end(), name);
  if (it != found->end()) return static_cast<int>(it - found->begin());
  found->push_back(name);
  return static_cast<int>(found->size()) - 1;
}

/// [can.GROUP.NAME.x] / [.y] tables: currents_in (AMBs) or sensors_out (sensors).
void ReadAxisGroup(const TableReader& can, std::string_view group, CanSignalRole role,
                   std::string_view scale_key, std::string_view offset_key,
                   const std::vector<std::string>* known, std::vector<std::string>* found,
                   const Defaults& defaults, std::vector<CanSignalSpec>* signals) {
  const std::string_view noun = role == CanSignalRole::kCurrent ? "AMB" : "sensor";
  for (const auto& [name, named] : can.NamedTables(group)) {
    named.AllowOnly({"x", "y"});
    if (!named.Has("x") && !named.Has("y")) {
      throw ConfigError(fmt::format("{}: key '{}': expected [{}.x] and/or [{}.y]",
                                    NodeLocation(named.table(), defaults.source_name), named.path(),
                                    named.path(), named.path()));
    }
    const int index = ResolveName(named, name, known, found, noun);
    for (const int axis : {0, 1}) {
      const std::optional<TableReader> table = named.OptionalTable(axis == 0 ? "x" : "y");
      if (!table) continue;
      table->AllowOnly(With(kLayoutKeys, {scale_key, offset_key}));
      CanSignalSpec signal = StartSignal(*table, defaults, role);
      signal.layout = ReadLayout(*table, defaults, true);
      signal.scaling = ReadScaling(*table, scale_key, offset_key);
      signal.index = index;
      signal.axis = axis;
      signals->push_back(std::move(signal));
    }
  }
}

void ReadTriggers(const TableReader& can, const Defaults& defaults,
                  std::vector<CanSignalSpec>* signals) {
  const std::optional<TableReader> triggers = can.OptionalTable("trigger_in");
  if (!triggers) return;
  triggers->AllowOnly({"power_fail", "power_restore"});
  for (const auto& [key, role] : {std::pair{"power_fail", CanSignalRole::kPowerFail},
                                  std::pair{"power_restore", CanSignalRole::kPowerRestore}}) {
    const std::optional<TableReader> table = triggers->OptionalTable(key);
    if (!table) continue;
    CanSignalSpec signal = StartSignal(*table, defaults, role);
    signal.any_frame = table->Bool("any_frame", false);
    if (signal.any_frame) {
      table->AllowOnly({"id", "extended", "any_frame"});
      signal.layout = ReadLayout(*table, defaults, false);
    } else {
      // Unsigned bits only: "signed" is not a key here.
      table->AllowOnly({"id", "extended", "byte_offset", "width_bytes", "byte_order", "mask",
                        "value", "any_frame"});
      signal.layout = ReadLayout(*table, defaults, true);
      const auto width_max = static_cast<std::uint32_t>(RawMax(signal.layout));
      signal.mask = ReadUnsigned(*table, "mask", 1, width_max, "a non-zero bit mask", width_max);
      signal.value =
          ReadUnsigned(*table, "value", 0, width_max, "an unsigned raw value", std::nullopt);
      if ((signal.value & ~signal.mask) != 0) {
        table->Fail("value", fmt::format("a value within mask = {:#x} (else it never matches)",
                                         signal.mask));
      }
    }
    signals->push_back(std::move(signal));
  }
}

void ReadStatus(const TableReader& can, const Defaults& defaults,
                std::vector<CanSignalSpec>* signals) {
  const std::optional<TableReader> status = can.OptionalTable("status_out");
  if (!status) return;
  static const std::vector<std::pair<std::string_view, CanSignalRole>> kRoles = {
      {"in_contact", CanSignalRole::kStatusInContact},
      {"overrun_counter", CanSignalRole::kStatusOverruns},
      {"power_on", CanSignalRole::kStatusPowerOn},
      {"spin_speed", CanSignalRole::kStatusSpinSpeed},
      {"step_counter", CanSignalRole::kStatusStep},
  };
  std::vector<std::string_view> names;
  for (const auto& [name, role] : kRoles) names.push_back(name);
  status->AllowOnly(names);
  for (const auto& [name, role] : kRoles) {
    const std::optional<TableReader> table = status->OptionalTable(name);
    if (!table) continue;
    CanSignalSpec signal = StartSignal(*table, defaults, role);
    if (role == CanSignalRole::kStatusSpinSpeed) {
      table->AllowOnly(With(kLayoutKeys, {"scale_rad_s_per_count", "offset_rad_s"}));
      signal.scaling = ReadScaling(*table, "scale_rad_s_per_count", "offset_rad_s");
    } else {
      table->AllowOnly(kLayoutKeys);
    }
    signal.layout = ReadLayout(*table, defaults, true);
    signals->push_back(std::move(signal));
  }
}

toml::table Parse(const std::string& text, const std::string& source_name) {
  try {
    return toml::parse(text, std::string_view(source_name));
  } catch (const toml::parse_error& error) {
    throw ConfigError(fmt::format("{}:{}: {} (column {})", source_name, error.source().begin.line,
                                  error.description(), error.source().begin.column));
  }
}

}  // namespace

CanNames CanNamesOf(const ModelParams& params) {
  CanNames names;
  for (const auto& amb : params.ambs) names.ambs.push_back(amb.name);
  for (const auto& sensor : params.sensors) names.sensors.push_back(sensor.name);
  return names;
}

CanConfig ReadCanConfig(const TableReader& can, const CanNames* names) {
  can.AllowOnly({"interface", "exchange_rate_Hz", "fd", "bit_rate_switch", "bitrate_bps",
                 "data_bitrate_bps", "byte_order", "tx_len_bytes", "filter_input_ids",
                 "currents_in", "sensors_out", "trigger_in", "status_out"});
  CanConfig config;
  config.interface = can.String("interface");
  if (config.interface.empty() || config.interface.size() > 15) {
    can.Fail("interface", "an interface name of 1 to 15 characters");
  }
  // The unit goes in the message unless the shared reader already derives it from the key.
  const bool unit_known = !config_detail::UnitOfKey("exchange_rate_Hz").empty();
  config.exchange_rate_Hz =
      can.Number("exchange_rate_Hz",
                 NumberRule{.lower = 0.0,
                            .lower_inclusive = false,
                            .what = unit_known ? "a positive number" : "a positive number (Hz)"});
  config.fd = can.Bool("fd", false);
  if (!config.fd) {
    can.Reject("bit_rate_switch", "no bit_rate_switch with fd = false (classic CAN has none)");
    can.Reject("data_bitrate_bps", "no data_bitrate_bps with fd = false (classic CAN has none)");
  }
  config.bit_rate_switch = can.Bool("bit_rate_switch", config.fd);
  // ISO 11898-1 caps the nominal rate at 1 Mbit/s; FD data phases run up to ~8-12 Mbit/s.
  config.bitrate_bps = can.Number(
      "bitrate_bps",
      NumberRule{
          .lower = 0.0, .lower_inclusive = false, .upper = 1e6, .what = "a number in (0, 1e6]"},
      1e6);
  config.data_bitrate_bps = can.Number(
      "data_bitrate_bps",
      NumberRule{
          .lower = 0.0, .lower_inclusive = false, .upper = 20e6, .what = "a number in (0, 20e6]"},
      config.bitrate_bps);
  config.filter_input_ids = can.Bool("filter_input_ids", true);

  Defaults defaults{.fd = config.fd,
                    .byte_order = can.Choice("byte_order", {kLittle, kBig}, kLittle),
                    .source_name = can.source_name()};

  FrameMapSpec spec;
  spec.fd = config.fd;
  spec.bit_rate_switch = config.bit_rate_switch;
  spec.tx_len_bytes = can.Integer("tx_len_bytes", 0, config.fd ? kCanFdMaxLen : kCanMaxLen, 0);
  if (config.fd && !IsCanFdLength(spec.tx_len_bytes)) {
    can.Fail("tx_len_bytes", "a CAN FD length: 0..8, 12, 16, 20, 24, 32, 48 or 64");
  }
  ReadAxisGroup(can, "currents_in", CanSignalRole::kCurrent, "scale_A_per_count", "offset_A",
                names != nullptr ? &names->ambs : nullptr, &spec.amb_names, defaults,
                &spec.signals);
  ReadAxisGroup(can, "sensors_out", CanSignalRole::kSensor, "scale_m_per_count", "offset_m",
                names != nullptr ? &names->sensors : nullptr, &spec.sensor_names, defaults,
                &spec.signals);
  if (names != nullptr) {
    spec.amb_names = names->ambs;
    spec.sensor_names = names->sensors;
  }
  ReadTriggers(can, defaults, &spec.signals);
  ReadStatus(can, defaults, &spec.signals);
  config.frame_map = FrameMap(std::move(spec));

  // The bus must carry one frame of every id per exchange, both directions.
  double exchange_time_s = 0.0;
  int frames = 0;
  for (const auto& shapes : {config.frame_map.InputFrames(), config.frame_map.OutputFrames()}) {
    for (const CanFrameShape& shape : shapes) {
      exchange_time_s +=
          CanFrameWorstCaseTime_s(shape.extended, config.fd, config.bit_rate_switch, shape.len,
                                  config.bitrate_bps, config.data_bitrate_bps);
      ++frames;
    }
  }
  config.bus_load = exchange_time_s * config.exchange_rate_Hz;
  if (config.bus_load > 1.0) {
    can.Fail("exchange_rate_Hz",
             fmt::format("a rate the bus can carry: {} frames per exchange take up to {:.1f} us "
                         "at {} bit/s, so at most {:.0f} Hz",
                         frames, exchange_time_s * 1e6, config.bitrate_bps, 1.0 / exchange_time_s));
  }
  return config;
}

SocketCanOptions CanConfig::SocketOptions() const {
  SocketCanOptions options;
  options.interface = interface;
  options.socket.fd_frames = fd;
  if (filter_input_ids) options.socket.filters = frame_map.InputFilters();
  return options;
}

CanConfig LoadCanConfigFromString(const std::string& text, const std::string& source_name,
                                  const CanNames* names) {
  const toml::table root = Parse(text, source_name);
  const TableReader root_reader(root, "", source_name);
  return ReadCanConfig(root_reader.Table("can"), names);
}

CanConfig LoadCanConfig(const std::filesystem::path& path, const CanNames* names) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw ConfigError(fmt::format("{}: cannot open the config file", path.string()));
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad()) throw ConfigError(fmt::format("{}: cannot read the config file", path.string()));
  return LoadCanConfigFromString(text.str(), path.string(), names);
}

}  // namespace ambdrop
