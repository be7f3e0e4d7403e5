#pragma once
// Shared by the libFuzzer targets (tests/fuzz/README.md): the decoders read files, so each
// input is written to one scratch file per process first.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>

namespace ambdrop::fuzz {

/// The scratch file, removed when the fuzzer exits (each smoke run left one per target in
/// /tmp). A crash leaves it: libFuzzer writes the crashing input elsewhere anyway.
struct ScratchFile {
  std::string path;
  ~ScratchFile() { std::remove(path.c_str()); }
};

/// The input's bytes in a file of this process (overwritten by each input); returns its path.
inline std::string InputFile(const std::uint8_t* data, std::size_t size, const char* suffix) {
  static const ScratchFile file{"/tmp/ambdrop_fuzz_" + std::to_string(::getpid()) + "_input" +
                                suffix};
  std::ofstream(file.path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return file.path;
}

/// A config of the source tree (configs/NAME).
inline std::string ConfigPath(const char* name) {
  return std::string(AMBDROP_SOURCE_DIR) + "/configs/" + name;
}

}  // namespace ambdrop::fuzz
