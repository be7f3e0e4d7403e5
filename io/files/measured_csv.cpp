#include "io/files/measured_csv.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string_view>
#include <system_error>

namespace ambdrop {
namespace {

// A logger's clock jitters; a larger deviation means dropped or duplicated samples, which the
// fit's fixed-rate comparison would silently misalign.
constexpr double kMaxIntervalDeviation = 0.01;
// Long enough to recognise a bad field, short enough to keep a message on one line.
constexpr std::size_t kMaxFieldInMessage = 40;
// Spreadsheet programs prefix their UTF-8 exports with it.
constexpr std::string_view kUtf8Bom = "\xEF\xBB\xBF";

[[noreturn]] void Fail(const std::string& source, std::size_t line, std::string_view what) {
  throw MeasuredRecordError(fmt::format("{}:{}: {}", source, line, what));
}

std::string_view Trim(std::string_view text) {
  const std::size_t begin = text.find_first_not_of(" \t");
  if (begin == std::string_view::npos) return {};
  return text.substr(begin, text.find_last_not_of(" \t") - begin + 1);
}

/// Fields with the blanks around them removed (loggers often write "t, x").
void Split(std::string_view line, std::vector<std::string_view>* fields) {
  fields->clear();
  for (;;) {
    const std::size_t comma = line.find(',');
    fields->push_back(Trim(line.substr(0, comma)));
    if (comma == std::string_view::npos) return;
    line.remove_prefix(comma + 1);
  }
}

std::string Found(std::string_view field) {
  if (field.empty()) return "an empty field";
  if (field.size() > kMaxFieldInMessage) {
    return fmt::format("'{}...'", field.substr(0, kMaxFieldInMessage));
  }
  return fmt::format("'{}'", field);
}

// std::from_chars: the C locale's "." whatever the process locale, and exact round trips.
double ParseNumber(std::string_view field, const std::string& source, std::size_t line,
                   std::string_view column) {
  std::string_view digits = field;
  // from_chars refuses a leading '+', which printf("%+g") writes.
  if (digits.size() > 1 && digits[0] == '+' && digits[1] != '-' && digits[1] != '+') {
    digits.remove_prefix(1);
  }
  double value = 0.0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (error == std::errc::result_out_of_range) {
    Fail(source, line,
         fmt::format("column '{}': expected a number within the range of a double, found {}",
                     column, Found(field)));
  }
  if (error != std::errc() || end != digits.data() + digits.size()) {
    Fail(source, line,
         fmt::format("column '{}': expected a number, found {}", column, Found(field)));
  }
  if (!std::isfinite(value)) {
    Fail(source, line,
         fmt::format("column '{}': expected a finite number, found {}", column, Found(field)));
  }
  return value;
}

void ReadHeader(const std::vector<std::string_view>& fields, std::size_t line,
                std::string_view time_unit, MeasuredRecord* record) {
  const std::string& time = record->time_column;
  if (fields[0] != time) {
    Fail(record->source, line,
         fmt::format("header column 1: expected '{}' (time, {}), found {}", time, time_unit,
                     Found(fields[0])));
  }
  for (std::size_t i = 1; i < fields.size(); ++i) {
    const std::string_view name = fields[i];
    if (name.empty()) {
      Fail(record->source, line,
           fmt::format("header column {}: expected a column name, found an empty field", i + 1));
    }
    const auto previous = std::find(record->columns.begin(), record->columns.end(), name);
    if (name == time || previous != record->columns.end()) {
      const std::size_t first =
          name == time ? 1 : 2 + static_cast<std::size_t>(previous - record->columns.begin());
      Fail(record->source, line,
           fmt::format("header column {}: expected a name no other column has, found {} "
                       "(column {} has it)",
                       i + 1, Found(name), first));
    }
    record->columns.emplace_back(name);
  }
  record->values.resize(record->columns.size());
}

void ReadRow(const std::vector<std::string_view>& fields, std::size_t line,
             std::string_view time_unit, MeasuredRecord* record) {
  const std::size_t width = 1 + record->columns.size();
  if (fields.size() < width) {
    // Split gives at least one field, so the first missing one is a channel, never t.
    Fail(record->source, line,
         fmt::format("column '{}': expected a number, found the end of the row ({} of {} fields)",
                     record->columns[fields.size() - 1], fields.size(), width));
  }
  if (fields.size() > width) {
    Fail(record->source, line,
         fmt::format("column {}: expected the end of the row (the header has {} columns), "
                     "found {}",
                     width + 1, width, Found(fields[width])));
  }
  const double t = ParseNumber(fields[0], record->source, line, record->time_column);
  if (!record->time_s.empty() && !(t > record->time_s.back())) {
    Fail(record->source, line,
         fmt::format("column '{}': expected a time after the previous row's {} {}, found {}",
                     record->time_column, record->time_s.back(), time_unit, Found(fields[0])));
  }
  record->time_s.push_back(t);
  for (std::size_t c = 0; c < record->columns.size(); ++c) {
    record->values[c].push_back(
        ParseNumber(fields[c + 1], record->source, line, record->columns[c]));
  }
}

// The worst interval is the one reported: after a dropped sample every interval may deviate
// from the shifted mean, but the gap is the one to point at.
void CheckEvenSampling(const MeasuredRecord& record, const std::vector<std::size_t>& lines,
                       std::string_view unit) {
  const double mean = record.SampleInterval();
  std::size_t worst = 1;
  double worst_deviation = -1.0;
  for (std::size_t i = 1; i < record.time_s.size(); ++i) {
    const double deviation = std::abs(record.time_s[i] - record.time_s[i - 1] - mean);
    if (deviation > worst_deviation) {
      worst = i;
      worst_deviation = deviation;
    }
  }
  if (worst_deviation <= kMaxIntervalDeviation * mean) return;
  Fail(record.source, lines[worst],
       fmt::format("column '{}': expected a sample interval within {:g} % of the mean {:.6g} {}, "
                   "found {:.6g} {} after the row at line {}",
                   record.time_column, 100.0 * kMaxIntervalDeviation, mean, unit,
                   record.time_s[worst] - record.time_s[worst - 1], unit, lines[worst - 1]));
}

// The reader would refuse what this lets through, so the writer refuses it first.
void CheckWritable(const std::filesystem::path& path, const MeasuredRecord& record) {
  const auto fail = [&path](std::string_view what) {
    throw MeasuredRecordError(
        fmt::format("{}: cannot write the measured record: {}", path.string(), what));
  };
  if (record.values.size() != record.columns.size()) {
    fail(fmt::format("{} column names but {} value columns", record.columns.size(),
                     record.values.size()));
  }
  for (std::size_t c = 0; c < record.columns.size(); ++c) {
    const std::string& name = record.columns[c];
    if (name.empty() || name == record.time_column ||
        name.find_first_of(",\r\n") != std::string::npos || Trim(name) != name) {
      fail(
          fmt::format("column name {:?} is empty, the time column's '{}', or holds a comma, line "
                      "break or surrounding blanks",
                      name, record.time_column));
    }
    if (std::find(record.columns.begin(), record.columns.begin() + c, name) !=
        record.columns.begin() + c) {
      fail(fmt::format("column name {:?} appears twice", name));
    }
    if (record.values[c].size() != record.time_s.size()) {
      fail(fmt::format("column '{}' has {} values, t has {}", name, record.values[c].size(),
                       record.time_s.size()));
    }
  }
}

}  // namespace

int MeasuredRecord::Column(const std::string& name) const {
  const auto it = std::find(columns.begin(), columns.end(), name);
  return it == columns.end() ? -1 : static_cast<int>(it - columns.begin());
}

double MeasuredRecord::SampleInterval() const {
  // 0 for fewer than two samples, which ReadMeasuredCsv never returns.
  if (time_s.size() < 2) return 0.0;
  return (time_s.back() - time_s.front()) / static_cast<double>(time_s.size() - 1);
}

MeasuredRecord ReadMeasuredCsv(const std::filesystem::path& path, const std::string& time_column,
                               const std::string& time_unit) {
  MeasuredRecord record;
  record.source = path.string();
  record.time_column = time_column;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw MeasuredRecordError(fmt::format("{}: cannot open the measured record: {}", record.source,
                                          std::strerror(errno)));
  }
  std::string text;
  std::vector<std::string_view> fields;
  std::vector<std::size_t> row_lines;  // for messages about intervals, found after reading
  std::size_t header_line = 0;
  for (std::size_t line = 1; std::getline(in, text); ++line) {
    std::string_view content = text;
    if (line == 1 && content.starts_with(kUtf8Bom)) content.remove_prefix(kUtf8Bom.size());
    if (content.ends_with('\r')) content.remove_suffix(1);
    const std::string_view trimmed = Trim(content);
    if (trimmed.empty() || trimmed.front() == '#') continue;
    Split(content, &fields);
    if (header_line == 0) {
      header_line = line;
      ReadHeader(fields, line, time_unit, &record);
    } else {
      ReadRow(fields, line, time_unit, &record);
      row_lines.push_back(line);
    }
  }
  if (in.bad()) {
    throw MeasuredRecordError(fmt::format("{}: cannot read the measured record", record.source));
  }
  if (header_line == 0) {
    throw MeasuredRecordError(fmt::format(
        "{}: expected a header row starting with '{}', found no lines but comments and blanks",
        record.source, time_column));
  }
  if (record.time_s.size() < 2) {
    Fail(record.source, header_line,
         fmt::format("expected at least 2 rows of samples below the header, found {}",
                     record.time_s.size()));
  }
  CheckEvenSampling(record, row_lines, time_unit);
  return record;
}

