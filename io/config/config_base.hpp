#pragma once
#include <toml++/toml.h>

#include <filesystem>
#include <string>

namespace ambdrop::config_detail {

/// Resolves `base = "other.toml"` (relative to `directory`): the base file is loaded (its own
/// base first), then this table is laid over it. Sections merge key by key; a named component
/// (`[amb.NAME]`, `[tdb.NAME]`, `[sensor.NAME]`, `[bearing.NAME]`, `[unbalance.NAME]`) given
/// here replaces the base's component of that name whole, so a derived rig can swap an AMB's
/// force law. Nodes keep their own file and line for error messages.
toml::table ResolveBase(toml::table table, const std::filesystem::path& directory,
                        const std::string& source_name, int depth = 0);

}  // namespace ambdrop::config_detail
