#include "tools/cli/settled_start_refusal.hpp"

#include <fmt/format.h>

namespace ambdrop {

bool RefusesSettledStart(const Model& model, const std::string& config_path, const char* run_kind) {
  if (!(model.params.simulation.settle_s > 0.0)) return false;
  fmt::print(stderr,
             "error: {}: simulation.settle_s = {} s: a {} run starts from the levitated "
             "equilibrium; the settled start is for sim and fit (set settle_s = 0)\n",
             config_path, model.params.simulation.settle_s, run_kind);
  return true;
}

}  // namespace ambdrop
