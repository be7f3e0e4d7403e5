#include "io/config/config_file.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>

namespace ambdrop::config_detail {

std::optional<std::string> ReadConfigFile(const std::filesystem::path& path, std::string* why) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (ec) {
    *why = fmt::format("cannot open {}: {}", path.string(), ec.message());
    return std::nullopt;
  }
  if (!std::filesystem::is_regular_file(status)) {
    *why = fmt::format(
        "{} is not a regular file ({})", path.string(),
        std::filesystem::is_directory(status) ? "a folder" : "a device or special file");
    return std::nullopt;
  }
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec || size > kMaxConfigFileBytes) {
    *why = ec ? fmt::format("cannot read {}: {}", path.string(), ec.message())
              : fmt::format("{} holds {} bytes, more than a config's {}", path.string(), size,
                            kMaxConfigFileBytes);
    return std::nullopt;
  }
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    *why = fmt::format("cannot open {}: {}", path.string(), std::strerror(errno));
    return std::nullopt;
  }
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad()) {
    *why = fmt::format("cannot read {}", path.string());
    return std::nullopt;
  }
  return text.str();
}

}  // namespace ambdrop::config_detail
