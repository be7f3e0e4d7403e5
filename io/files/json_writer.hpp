#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ambdrop {

/// A tiny streaming JSON writer: keys come out in the order they are written (reports read
/// top-down), doubles with 17 significant digits (they parse back to the same bits), and NaN,
/// infinities and absent optionals as null (JSON has no spelling for them).
///
/// Misuse (a value where a key is due, unbalanced Begin/End) throws std::logic_error: it is a
/// programming error, and silently emitting invalid JSON would be worse.
class JsonWriter {
 public:
  /// `indent` spaces per level; 0 writes everything on one line.
  explicit JsonWriter(int indent = 2);

  /// `compact` containers are written on one line whatever the indent (numeric lists).
  JsonWriter& BeginObject(bool compact = false);
  JsonWriter& EndObject();
  JsonWriter& BeginArray(bool compact = false);
  JsonWriter& EndArray();

  /// The next member's name; must be followed by exactly one value or container.
  JsonWriter& Key(std::string_view key);

  JsonWriter& Number(double value);
  JsonWriter& Number(std::optional<double> value);
  JsonWriter& Integer(std::int64_t value);
  JsonWriter& Bool(bool value);
  JsonWriter& String(std::string_view value);
  JsonWriter& Null();

  /// A compact array of numbers.
  JsonWriter& NumberArray(const std::vector<double>& values);

  /// True once the single top-level value is complete.
  bool complete() const noexcept { return complete_; }
  /// The document so far; call when complete() for valid JSON. Ends with a newline.
  const std::string& str() const noexcept { return text_; }

 private:
  struct Frame {
    bool is_object = false;
    bool compact = false;
    int count = 0;
  };

  void BeforeValue();
  void AfterScalar();
  void Begin(bool is_object, bool compact, char open);
  void End(bool is_object, char close);
  void NewLine(std::size_t depth);
  bool InCompact() const noexcept;
  void AppendEscaped(std::string_view value);

  int indent_;
  std::string text_;
  std::vector<Frame> stack_;
  bool key_pending_ = false;
  bool complete_ = false;
};

/// Writes `text` to `path` (replacing it); throws std::runtime_error naming the path on failure.
void WriteTextFile(const std::filesystem::path& path, std::string_view text);

}  // namespace ambdrop