void WriteMeasuredCsv(const std::filesystem::path& path, const MeasuredRecord& record) {
  CheckWritable(path, record);
  if (record.time_column.empty() ||
      record.time_column.find_first_of(",\r\n") != std::string::npos ||
      Trim(record.time_column) != record.time_column) {
    throw MeasuredRecordError(
        fmt::format("{}: cannot write the measured record: time column name "
                    "{:?} is empty or holds a comma, line break or blanks",
                    path.string(), record.time_column));
  }
  std::string out = record.time_column;
  for (const std::string& name : record.columns) out += "," + name;
  out += '\n';
  for (std::size_t row = 0; row < record.time_s.size(); ++row) {
    fmt::format_to(std::back_inserter(out), "{:.17g}", record.time_s[row]);
    for (const std::vector<double>& column : record.values) {
      fmt::format_to(std::back_inserter(out), ",{:.17g}", column[row]);
    }
    out += '\n';
  }
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file) {
    throw MeasuredRecordError(
        fmt::format("{}: cannot open for writing: {}", path.string(), std::strerror(errno)));
  }
  file.write(out.data(), static_cast<std::streamsize>(out.size()));
  file.close();
  if (!file) throw MeasuredRecordError(fmt::format("{}: cannot write", path.string()));
}

}  // namespace ambdrop
