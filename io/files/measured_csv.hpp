#pragma once
// A measured record as CSV: a header row, the time column first (`t` unless the [measurement]
// table names another: io/files/measured_record_si.hpp), then one column per channel; one row per
// sample. This reader takes the numbers as written; the conversion to SI comes after it. Read
// strictly: every problem is a MeasuredRecordError naming the file, line and column (a missing or
// non-numeric value, a short or long row, a duplicate or empty header name, t not increasing, rows
// sampled unevenly).
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace ambdrop {

class MeasuredRecordError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct MeasuredRecord {
  std::string source;                       ///< the file, for messages
  std::string time_column = "t";            ///< the time column's header name
  std::vector<double> time_s;               ///< the time column (s once converted to SI)
  std::vector<std::string> columns;         ///< header names after t
  std::vector<std::vector<double>> values;  ///< values[c][row], one vector per column

  /// Index of a column by header name; -1 if there is none.
  int Column(const std::string& name) const;
  /// Mean sample interval (s).
  double SampleInterval() const;
};

/// Reads and checks a record. Lines starting with '#' and blank lines are skipped. The sample
/// interval may vary by at most 1 % around its mean (a logger's clock jitter).
/// `time_column` names the first column and `time_unit` its unit (for messages only).
MeasuredRecord ReadMeasuredCsv(const std::filesystem::path& path,
                               const std::string& time_column = "t",
                               const std::string& time_unit = "s");

/// Writes a record with 17 significant digits (bit-faithful), its time column first.
void WriteMeasuredCsv(const std::filesystem::path& path, const MeasuredRecord& record);

}  // namespace ambdrop
