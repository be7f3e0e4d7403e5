#pragma once
#include <string>
#include <vector>

#include "io/config/config_loader.hpp"
#include "io/config/config_variants.hpp"
#include "rt_core/model_params.hpp"

namespace ambdrop::testing {

/// Path of a file in the source tree's configs/ folder.
std::string ConfigPath(const std::string& file_name);

/// Loads configs/<file_name> with optional overrides.
ModelParams LoadTestConfig(const std::string& file_name,
                           const std::vector<std::string>& overrides = {});

/// The file names of every rig in configs/ (the scenarios are runs of these), sorted.
std::vector<std::string> RigConfigFiles();
/// The independent rigs' translated configs (tests/truth/*.toml), as paths ConfigPath takes.
std::vector<std::string> TruthRigConfigFiles();

/// The ConfigError a config text (named test.toml) with `overrides` raises, or "no error".
std::string ConfigErrorOf(const std::string& text, const std::vector<std::string>& overrides = {});

/// The smallest rigid rotor a config accepts, as the config-key tests start their texts: an
/// empty first line, then [rotor] and [rotor.rigid] on lines 2-8, so a table appended after it
/// starts on line 9 (their expected errors name lines).
inline const std::string kSmallRigidRotor = R"(
[rotor]
model = "rigid"
[rotor.rigid]
mass_kg = 10.0
polar_inertia_kg_m2 = 0.01
transverse_inertia_kg_m2 = 0.1
centre_of_mass_m = 0.2
)";
/// ... and one sensor at 0.1 m (lines 9-10): a table appended after it starts on line 11.
inline const std::string kSmallRigidRotorWithSensor =
    kSmallRigidRotor + "[sensor.a]\nposition_m = 0.1\n";

/// The same kept as a tree that effects' --set overrides are applied to (what `ambdrop fit` does).
ConfigVariants LoadTestVariants(const std::string& file_name,
                                const std::vector<std::string>& overrides = {});

}  // namespace ambdrop::testing
