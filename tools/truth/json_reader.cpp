#include "json_reader.hpp"

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace ambdrop_truth {

namespace {

[[noreturn]] void Fail(const std::string& path, const std::string& what) {
  throw std::runtime_error((path.empty() ? std::string("document") : path) + ": " + what);
}

const char* KindName(JsonValue::Kind kind) {
  switch (kind) {
    case JsonValue::Kind::kNull:
      return "null";
    case JsonValue::Kind::kBool:
      return "a boolean";
    case JsonValue::Kind::kNumber:
      return "a number";
    case JsonValue::Kind::kString:
      return "a string";
    case JsonValue::Kind::kArray:
      return "an array";
    case JsonValue::Kind::kObject:
      return "an object";
  }
  return "?";
}

}  // namespace

class JsonParser {
 public:
  explicit JsonParser(std::string_view text) : text_(text) {}

  JsonValue Document() {
    JsonValue v = Value("");
    SkipSpace();
    if (pos_ != text_.size()) Error("text after the document");
    return v;
  }

 private:
  [[noreturn]] void Error(const std::string& what) const {
    int line = 1;
    for (std::size_t i = 0; i < pos_ && i < text_.size(); ++i) line += text_[i] == '\n' ? 1 : 0;
    throw std::runtime_error("JSON line " + std::to_string(line) + ": " + what);
  }

  void SkipSpace() {
    while (pos_ < text_.size() && (text_[pos_] == ' ' || text_[pos_] == '\n' ||
                                   text_[pos_] == '\t' || text_[pos_] == '\r')) {
      ++pos_;
    }
  }

  char Peek() {
    SkipSpace();
    if (pos_ >= text_.size()) Error("unexpected end");
    return text_[pos_];
  }

  void Expect(char c) {
    if (Peek() != c) Error(std::string("expected '") + c + "'");
    ++pos_;
  }

  bool Literal(std::string_view word) {
    if (text_.substr(pos_, word.size()) != word) return false;
    pos_ += word.size();
    return true;
  }

  std::string String() {
    Expect('"');
    std::string out;
    while (true) {
      if (pos_ >= text_.size()) Error("unterminated string");
      const char c = text_[pos_++];
      if (c == '"') return out;
      if (c != '\\') {
        out += c;
        continue;
      }
      if (pos_ >= text_.size()) Error("unterminated escape");
      const char e = text_[pos_++];
      switch (e) {
        case 'n':
          out += '\n';
          break;
        case 't':
          out += '\t';
          break;
        case '"':
        case '\\':
        case '/':
          out += e;
          break;
        default:
          // Rig files are ASCII; \uXXXX and the rarer escapes are not needed.
          Error(std::string("unsupported escape \\") + e);
      }
    }
  }

  JsonValue Value(const std::string& path) {
    JsonValue v;
    v.path_ = path;
    const char c = Peek();
    if (c == '{') {
      ++pos_;
      v.kind_ = JsonValue::Kind::kObject;
      if (Peek() == '}') {
        ++pos_;
        return v;
      }
      while (true) {
        const std::string key = String();
        for (const auto& member : v.members_) {
          if (member.first == key) Error("duplicate key '" + key + "'");
        }
        Expect(':');
        v.members_.emplace_back(key, Value(path.empty() ? key : path + "." + key));
        if (Peek() == ',') {
          ++pos_;
          continue;
        }
        Expect('}');
        return v;
      }
    }
    if (c == '[') {
      ++pos_;
      v.kind_ = JsonValue::Kind::kArray;
      if (Peek() == ']') {
        ++pos_;
        return v;
      }
      while (true) {
        v.items_.push_back(Value(path + "[" + std::to_string(v.items_.size()) + "]"));
        if (Peek() == ',') {
          ++pos_;
          continue;
        }
        Expect(']');
        return v;
      }
    }
    if (c == '"') {
      v.kind_ = JsonValue::Kind::kString;
      v.text_ = String();
      return v;
    }
    if (Literal("true") || Literal("false")) {
      v.kind_ = JsonValue::Kind::kBool;
      v.boolean_ = text_[pos_ - 1] == 'e' && text_[pos_ - 2] == 'u';  // "true" ends in "ue"
      return v;
    }
    if (Literal("null")) return v;
    // A number: strtod on a bounded copy (the view need not be NUL-terminated).
    const std::size_t start = pos_;
    while (pos_ < text_.size() &&
           std::string_view("+-0123456789.eE").find(text_[pos_]) != std::string_view::npos) {
      ++pos_;
    }
    if (pos_ == start) Error("unexpected character");
    const std::string number(text_.substr(start, pos_ - start));
    char* end = nullptr;
    v.kind_ = JsonValue::Kind::kNumber;
    v.number_ = std::strtod(number.c_str(), &end);
    if (end != number.c_str() + number.size()) Error("bad number '" + number + "'");
    return v;
  }

  std::string_view text_;
  std::size_t pos_ = 0;
};

const JsonValue* JsonValue::Find(std::string_view key) const {
  if (kind_ != Kind::kObject)
    Fail(path_, std::string("expected an object, found ") + KindName(kind_));
  for (const auto& member : members_) {
    if (member.first == key) return &member.second;
  }
  return nullptr;
}

const JsonValue& JsonValue::At(std::string_view key) const {
  const JsonValue* v = Find(key);
  if (v == nullptr) Fail(path_, "missing key '" + std::string(key) + "'");
  return *v;
}

const std::vector<JsonValue>& JsonValue::Items() const {
  if (kind_ != Kind::kArray)
    Fail(path_, std::string("expected an array, found ") + KindName(kind_));
  return items_;
}

const std::vector<std::pair<std::string, JsonValue>>& JsonValue::Members() const {
  if (kind_ != Kind::kObject)
    Fail(path_, std::string("expected an object, found ") + KindName(kind_));
  return members_;
}

double JsonValue::AsNumber() const {
  if (kind_ != Kind::kNumber)
    Fail(path_, std::string("expected a number, found ") + KindName(kind_));
  return number_;
}

bool JsonValue::AsBool() const {
  if (kind_ != Kind::kBool)
    Fail(path_, std::string("expected a boolean, found ") + KindName(kind_));
  return boolean_;
}

const std::string& JsonValue::AsString() const {
  if (kind_ != Kind::kString)
    Fail(path_, std::string("expected a string, found ") + KindName(kind_));
  return text_;
}

double JsonValue::Number(std::string_view key, double fallback) const {
  const JsonValue* v = Find(key);
  return v == nullptr ? fallback : v->AsNumber();
}

std::string JsonValue::String(std::string_view key, std::string_view fallback) const {
  const JsonValue* v = Find(key);
  return v == nullptr ? std::string(fallback) : v->AsString();
}

bool JsonValue::Bool(std::string_view key, bool fallback) const {
  const JsonValue* v = Find(key);
  return v == nullptr ? fallback : v->AsBool();
}

JsonValue ParseJson(std::string_view text) {
  return JsonParser(text).Document();
}

JsonValue ReadJsonFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::ostringstream text;
  text << in.rdbuf();
  try {
    return ParseJson(text.str());
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
}

}  // namespace ambdrop_truth
