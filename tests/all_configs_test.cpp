// Every config shipped in configs/ loads, builds and runs its first 10 ms without diverging.
#include <gtest/gtest.h>

#include <filesystem>

#include "controller_if/loop/offline_run.hpp"
#include "io/config/config_loader.hpp"
#include "rt_core/model.hpp"

namespace ambdrop::all_configs_test {
namespace {

TEST(AllConfigs, LoadBuildAndRun) {
  int count = 0;
  const std::filesystem::path dir = std::filesystem::path(AMBDROP_SOURCE_DIR) / "configs";
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir)) {
    if (entry.path().extension() != ".toml") continue;
    SCOPED_TRACE(entry.path().string());
    const LoadedConfig config = LoadConfig(entry.path(), {"simulation.duration_s=0.01"});
    const Model model = BuildModel(config.params);
    const OfflineRunResult r = RunOffline(model, {});
    EXPECT_EQ(r.status, StepStatus::kOk) << r.failure_message;
    EXPECT_EQ(r.steps, model.total_steps);
    ++count;
  }
  EXPECT_GE(count, 3);
}

}  // namespace
}  // namespace ambdrop::all_configs_test
