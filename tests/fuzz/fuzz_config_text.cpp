// A config from text (io/config/config_loader.hpp): any text either loads or is a ConfigError
// naming file, line and key; no other exception, crash or undefined behaviour. Stops after
// validation (the model is not built: that is the config's consumers' job).
#include <cstddef>
#include <cstdint>
#include <string>

#include "io/config/config_loader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    (void)ambdrop::LoadConfigFromString(text, "fuzz.toml", {});
  } catch (const ambdrop::ConfigError&) {
  }
  return 0;
}
