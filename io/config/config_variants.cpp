#include "io/config/config_variants.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>
#include <utility>

#include "io/config/config_file.hpp"
#include "io/config/config_overrides.hpp"
#include "io/config/config_tree.hpp"

namespace ambdrop {

struct ConfigVariants::Tree {
  toml::table root;
  std::string text;
  std::string source_name;
  std::vector<std::string> overrides;  ///< the user's own
};

ConfigVariants::ConfigVariants(std::unique_ptr<Tree> tree, LoadedConfig declared)
    : tree_(std::move(tree)), declared_(std::move(declared)) {}
ConfigVariants::ConfigVariants(ConfigVariants&&) noexcept = default;
ConfigVariants& ConfigVariants::operator=(ConfigVariants&&) noexcept = default;
ConfigVariants::~ConfigVariants() = default;

ConfigVariants ConfigVariants::Load(const std::filesystem::path& path,
                                    const std::vector<std::string>& overrides) {
  std::string why;
  const std::optional<std::string> text = config_detail::ReadConfigFile(path, &why);
  if (!text)
    throw ConfigError(fmt::format("{}: not a readable config file: {}", path.string(), why));
  return FromString(*text, path.string(), overrides);
}

ConfigVariants ConfigVariants::FromString(const std::string& text, const std::string& source_name,
                                          const std::vector<std::string>& overrides) {
  auto tree = std::make_unique<Tree>();
  tree->root = config_detail::ConfigTree(text, source_name, overrides);
  tree->text = text;
  tree->source_name = source_name;
  tree->overrides = overrides;
  LoadedConfig declared = config_detail::ReadLoadedConfig(tree->root, text, source_name);
  return ConfigVariants(std::move(tree), std::move(declared));
}

LoadedConfig ConfigVariants::With(const std::vector<std::string>& overrides) const {
  if (overrides.empty()) return declared_;
  // Parsed again rather than copied: toml++ copies a node without its source, and the readers
  // need it (which key came from --set, and where each stands in the file for the messages).
  // With a copy, the user's own `--set ...current_law=...` looked like the file's, and every
  // variant refused the file's numbers of the law it replaced.
  toml::table root = config_detail::ConfigTree(tree_->text, tree_->source_name, tree_->overrides);
  for (const std::string& o : overrides) config_detail::ApplyOverride(root, o);
  return config_detail::ReadLoadedConfig(root, tree_->text, tree_->source_name);
}

std::string OverrideNumber(double value) {
  if (!std::isfinite(value)) {
    throw std::invalid_argument(fmt::format("OverrideNumber: {} is not finite", value));
  }
  std::string text = fmt::format("{}", value);  // shortest round trip
  if (text.find_first_of(".eEn") == std::string::npos) text += ".0";
  return text;
}

std::string OverrideInteger(std::int64_t value) {
  return fmt::format("{}", value);
}

std::string OverrideFor(const ConfigKey& key, double value) {
  if (!std::isfinite(value)) {
    throw std::invalid_argument(fmt::format("OverrideFor: {} = {} is not finite", key.path, value));
  }
  return key.path + "=" +
         (key.integer ? OverrideInteger(std::llround(value)) : OverrideNumber(value));
}

}  // namespace ambdrop
