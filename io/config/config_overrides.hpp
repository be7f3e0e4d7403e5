#pragma once
#include <toml++/toml.h>

#include <string>

namespace ambdrop::config_detail {

/// Applies one "dotted.path=value" override (e.g. "rotor.sections[0].length_m=0.3") to `root`,
/// creating missing tables and array elements on the way. The value is read as TOML; if it is
/// not valid TOML it is taken as a bare string. Every node it creates carries the override as its
/// source, so later errors point at the command line.
void ApplyOverride(toml::table& root, const std::string& override_text);

}  // namespace ambdrop::config_detail
