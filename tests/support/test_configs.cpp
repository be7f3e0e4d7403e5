#include "test_configs.hpp"

#include <algorithm>
#include <filesystem>

namespace ambdrop::testing {

std::string ConfigPath(const std::string& file_name) {
  return std::string(AMBDROP_SOURCE_DIR) + "/configs/" + file_name;
}

ModelParams LoadTestConfig(const std::string& file_name,
                           const std::vector<std::string>& overrides) {
  return LoadConfig(ConfigPath(file_name), overrides).params;
}

std::vector<std::string> RigConfigFiles() {
  std::vector<std::string> rigs;
  for (const auto& entry : std::filesystem::directory_iterator(ConfigPath(""))) {
    if (entry.path().extension() == ".toml") rigs.push_back(entry.path().filename().string());
  }
  std::sort(rigs.begin(), rigs.end());
  return rigs;
}

std::vector<std::string> TruthRigConfigFiles() {
  std::vector<std::string> rigs;
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(AMBDROP_SOURCE_DIR) + "/tests/truth")) {
    if (entry.path().extension() == ".toml") {
      rigs.push_back("../tests/truth/" + entry.path().filename().string());
    }
  }
  std::sort(rigs.begin(), rigs.end());
  return rigs;
}

std::string ConfigErrorOf(const std::string& text, const std::vector<std::string>& overrides) {
  try {
    LoadConfigFromString(text, "test.toml", overrides);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

ConfigVariants LoadTestVariants(const std::string& file_name,
                                const std::vector<std::string>& overrides) {
  return ConfigVariants::Load(ConfigPath(file_name), overrides);
}

}  // namespace ambdrop::testing
