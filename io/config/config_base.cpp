#include "io/config/config_base.hpp"

#include <fmt/format.h>

#include <array>
#include <optional>
#include <string_view>

#include "io/config/config_file.hpp"
#include "io/config/config_loader.hpp"
#include "io/config/toml_reader.hpp"

namespace ambdrop::config_detail {
namespace {

constexpr int kMaxBaseDepth = 8;
constexpr std::array<std::string_view, 5> kComponentSections = {"amb", "tdb", "sensor", "bearing",
                                                                "unbalance"};

bool IsComponentSection(std::string_view key) {
  for (const std::string_view s : kComponentSections) {
    if (s == key) return true;
  }
  return false;
}

// Lays `over` onto `base`. depth 0: sections; depth 1 of a component section: whole components.
// Nodes are moved, not copied: toml++ copies drop a node's source (file and line), which the
// error messages need.
void Merge(toml::table& base, toml::table& over, bool components_replace) {
  for (auto&& [key, node] : over) {
    toml::node* existing = base.get(key.str());
    const bool both_tables = existing && existing->is_table() && node.is_table();
    if (both_tables && !components_replace) {
      Merge(*existing->as_table(), *node.as_table(), false);
      continue;
    }
    base.insert_or_assign(key.str(), std::move(node));
  }
}

}  // namespace

toml::table ResolveBase(toml::table table, const std::filesystem::path& directory,
                        const std::string& source_name, int depth) {
  const toml::node* base_node = table.get("base");
  if (base_node == nullptr) return table;
  if (!base_node->is_string()) {
    ThrowBadValue(*base_node, source_name, "base", "the path of a base config (a string)");
  }
  if (depth >= kMaxBaseDepth) {
    ThrowBadValue(
        *base_node, source_name, "base",
        fmt::format("at most {} levels of base configs (is there a cycle?)", kMaxBaseDepth));
  }
  const std::filesystem::path base_path = directory / base_node->as_string()->get();
  std::string why;
  const std::optional<std::string> text = ReadConfigFile(base_path, &why);
  if (!text) {
    ThrowBadValue(*base_node, source_name, "base", "a readable config file",
                  fmt::format("\"{}\" ({})", base_node->as_string()->get(), why));
  }
  toml::table base;
  try {
    base = toml::parse(*text, base_path.string());
  } catch (const toml::parse_error& error) {
    throw ConfigError(fmt::format("{}:{}: {} (column {})", base_path.string(),
                                  error.source().begin.line, error.description(),
                                  error.source().begin.column));
  }
  base = ResolveBase(std::move(base), base_path.parent_path(), base_path.string(), depth + 1);
  table.erase("base");
  for (auto&& [key, node] : table) {
    toml::node* existing = base.get(key.str());
    if (existing && existing->is_table() && node.is_table()) {
      Merge(*existing->as_table(), *node.as_table(), IsComponentSection(key.str()));
    } else {
      base.insert_or_assign(key.str(), std::move(node));
    }
  }
  return base;
}

}  // namespace ambdrop::config_detail
