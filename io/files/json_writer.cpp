#include "io/files/json_writer.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

namespace ambdrop {

JsonWriter::JsonWriter(int indent) : indent_(indent < 0 ? 0 : indent) {}

bool JsonWriter::InCompact() const noexcept {
  return indent_ == 0 || (!stack_.empty() && stack_.back().compact);
}

void JsonWriter::NewLine(std::size_t depth) {
  text_.push_back('\n');
  text_.append(depth * static_cast<std::size_t>(indent_), ' ');
}

// Everything that writes a value (scalar or container opening) goes through here, so the
// separator and key bookkeeping live in one place.
void JsonWriter::BeforeValue() {
  if (complete_) throw std::logic_error("JsonWriter: a second top-level value");
  if (stack_.empty()) return;
  Frame& frame = stack_.back();
  if (frame.is_object) {
    if (!key_pending_) throw std::logic_error("JsonWriter: object member without a key");
    key_pending_ = false;
    return;  // Key() already wrote the separator and the name
  }
  if (frame.count > 0) text_.push_back(',');
  if (InCompact()) {
    if (frame.count > 0 && indent_ > 0) text_.push_back(' ');
  } else {
    NewLine(stack_.size());
  }
  ++frame.count;
}

JsonWriter& JsonWriter::Key(std::string_view key) {
  if (stack_.empty() || !stack_.back().is_object) {
    throw std::logic_error("JsonWriter: a key outside an object");
  }
  if (key_pending_) throw std::logic_error("JsonWriter: two keys in a row");
  Frame& frame = stack_.back();
  if (frame.count > 0) text_.push_back(',');
  if (InCompact()) {
    if (frame.count > 0 && indent_ > 0) text_.push_back(' ');
  } else {
    NewLine(stack_.size());
  }
  ++frame.count;
  AppendEscaped(key);
  text_.append(indent_ > 0 ? ": " : ":");
  key_pending_ = true;
  return *this;
}

void JsonWriter::Begin(bool is_object, bool compact, char open) {
  BeforeValue();
  text_.push_back(open);
  stack_.push_back(Frame{is_object, compact || InCompact(), 0});
}

void JsonWriter::End(bool is_object, char close) {
  if (stack_.empty() || stack_.back().is_object != is_object) {
    throw std::logic_error("JsonWriter: unbalanced container");
  }
  if (key_pending_) throw std::logic_error("JsonWriter: key without a value");
  const Frame frame = stack_.back();
  stack_.pop_back();
  if (frame.count > 0 && !frame.compact) NewLine(stack_.size());
  text_.push_back(close);
  if (stack_.empty()) {
    complete_ = true;
    text_.push_back('\n');
  }
}

void JsonWriter::AfterScalar() {
  if (!stack_.empty()) return;
  complete_ = true;
  text_.push_back('\n');
}

JsonWriter& JsonWriter::BeginObject(bool compact) {
  Begin(true, compact, '{');
  return *this;
}

JsonWriter& JsonWriter::EndObject() {
  End(true, '}');
  return *this;
}

JsonWriter& JsonWriter::BeginArray(bool compact) {
  Begin(false, compact, '[');
  return *this;
}

JsonWriter& JsonWriter::EndArray() {
  End(false, ']');
  return *this;
}

JsonWriter& JsonWriter::Number(double value) {
  if (!std::isfinite(value)) return Null();
  BeforeValue();
  // {:.17g} round-trips every double; it never produces a JSON-invalid spelling for finite
  // values ("1e+20", "-0", "0.10000000000000001" are all valid numbers).
  fmt::format_to(std::back_inserter(text_), "{:.17g}", value);
  AfterScalar();
  return *this;
}

JsonWriter& JsonWriter::Number(std::optional<double> value) {
  return value ? Number(*value) : Null();
}

JsonWriter& JsonWriter::Integer(std::int64_t value) {
  BeforeValue();
  fmt::format_to(std::back_inserter(text_), "{}", value);
  AfterScalar();
  return *this;
}

JsonWriter& JsonWriter::Bool(bool value) {
  BeforeValue();
  text_.append(value ? "true" : "false");
  AfterScalar();
  return *this;
}

JsonWriter& JsonWriter::String(std::string_view value) {
  BeforeValue();
  AppendEscaped(value);
  AfterScalar();
  return *this;
}

JsonWriter& JsonWriter::Null() {
  BeforeValue();
  text_.append("null");
  AfterScalar();
  return *this;
}

JsonWriter& JsonWriter::NumberArray(const std::vector<double>& values) {
  BeginArray(true);
  for (double value : values) Number(value);
  return EndArray();
}

void JsonWriter::AppendEscaped(std::string_view value) {
  text_.push_back('"');
  for (char c : value) {
    switch (c) {
      case '"':
        text_.append("\\\"");
        break;
      case '\\':
        text_.append("\\\\");
        break;
      case '\n':
        text_.append("\\n");
        break;
      case '\r':
        text_.append("\\r");
        break;
      case '\t':
        text_.append("\\t");
        break;
      default:
        // Other control characters must be escaped; bytes >= 0x80 are passed through (UTF-8).
        if (static_cast<unsigned char>(c) < 0x20) {
          fmt::format_to(std::back_inserter(text_), "\\u{:04x}", static_cast<unsigned>(c));
        } else {
          text_.push_back(c);
        }
    }
  }
  text_.push_back('"');
}

void WriteTextFile(const std::filesystem::path& path, std::string_view text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) {
    throw std::runtime_error(
        fmt::format("cannot open '{}' for writing: {}", path.string(), std::strerror(errno)));
  }
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  out.close();
  if (!out) throw std::runtime_error(fmt::format("cannot write '{}'", path.string()));
}

}  // namespace ambdrop
