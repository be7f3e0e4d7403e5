#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace ambdrop::config_detail {

/// Larger than any rig config (a 1024-point current profile per AMB is ~100 kB).
inline constexpr std::uintmax_t kMaxConfigFileBytes = 16u << 20;

/// The text of a config file, or nullopt with `*why` saying what is wrong with the path: it
/// cannot be opened, is not a regular file (a folder reads as empty, /dev/zero never ends), is
/// larger than kMaxConfigFileBytes, or cannot be read.
std::optional<std::string> ReadConfigFile(const std::filesystem::path& path, std::string* why);

}  // namespace ambdrop::config_detail
