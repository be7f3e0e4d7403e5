#pragma once
// What a controller designer needs of the emulated plant (issue 17 item 2), from the rig as
// built: the wire's index order and names, units, signs and rates, and per AMB the static load,
// the linearised gains ki and ks, the bias, limits and the power-loss law; the sensors' models;
// the in-process reference controller's gains in A/m. Versioned (schema_version): issue 24's
// additions extend it. `ambdrop hil CONFIG --describe FILE.json` writes it.
#include <string>

#include "rt_core/model.hpp"

namespace ambdrop {

inline constexpr int kPlantDescriptionVersion = 1;

/// The description as JSON text (`config_path` is reported as given).
std::string PlantDescriptionJson(const Model& model, const std::string& config_path);

}  // namespace ambdrop
