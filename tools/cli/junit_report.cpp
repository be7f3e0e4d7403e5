#include "tools/cli/junit_report.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "io/files/json_writer.hpp"

namespace ambdrop {
namespace {

// XML's five escapes; control characters other than tab and newline are not allowed in XML 1.0.
std::string Escape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n') {
          out += ' ';
        } else {
          out += c;
        }
    }
  }
  return out;
}

}  // namespace

std::string JunitXml(const std::string& suite, const std::vector<JunitCase>& cases, double time_s) {
  const auto failures =
      std::count_if(cases.begin(), cases.end(), [](const JunitCase& c) { return !c.pass; });
  std::string xml = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  xml += fmt::format("<testsuites tests=\"{}\" failures=\"{}\">\n", cases.size(), failures);
  xml += fmt::format(
      "  <testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" errors=\"0\" "
      "time=\"{:.3f}\">\n",
      Escape(suite), cases.size(), failures, time_s);
  for (const JunitCase& c : cases) {
    xml += fmt::format("    <testcase classname=\"{}\" name=\"{}\"", Escape(c.classname),
                       Escape(c.name));
    if (c.pass) {
      xml += "/>\n";
      continue;
    }
    xml += fmt::format(">\n      <failure message=\"{}\">{}</failure>\n    </testcase>\n",
                       Escape(c.message), Escape(c.message));
  }
  xml += "  </testsuite>\n</testsuites>\n";
  return xml;
}

void WriteJunit(const std::filesystem::path& path, const std::string& suite,
                const std::vector<JunitCase>& cases, double time_s) {
  WriteTextFile(path, JunitXml(suite, cases, time_s));
}

}  // namespace ambdrop
