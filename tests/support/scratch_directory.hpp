#pragma once
#include <filesystem>
#include <string>

namespace ambdrop::testing {

/// A fresh directory temp_directory_path()/<prefix>_<pid>_<test name>, removed with everything in
/// it when the object goes. Tests must not leave files behind; the name includes the test so
/// parallel ctest processes never share a directory.
class ScratchDirectory {
 public:
  explicit ScratchDirectory(const std::string& prefix);
  ~ScratchDirectory();
  ScratchDirectory(const ScratchDirectory&) = delete;
  ScratchDirectory& operator=(const ScratchDirectory&) = delete;
  const std::filesystem::path& path() const { return path_; }
  /// path()/name (the file is not created).
  std::filesystem::path File(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

}  // namespace ambdrop::testing
