#include "io/config/config_overrides.hpp"

#include <fmt/format.h>

#include <cctype>
#include <charconv>
#include <sstream>
#include <string_view>
#include <vector>

#include "io/config/config_loader.hpp"
#include "io/config/toml_reader.hpp"

namespace ambdrop::config_detail {
namespace {

/// "sections[0]" is the key "sections" followed by the index 0.
struct PathSegment {
  std::string key;
  std::vector<std::size_t> indices;
};

[[noreturn]] void Throw(const std::string& origin, std::string_view message) {
  throw ConfigError(fmt::format("{}: {}", origin, message));
}

std::string_view Trim(std::string_view text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(" \t");
  return text.substr(first, last - first + 1);
}

bool IsBareKeyChar(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '-';
}

std::vector<PathSegment> ParsePath(std::string_view path, const std::string& origin) {
  const auto fail = [&]() {
    Throw(origin, fmt::format("expected a dotted key path such as tdb.NAME.clearance_m or "
                              "rotor.sections[0].length_m, found '{}'",
                              path));
  };
  std::vector<PathSegment> segments;
  std::size_t i = 0;
  while (true) {
    PathSegment segment;
    const std::size_t start = i;
    while (i < path.size() && IsBareKeyChar(path[i])) ++i;
    if (i == start) fail();
    segment.key = std::string(path.substr(start, i - start));
    while (i < path.size() && path[i] == '[') {
      const std::size_t close = path.find(']', i);
      if (close == std::string_view::npos || close == i + 1) fail();
      std::size_t index = 0;
      const auto [end, error] = std::from_chars(path.data() + i + 1, path.data() + close, index);
      if (error != std::errc() || end != path.data() + close) fail();
      segment.indices.push_back(index);
      i = close + 1;
    }
    segments.push_back(std::move(segment));
    if (i == path.size()) return segments;
    if (path[i] != '.') fail();
    ++i;
  }
}

toml::table ParseDocument(const std::string& document, const std::string& origin) {
  return toml::parse(document, std::string_view(origin));
}

/// A one-key document {v = value}; parsing it keeps `origin` as the value's source.
toml::table ParseValue(std::string_view value, const std::string& origin) {
  try {
    toml::table document = ParseDocument(fmt::format("v = {}", value), origin);
    if (document.size() == 1 && document.contains("v")) return document;
  } catch (const toml::parse_error&) {
    // Not TOML: a bare word such as `centred`, taken as a string below.
  }
  std::ostringstream quoted;
  quoted << toml::table{{"v", std::string(value)}};
  return ParseDocument(quoted.str(), origin);
}

toml::table NewTable(const std::string& origin) {
  toml::table document = ParseDocument("[v]", origin);
  return std::move(*document.get_as<toml::table>("v"));
}

toml::array NewArray(const std::string& origin) {
  toml::table document = ParseDocument("v = []", origin);
  return std::move(*document.get_as<toml::array>("v"));
}

}  // namespace

void ApplyOverride(toml::table& root, const std::string& override_text) {
  const std::string origin = std::string(kOverrideOriginPrefix) + override_text;
  const std::size_t equals = override_text.find('=');
  if (equals == std::string::npos) {
    Throw(origin, fmt::format("expected dotted.path=value, found '{}'", override_text));
  }
  const std::string_view text = override_text;
  const std::vector<PathSegment> segments = ParsePath(Trim(text.substr(0, equals)), origin);
  toml::table value_document = ParseValue(Trim(text.substr(equals + 1)), origin);
  toml::node& value = *value_document.get("v");

  toml::table* table = &root;
  std::string dotted;
  for (std::size_t s = 0; s < segments.size(); ++s) {
    const PathSegment& segment = segments[s];
    const bool last_segment = s + 1 == segments.size();
    dotted = dotted.empty() ? segment.key : fmt::format("{}.{}", dotted, segment.key);
    if (last_segment && segment.indices.empty()) {
      table->insert_or_assign(segment.key, std::move(value));
      return;
    }
    if (!table->contains(segment.key)) {
      if (segment.indices.empty()) {
        table->insert_or_assign(segment.key, NewTable(origin));
      } else {
        table->insert_or_assign(segment.key, NewArray(origin));
      }
    }
    toml::node* node = table->get(segment.key);
    for (std::size_t k = 0; k < segment.indices.size(); ++k) {
      toml::array* array = node->as_array();
      if (array == nullptr) {
        Throw(origin,
              fmt::format("key '{}': expected an array, found {}", dotted, DescribeValue(*node)));
      }
      const std::size_t index = segment.indices[k];
      if (index > array->size()) {
        Throw(origin, fmt::format("key '{}[{}]': expected an index in [0, {}] ({} appends an "
                                  "element), found {}",
                                  dotted, index, array->size(), array->size(), index));
      }
      const bool last_index = k + 1 == segment.indices.size();
      if (last_segment && last_index) {
        if (index < array->size()) {
          array->replace(array->cbegin() + static_cast<std::ptrdiff_t>(index), std::move(value));
        } else {
          array->push_back(std::move(value));
        }
        return;
      }
      if (index == array->size()) {
        if (last_index) {
          array->push_back(NewTable(origin));
        } else {
          array->push_back(NewArray(origin));
        }
      }
      node = array->get(index);
      dotted += fmt::format("[{}]", index);
    }
    table = node->as_table();
    if (table == nullptr) {
      Throw(origin,
            fmt::format("key '{}': expected a table, found {}", dotted, DescribeValue(*node)));
    }
  }
}

}  // namespace ambdrop::config_detail
