#include "test_configs.hpp"

namespace ambdrop::testing {

std::string ConfigPath(const std::string& file_name) {
  return std::string(AMBDROP_SOURCE_DIR) + "/configs/" + file_name;
}

ModelParams LoadTestConfig(const std::string& file_name,
                           const std::vector<std::string>& overrides) {
  return LoadConfig(ConfigPath(file_name), overrides).params;
}

ConfigVariants LoadTestVariants(const std::string& file_name,
                                const std::vector<std::string>& overrides) {
  return ConfigVariants::Load(ConfigPath(file_name), overrides);
}

}  // namespace ambdrop::testing
