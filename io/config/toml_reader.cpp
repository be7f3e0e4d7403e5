#include "io/config/toml_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <sstream>

#include "io/config/config_loader.hpp"

namespace ambdrop::config_detail {
namespace {

// Long enough for a short array, short enough to keep a message on one line.
constexpr std::size_t kMaxDescriptionLength = 80;

std::string DescribeNested(const toml::node& node, bool nested) {
  switch (node.type()) {
    case toml::node_type::string:
      return fmt::format("{:?}", node.as_string()->get());
    case toml::node_type::integer:
      return fmt::format("{}", node.as_integer()->get());
    case toml::node_type::floating_point:
      return fmt::format("{}", node.as_floating_point()->get());
    case toml::node_type::boolean:
      return node.as_boolean()->get() ? "true" : "false";
    case toml::node_type::table:
      return nested ? "{...}" : "a table";
    case toml::node_type::array: {
      std::string out = "[";
      const toml::array& array = *node.as_array();
      for (std::size_t i = 0; i < array.size(); ++i) {
        if (i > 0) out += ", ";
        out += DescribeNested(array[i], true);
        if (out.size() > kMaxDescriptionLength) break;
      }
      return out + "]";
    }
    default: {
      std::ostringstream stream;
      node.visit([&stream](const auto& value) { stream << value; });
      return stream.str();
    }
  }
}

std::string FormatRange(double lower, bool lower_inclusive, double upper, bool upper_inclusive) {
  return fmt::format("{}{}, {}{}", lower_inclusive ? '[' : '(', lower, upper,
                     upper_inclusive ? ']' : ')');
}

std::string Join(const std::vector<std::string_view>& words, std::string_view separator,
                 bool quoted) {
  std::string out;
  for (std::size_t i = 0; i < words.size(); ++i) {
    if (i > 0) out += separator;
    out += quoted ? fmt::format("{:?}", words[i]) : std::string(words[i]);
  }
  return out;
}

}  // namespace

bool NumberRule::Accepts(double value) const {
  if (!std::isfinite(value)) return false;
  if (lower_inclusive ? value < lower : value <= lower) return false;
  if (upper_inclusive ? value > upper : value >= upper) return false;
  return true;
}

NumberRule AnyNumber() {
  return NumberRule{.what = "a finite number"};
}

NumberRule Positive() {
  return NumberRule{.lower = 0.0, .lower_inclusive = false, .what = "a positive number"};
}

NumberRule NonNegative() {
  return NumberRule{.lower = 0.0, .what = "a non-negative number"};
}

NumberRule InRange(double lower, double upper) {
  return NumberRule{.lower = lower,
                    .upper = upper,
                    .what = "a number in " + FormatRange(lower, true, upper, true)};
}

NumberRule InHalfOpenRange(double lower, double upper) {
  return NumberRule{.lower = lower,
                    .upper = upper,
                    .upper_inclusive = false,
                    .what = "a number in " + FormatRange(lower, true, upper, false)};
}

NumberRule AtLeast(double lower, std::string what) {
  return NumberRule{.lower = lower, .what = std::move(what)};
}

NumberRule NonNegativeBelow(double upper, std::string what) {
  return NumberRule{
      .lower = 0.0, .upper = upper, .upper_inclusive = false, .what = std::move(what)};
}

namespace {

// The unit at the end of a name, longest suffix first, so that "_N_m_s" wins over "_m_s" and
// "_s". The house's compounds without "per" keep their spelling: "_rad_s" is rad/s, "_m_s" m/s,
// "_m_s2" m/s^2, "_kg_m3" kg/m^3, while "_kg_m2", "_N_m_s" and "_N_m_s2" are products.
std::string_view SuffixUnit(std::string_view name) {
  static constexpr std::array<std::pair<std::string_view, std::string_view>, 23> kUnits = {{
      {"_N_m_s2", "N m s^2"},
      {"_N_m_s", "N m s"},
      {"_kg_m3", "kg/m^3"},
      {"_kg_m2", "kg m^2"},
      {"_rad_s", "rad/s"},
      {"_N_m2", "N m^2"},
      {"_m_s2", "m/s^2"},
      {"_kg_m", "kg m"},
      {"_N_m", "N m"},
      {"_N_s", "N s"},
      {"_m_s", "m/s"},
      {"_bps", "bit/s"},
      {"_rad", "rad"},
      {"_kg", "kg"},
      {"_Pa", "Pa"},
      {"_Hz", "Hz"},
      {"_m2", "m^2"},
      {"_A", "A"},
      {"_N", "N"},
      {"_T", "T"},
      {"_V", "V"},
      {"_m", "m"},
      {"_s", "s"},
  }};
  for (const auto& [suffix, unit] : kUnits) {
    if (name.ends_with(suffix)) return unit;
  }
  // Sensor and CAN counts: "counts_per_m", "scale_A_per_count".
  if (name == "count" || name == "counts" || name.ends_with("_count") ||
      name.ends_with("_counts")) {
    return "count";
  }
  return {};
}

// The unit after "_per_": one base unit with an optional power ("m", "m2", "A2"), a contact
// law's exponent ("m1_5", "m_n", "m_e"), or a product of base units. "" when it is none.
std::string DenominatorUnit(std::string_view text) {
  static constexpr std::array<std::pair<std::string_view, std::string_view>, 3> kPowers = {{
      {"m1_5", "m^1.5"},
      {"m_n", "m^n"},
      {"m_e", "m^e"},
  }};
  for (const auto& [name, unit] : kPowers) {
    if (text == name) return std::string(unit);
  }
  static constexpr std::array<std::string_view, 11> kBase = {"kg", "rad", "Pa", "Hz", "count", "m",
                                                             "s",  "A",   "V",  "N",  "T"};
  std::string out;
  int factors = 0;
  while (!text.empty()) {
    const std::size_t end = std::min(text.find('_'), text.size());
    std::string_view token = text.substr(0, end);
    text = end < text.size() ? text.substr(end + 1) : std::string_view();
    std::string_view power;
    const std::size_t digits = token.find_first_of("0123456789");
    if (digits != std::string_view::npos && digits > 0) {
      power = token.substr(digits);
      token = token.substr(0, digits);
      if (power.find_first_not_of("0123456789") != std::string_view::npos) return {};
    }
    if (std::find(kBase.begin(), kBase.end(), token) == kBase.end()) return {};
    if (factors++ > 0) out += ' ';
    out += token;
    if (!power.empty()) out += fmt::format("^{}", power);
  }
  if (factors == 0) return {};
  return factors == 1 ? out : fmt::format("({})", out);
}

}  // namespace

std::string UnitOfKey(std::string_view key) {
  // A compound X_per_Y reads X/Y: "sensor_gain_V_per_m" V/m, "ki_per_s" 1/s (the name before
  // "per" carries no unit), "scale_rad_s_per_count" (rad/s)/count.
  const std::size_t per = key.rfind("_per_");
  if (per != std::string_view::npos) {
    const std::string denominator = DenominatorUnit(key.substr(per + 5));
    if (!denominator.empty()) {
      const std::string_view numerator = SuffixUnit(key.substr(0, per));
      if (numerator.empty()) return "1/" + denominator;
      if (numerator.find('/') != std::string_view::npos) {
        return fmt::format("({})/{}", numerator, denominator);
      }
      return fmt::format("{}/{}", numerator, denominator);
    }
  }
  return std::string(SuffixUnit(key));
}

std::string ExpectedWithUnit(std::string_view what, std::string_view key) {
  const std::string unit = UnitOfKey(key);
  return unit.empty() ? std::string(what) : fmt::format("{} ({})", what, unit);
}

std::string NodeLocation(const toml::node& node, std::string_view fallback_source) {
  const toml::source_region& source = node.source();
  if (source.path && source.path->starts_with(kOverrideOriginPrefix)) return *source.path;
  const std::string_view file = source.path ? std::string_view(*source.path) : fallback_source;
  if (source.begin.line == 0) return std::string(file);
  return fmt::format("{}:{}", file, source.begin.line);
}

std::string DescribeValue(const toml::node& node) {
  std::string text = DescribeNested(node, false);
  if (text.size() > kMaxDescriptionLength) {
    text.resize(kMaxDescriptionLength);
    text += "...";
  }
  return text;
}

void ThrowBadValue(const toml::node& node, std::string_view fallback_source,
                   std::string_view dotted_key, std::string_view expected, std::string_view found) {
  throw ConfigError(fmt::format("{}: key '{}': expected {}, found {}",
                                NodeLocation(node, fallback_source), dotted_key, expected, found));
}

void ThrowBadValue(const toml::node& node, std::string_view fallback_source,
                   std::string_view dotted_key, std::string_view expected) {
  ThrowBadValue(node, fallback_source, dotted_key, expected, DescribeValue(node));
}

double ReadNumber(const toml::node& node, std::string_view fallback_source,
                  std::string_view dotted_key, const NumberRule& rule, std::string_view expected) {
  double value = 0.0;
  if (const auto* integer = node.as_integer()) {
    value = static_cast<double>(integer->get());
  } else if (const auto* floating = node.as_floating_point()) {
    value = floating->get();
  } else {
    ThrowBadValue(node, fallback_source, dotted_key, expected);
  }
  if (!rule.Accepts(value)) ThrowBadValue(node, fallback_source, dotted_key, expected);
  return value;
}

TableReader::TableReader(const toml::table& table, std::string path, std::string source_name,
                         KeyLog* log)
    : table_(&table), path_(std::move(path)), source_name_(std::move(source_name)), log_(log) {}

void TableReader::Log(std::string_view key, double value, const NumberRule& rule,
                      const toml::node* node, bool integer) const {
  if (log_ == nullptr) return;
  ConfigKey k;
  k.path = KeyPath(key);
  k.unit = KeyUnit(key);
  k.key_class = ClassOfKey(k.path);
  k.value = value;
  k.declared = node != nullptr;
  k.integer = integer;
  k.lower = rule.lower;
  k.upper = rule.upper;
  k.lower_inclusive = rule.lower_inclusive;
  k.upper_inclusive = rule.upper_inclusive;
  if (node != nullptr) k.location = NodeLocation(*node, source_name_);
  if (const toml::node* enabled = table_->get("enabled")) {
    if (const auto* flag = enabled->as_boolean()) k.in_force = flag->get();
  }
  log_->Record(std::move(k));
}

std::string TableReader::KeyPath(std::string_view key) const {
  return path_.empty() ? std::string(key) : fmt::format("{}.{}", path_, key);
}

void TableReader::AllowOnly(const std::vector<std::string_view>& allowed) const {
  for (const auto& [key, node] : *table_) {
    if (std::find(allowed.begin(), allowed.end(), key.str()) != allowed.end()) continue;
    throw ConfigError(fmt::format("{}: unknown key '{}' (allowed here: {})",
                                  NodeLocation(node, source_name_), KeyPath(key.str()),
                                  Join(allowed, ", ", false)));
  }
}

const toml::node* TableReader::Find(std::string_view key) const {
  return table_->get(key);
}

void TableReader::Reject(std::string_view key, std::string_view expected) const {
  if (Has(key)) Fail(key, expected);
}

bool TableReader::FromOverride(std::string_view key) const {
  const toml::node* node = Find(key);
  if (node == nullptr) return false;
  const toml::source_region& source = node->source();
  return source.path && source.path->starts_with(kOverrideOriginPrefix);
}

const toml::node& TableReader::Require(std::string_view key, std::string_view expected) const {
  const toml::node* node = Find(key);
  if (node == nullptr) FailMissing(key, expected);
  return *node;
}

double TableReader::Number(std::string_view key, const NumberRule& rule) const {
  const std::string expected = ExpectedWithUnit(rule.what, key);
  const toml::node& node = Require(key, expected);
  const double value = ReadNumber(node, source_name_, KeyPath(key), rule, expected);
  Log(key, value, rule, &node);
  return value;
}

double TableReader::Number(std::string_view key, const NumberRule& rule, double fallback) const {
  if (std::optional<double> value = OptionalNumber(key, rule)) return *value;
  // A default the key itself may not take is a sentinel, not a number to fit: infinite for
  // "none" (no current limit), 0 for "derived from other keys" (a 4-DOF bearing's kq).
  if (std::isfinite(fallback) && rule.Accepts(fallback)) Log(key, fallback, rule, nullptr);
  return fallback;
}

std::optional<double> TableReader::OptionalNumber(std::string_view key,
                                                  const NumberRule& rule) const {
  if (!Has(key)) return std::nullopt;
  return Number(key, rule);
}

int TableReader::Integer(std::string_view key, int lower, int upper, int fallback) const {
  return static_cast<int>(Integer64(key, lower, upper, fallback));
}

std::int64_t TableReader::Integer64(std::string_view key, std::int64_t lower, std::int64_t upper,
                                    std::int64_t fallback) const {
  // Logged like a number (the registry's range is the reader's), marked integer so that an
  // override is written without a decimal point. A default outside the range is a sentinel
  // ("none", "derived"), not a value, as in Number.
  const NumberRule range{.lower = static_cast<double>(lower),
                         .upper = static_cast<double>(upper),
                         .what = "an integer"};
  const toml::node* node = Find(key);
  if (node == nullptr) {
    if (fallback >= lower && fallback <= upper) {
      Log(key, static_cast<double>(fallback), range, nullptr, true);
    }
    return fallback;
  }
  const std::string expected = upper == INT_MAX || upper == INT64_MAX
                                   ? fmt::format("an integer >= {}", lower)
                                   : fmt::format("an integer in [{}, {}]", lower, upper);
  const auto* integer = node->as_integer();
  if (integer == nullptr || integer->get() < lower || integer->get() > upper) {
    Fail(key, expected);
  }
  Log(key, static_cast<double>(integer->get()), range, node, true);
  return integer->get();
}

bool TableReader::Bool(std::string_view key, bool fallback) const {
  const toml::node* node = Find(key);
  if (node == nullptr) return fallback;
  if (!node->is_boolean()) Fail(key, "a boolean (true or false)");
  return node->as_boolean()->get();
}

std::string TableReader::String(std::string_view key) const {
  const toml::node& node = Require(key, "a string");
  if (!node.is_string()) Fail(key, "a string");
  return node.as_string()->get();
}

std::string TableReader::String(std::string_view key, std::string_view fallback) const {
  if (!Has(key)) return std::string(fallback);
  return String(key);
}

std::string TableReader::Choice(std::string_view key, const std::vector<std::string_view>& choices,
                                std::optional<std::string_view> fallback) const {
  const std::string expected = "one of " + Join(choices, ", ", true);
  const toml::node* node = Find(key);
  if (node == nullptr) {
    if (fallback) return std::string(*fallback);
    FailMissing(key, expected);
  }
  if (!node->is_string()) Fail(key, expected);
  const std::string& value = node->as_string()->get();
  if (std::find(choices.begin(), choices.end(), value) == choices.end()) Fail(key, expected);
  return value;
}

TableReader TableReader::Table(std::string_view key) const {
  const std::string expected = fmt::format("a table ([{}])", KeyPath(key));
  const toml::node& node = Require(key, expected);
  if (!node.is_table()) Fail(key, expected);
  return TableReader(*node.as_table(), KeyPath(key), source_name_, log_);
}

std::optional<TableReader> TableReader::OptionalTable(std::string_view key) const {
  if (!Has(key)) return std::nullopt;
  return Table(key);
}

std::vector<std::pair<std::string, TableReader>> TableReader::NamedTables(
    std::string_view key) const {
  std::vector<std::pair<std::string, TableReader>> out;
  const toml::node* node = Find(key);
  if (node == nullptr) return out;
  const std::string path = KeyPath(key);
  if (!node->is_table()) Fail(key, fmt::format("a table of named entries ([{}.NAME])", path));
  for (const auto& [name, child] : *node->as_table()) {
    const std::string child_path = fmt::format("{}.{}", path, name.str());
    if (!child.is_table()) {
      ThrowBadValue(child, source_name_, child_path, fmt::format("a table ([{}])", child_path));
    }
    out.emplace_back(std::string(name.str()),
                     TableReader(*child.as_table(), child_path, source_name_, log_));
  }
  return out;
}

std::vector<TableReader> TableReader::TableArray(std::string_view key) const {
  std::vector<TableReader> out;
  const toml::node* node = Find(key);
  if (node == nullptr) return out;
  const std::string path = KeyPath(key);
  if (!node->is_array()) Fail(key, fmt::format("an array of tables ([[{}]])", path));
  const toml::array& array = *node->as_array();
  for (std::size_t i = 0; i < array.size(); ++i) {
    const std::string element_path = fmt::format("{}[{}]", path, i);
    if (!array[i].is_table()) {
      ThrowBadValue(array[i], source_name_, element_path,
                    fmt::format("a table (an element of [[{}]])", path));
    }
    out.emplace_back(*array[i].as_table(), element_path, source_name_, log_);
  }
  return out;
}

const toml::array* TableReader::OptionalArray(std::string_view key,
                                              std::string_view expected) const {
  const toml::node* node = Find(key);
  if (node == nullptr) return nullptr;
  if (!node->is_array()) Fail(key, expected);
  return node->as_array();
}

void TableReader::CheckCount(std::string_view key, std::size_t count, int max,
                             std::string_view noun) const {
  if (count <= static_cast<std::size_t>(max)) return;
  Fail(key, fmt::format("at most {} {}", max, noun), fmt::format("{} {}", count, noun));
}

void TableReader::Fail(std::string_view key, std::string_view expected) const {
  ThrowBadValue(Require(key, expected), source_name_, KeyPath(key), expected);
}

void TableReader::Fail(std::string_view key, std::string_view expected,
                       std::string_view found) const {
  ThrowBadValue(Require(key, expected), source_name_, KeyPath(key), expected, found);
}

void TableReader::FailMissing(std::string_view key, std::string_view expected) const {
  throw ConfigError(fmt::format("{}: missing key '{}': expected {}",
                                NodeLocation(*table_, source_name_), KeyPath(key), expected));
}

}  // namespace ambdrop::config_detail
