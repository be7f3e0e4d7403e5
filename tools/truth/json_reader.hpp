#pragma once
// A small JSON reader for rig files: objects, arrays, numbers, strings, booleans and null.
// Every value remembers its path ("tdbs[1].clearance_m") so that an error names what is wrong.
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace ambdrop_truth {

class JsonValue {
 public:
  enum class Kind { kNull, kBool, kNumber, kString, kArray, kObject };

  Kind kind() const { return kind_; }
  const std::string& path() const { return path_; }

  /// The member `key`; throws std::runtime_error naming the path when absent.
  const JsonValue& At(std::string_view key) const;
  /// The member `key` or nullptr.
  const JsonValue* Find(std::string_view key) const;
  const std::vector<JsonValue>& Items() const;  ///< an array's elements; throws otherwise
  const std::vector<std::pair<std::string, JsonValue>>& Members() const;

  double AsNumber() const;
  bool AsBool() const;
  const std::string& AsString() const;

  /// Shorthands for members: required, or with a default when absent.
  double Number(std::string_view key) const { return At(key).AsNumber(); }
  double Number(std::string_view key, double fallback) const;
  std::string String(std::string_view key) const { return At(key).AsString(); }
  std::string String(std::string_view key, std::string_view fallback) const;
  bool Bool(std::string_view key, bool fallback) const;

 private:
  friend class JsonParser;
  Kind kind_ = Kind::kNull;
  double number_ = 0.0;
  bool boolean_ = false;
  std::string text_;
  std::vector<JsonValue> items_;
  std::vector<std::pair<std::string, JsonValue>> members_;
  std::string path_;
};

/// Parses a whole document; throws std::runtime_error with the line of a syntax error.
JsonValue ParseJson(std::string_view text);

/// Reads and parses a file; throws std::runtime_error naming the file.
JsonValue ReadJsonFile(const std::string& path);

}  // namespace ambdrop_truth
