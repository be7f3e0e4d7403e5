#include "tools/cli/command_config.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <exception>
#include <stdexcept>

#include "controller_if/loop/hil_session.hpp"

namespace ambdrop {

std::optional<LoadedConfig> LoadCommandConfig(const std::string& path,
                                              const std::vector<std::string>& overrides) {
  try {
    return LoadConfig(path, overrides);
  } catch (const ConfigError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
  } catch (const std::exception& e) {
    // Anything else the loader throws (an unreadable file ...) is still a problem of the input.
    fmt::print(stderr, "error: {}: {}\n", path, e.what());
  }
  return std::nullopt;
}

std::optional<Model> BuildCommandModel(const std::string& path, const ModelParams& params) {
  try {
    std::optional<Model> model(BuildModel(params));
    if (model->params.controller.kind != ControllerKind::kNone) ControllerSubsteps(*model);
    return model;
  } catch (const std::invalid_argument& e) {
    fmt::print(stderr, "error: {}: cannot build the model: {}\n", path, e.what());
  }
  return std::nullopt;
}

}  // namespace ambdrop
