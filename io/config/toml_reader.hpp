#pragma once
// Strict reading of a parsed TOML table: every accessor either returns a valid value or throws
// ConfigError naming the source location, the dotted key, what was expected and what was found.
#include <toml++/toml.h>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "io/config/config_keys.hpp"

namespace ambdrop::config_detail {

/// Overridden nodes carry "--set path=value" as their source path, so that errors about them
/// point at the command line instead of the file.
inline constexpr std::string_view kOverrideOriginPrefix = "--set ";

/// Accepted range of a number; non-finite numbers are always rejected.
struct NumberRule {
  double lower = -std::numeric_limits<double>::infinity();
  bool lower_inclusive = true;
  double upper = std::numeric_limits<double>::infinity();
  bool upper_inclusive = true;
  std::string what;  ///< "a positive number"; the unit is added from the key name

  bool Accepts(double value) const;
};

NumberRule AnyNumber();
NumberRule Positive();
NumberRule NonNegative();
NumberRule InRange(double lower, double upper);               ///< [lower, upper]
NumberRule InHalfOpenRange(double lower, double upper);       ///< [lower, upper)
NumberRule AtLeast(double lower, std::string what);           ///< [lower, inf)
NumberRule NonNegativeBelow(double upper, std::string what);  ///< [0, upper)

/// "m" for "clearance_m", "N s/m" for "damping_N_s_per_m", "" when the key carries no unit.
std::string UnitOfKey(std::string_view key);

/// `what` followed by the unit of `key` in brackets, if it has one.
std::string ExpectedWithUnit(std::string_view what, std::string_view key);

/// "FILE:LINE", or "--set path=value" for a node that came from an override.
std::string NodeLocation(const toml::node& node, std::string_view fallback_source);

/// The value as it would read in TOML (strings quoted, arrays bracketed), shortened.
std::string DescribeValue(const toml::node& node);

[[noreturn]] void ThrowBadValue(const toml::node& node, std::string_view fallback_source,
                                std::string_view dotted_key, std::string_view expected,
                                std::string_view found);
[[noreturn]] void ThrowBadValue(const toml::node& node, std::string_view fallback_source,
                                std::string_view dotted_key, std::string_view expected);

/// A finite number (integers accepted) satisfying `rule`, else ThrowBadValue with `expected`.
double ReadNumber(const toml::node& node, std::string_view fallback_source,
                  std::string_view dotted_key, const NumberRule& rule, std::string_view expected);

/// View of one table at a dotted path; cheap to copy, refers to the parsed document.
class TableReader {
 public:
  /// `log` (optional) records every number read through this reader and the readers of its
  /// sub-tables: the config's key registry (io/config/config_keys.hpp).
  TableReader(const toml::table& table, std::string path, std::string source_name,
              KeyLog* log = nullptr);

  const std::string& path() const { return path_; }
  const std::string& source_name() const { return source_name_; }
  const toml::table& table() const { return *table_; }
  std::string KeyPath(std::string_view key) const;

  /// Throws on the first key (in sorted order) not in `allowed`.
  void AllowOnly(const std::vector<std::string_view>& allowed) const;

  const toml::node* Find(std::string_view key) const;
  bool Has(std::string_view key) const { return Find(key) != nullptr; }

  /// Throws "key: expected `expected`, found ..." if `key` is present.
  void Reject(std::string_view key, std::string_view expected) const;
  /// Whether `key` is present and was given by a --set override (not by the file or its base).
  bool FromOverride(std::string_view key) const;

  double Number(std::string_view key, const NumberRule& rule) const;
  double Number(std::string_view key, const NumberRule& rule, double fallback) const;
  std::optional<double> OptionalNumber(std::string_view key, const NumberRule& rule) const;
  int Integer(std::string_view key, int lower, int upper, int fallback) const;
  std::int64_t Integer64(std::string_view key, std::int64_t lower, std::int64_t upper,
                         std::int64_t fallback) const;
  bool Bool(std::string_view key, bool fallback) const;
  std::string String(std::string_view key) const;
  std::string String(std::string_view key, std::string_view fallback) const;
  /// One of `choices`; required when `fallback` is empty.
  std::string Choice(std::string_view key, const std::vector<std::string_view>& choices,
                     std::optional<std::string_view> fallback = std::nullopt) const;

  TableReader Table(std::string_view key) const;
  std::optional<TableReader> OptionalTable(std::string_view key) const;
  /// Sub-tables keyed by a user-chosen name ([tdb.NAME]); empty when `key` is absent.
  std::vector<std::pair<std::string, TableReader>> NamedTables(std::string_view key) const;
  /// An array of tables ([[key]]); empty when `key` is absent.
  std::vector<TableReader> TableArray(std::string_view key) const;
  /// nullptr when absent.
  const toml::array* OptionalArray(std::string_view key, std::string_view expected) const;

  /// Number of entries of a present `key` must not exceed `max`.
  void CheckCount(std::string_view key, std::size_t count, int max, std::string_view noun) const;

  [[noreturn]] void Fail(std::string_view key, std::string_view expected) const;
  [[noreturn]] void Fail(std::string_view key, std::string_view expected,
                         std::string_view found) const;
  [[noreturn]] void FailMissing(std::string_view key, std::string_view expected) const;

 private:
  const toml::node& Require(std::string_view key, std::string_view expected) const;
  void Log(std::string_view key, double value, const NumberRule& rule, const toml::node* node,
           bool integer = false) const;

  const toml::table* table_;
  std::string path_;
  std::string source_name_;
  KeyLog* log_ = nullptr;
};

}  // namespace ambdrop::config_detail
