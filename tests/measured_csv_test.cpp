// Measured records as CSV: written and read back bit for bit, and every malformed file a
// MeasuredRecordError naming the file, line and column.
#include "io/files/measured_csv.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

namespace ambdrop::measured_csv_test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::StartsWith;

class MeasuredCsv : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string test = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    // Parameterised tests are named "Test/Case": one directory, not two.
    std::replace(test.begin(), test.end(), '/', '_');
    dir_ = fs::temp_directory_path() /
           ("ambdrop_measured_csv_" + std::to_string(::getpid()) + "_" + test);
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// Writes `text` byte for byte to a file in the test's directory.
  fs::path File(const std::string& text, const std::string& name = "record.csv") const {
    const fs::path path = dir_ / name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }

  /// The message of the MeasuredRecordError reading `text` throws.
  std::string ErrorOf(const std::string& text) const {
    try {
      ReadMeasuredCsv(File(text));
    } catch (const MeasuredRecordError& error) {
      return error.what();
    }
    ADD_FAILURE() << "read without a MeasuredRecordError:\n" << text;
    return {};
  }

  fs::path dir_;
};

std::uint64_t Bits(double value) {
  return std::bit_cast<std::uint64_t>(value);
}

TEST_F(MeasuredCsv, RoundTripIsBitExact) {
  MeasuredRecord record;
  for (int i = 0; i < 5; ++i) record.time_s.push_back(0.2 + i * 5e-5);
  record.columns = {"x_de", "i_de_y"};
  record.values = {
      {0.1, 1e-300, -0.0, std::numeric_limits<double>::denorm_min(), 1.0 / 3.0},
      {-2.5e-7, std::numeric_limits<double>::max(), std::numeric_limits<double>::min(), 0.0,
       -123456.789e10},
  };
  const fs::path path = dir_ / "round_trip.csv";
  WriteMeasuredCsv(path, record);
  const MeasuredRecord back = ReadMeasuredCsv(path);

  EXPECT_EQ(back.source, path.string());
  EXPECT_EQ(back.columns, record.columns);
  ASSERT_EQ(back.time_s.size(), record.time_s.size());
  ASSERT_EQ(back.values.size(), record.values.size());
  for (std::size_t row = 0; row < record.time_s.size(); ++row) {
    EXPECT_EQ(Bits(back.time_s[row]), Bits(record.time_s[row])) << "row " << row;
    for (std::size_t c = 0; c < record.columns.size(); ++c) {
      ASSERT_EQ(back.values[c].size(), record.time_s.size());
      EXPECT_EQ(Bits(back.values[c][row]), Bits(record.values[c][row]))
          << record.columns[c] << " row " << row << ": " << back.values[c][row];
    }
  }
  EXPECT_EQ(back.Column("x_de"), 0);
  EXPECT_EQ(back.Column("i_de_y"), 1);
  EXPECT_EQ(back.Column("t"), -1);
  EXPECT_EQ(back.Column("y_de"), -1);
  EXPECT_NEAR(back.SampleInterval(), 5e-5, 1e-15);
}

TEST_F(MeasuredCsv, HeaderIsTFirstThenTheColumns) {
  MeasuredRecord record;
  record.time_s = {0.0, 0.5};
  record.columns = {"a"};
  record.values = {{1.0, -0.0}};
  const fs::path path = dir_ / "small.csv";
  WriteMeasuredCsv(path, record);
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, "t,a\n0,1\n0.5,-0\n");
}

TEST_F(MeasuredCsv, CommentsBlanksAndCrlfAreAccepted) {
  const MeasuredRecord r = ReadMeasuredCsv(
      File("# logger v2, 20 kHz\r\n\r\nt, x_de ,y_de\r\n# a note mid-record\r\n0,1,-1\r\n"
           "   \r\n0.001,+2,2e-3\r\n0.002,3.5,.5\r\n"));
  EXPECT_EQ(r.columns, (std::vector<std::string>{"x_de", "y_de"}));
  EXPECT_EQ(r.time_s, (std::vector<double>{0.0, 0.001, 0.002}));
  EXPECT_EQ(r.values.at(0), (std::vector<double>{1.0, 2.0, 3.5}));
  EXPECT_EQ(r.values.at(1), (std::vector<double>{-1.0, 2e-3, 0.5}));
}

TEST_F(MeasuredCsv, LastLineNeedsNoNewlineAndBomIsSkipped) {
  const MeasuredRecord r = ReadMeasuredCsv(File("\xEF\xBB\xBFt,x\n0,1\n1,2"));
  EXPECT_EQ(r.time_s, (std::vector<double>{0.0, 1.0}));
  EXPECT_EQ(r.values.at(0), (std::vector<double>{1.0, 2.0}));
}

TEST_F(MeasuredCsv, SmallJitterIsAccepted) {
  // 0.5 % off the nominal 1 ms: within the 1 % a logger's clock may wander.
  const MeasuredRecord r = ReadMeasuredCsv(File("t,x\n0,0\n0.001,0\n0.002005,0\n0.003,0\n"));
  EXPECT_EQ(r.time_s.size(), 4U);
  EXPECT_DOUBLE_EQ(r.SampleInterval(), 0.001);
}

struct BadCase {
  std::string name;
  std::string text;
  int line;              ///< the line the message must name
  std::string expected;  ///< the message after "FILE:LINE: "
};

void PrintTo(const BadCase& c, std::ostream* out) {
  *out << c.name;
}

class MalformedCsv : public MeasuredCsv, public ::testing::WithParamInterface<BadCase> {};

TEST_P(MalformedCsv, ErrorNamesFileLineAndColumn) {
  const BadCase& c = GetParam();
  const std::string message = ErrorOf(c.text);
  const std::string location = (dir_ / "record.csv").string() + ":" + std::to_string(c.line) + ": ";
  EXPECT_THAT(message, StartsWith(location + c.expected));
}

std::vector<BadCase> BadCases() {
  return {
      {"NotANumber", "t,x_de\n0,abc\n0.001,1\n", 2,
       "column 'x_de': expected a number, found 'abc'"},
      {"TrailingGarbage", "t,x_de\n0,1\n0.001,1.5mm\n", 3,
       "column 'x_de': expected a number, found '1.5mm'"},
      {"DecimalComma", "t,x_de\n0;1\n", 2, "column 'x_de': expected a number, found the end"},
      {"EmptyValue", "t,x_de,y_de\n0,,1\n0.001,1,1\n", 2,
       "column 'x_de': expected a number, found an empty field"},
      {"BadTime", "t,x_de\n0,1\nnow,1\n", 3, "column 't': expected a number, found 'now'"},
      {"NotFinite", "t,x_de\n0,nan\n0.001,1\n", 2,
       "column 'x_de': expected a finite number, found 'nan'"},
      {"Infinite", "t,x_de\n0,1\n0.001,-inf\n", 3,
       "column 'x_de': expected a finite number, found '-inf'"},
      {"OutOfRange", "t,x_de\n0,1e400\n0.001,1\n", 2,
       "column 'x_de': expected a number within the range of a double, found '1e400'"},
      {"ShortRow", "t,x_de,y_de\n0,1,2\n0.001,1\n", 3,
       "column 'y_de': expected a number, found the end of the row (2 of 3 fields)"},
      {"LongRow", "t,x_de\n0,1\n0.001,1,7\n", 3,
       "column 3: expected the end of the row (the header has 2 columns), found '7'"},
      {"TrailingComma", "t,x_de\n0,1,\n", 2,
       "column 3: expected the end of the row (the header has 2 columns), found an empty field"},
      {"FirstHeaderNotT", "time_s,x_de\n0,1\n0.001,1\n", 1,
       "header column 1: expected 't' (time, s), found 'time_s'"},
      {"EmptyHeaderName", "t,x_de,,y_de\n", 1,
       "header column 3: expected a column name, found an empty field"},
      {"DuplicateHeaderName", "t,x_de,y_de,x_de\n", 1,
       "header column 4: expected a name no other column has, found 'x_de' (column 2 has it)"},
      {"SecondT", "t,t\n", 1, "header column 2: expected a name no other column has, found 't'"},
      {"TimeRepeats", "t,x\n0,1\n0.001,1\n0.001,1\n", 4,
       "column 't': expected a time after the previous row's 0.001 s, found '0.001'"},
      {"TimeGoesBack", "t,x\n0,1\n0.001,1\n0.0005,1\n", 4,
       "column 't': expected a time after the previous row's 0.001 s, found '0.0005'"},
      {"DroppedSample", "t,x\n0,1\n0.001,1\n0.002,1\n0.004,1\n0.005,1\n0.006,1\n0.007,1\n", 5,
       "column 't': expected a sample interval within 1 % of the mean 0.00116667 s, found 0.002 s "
       "after the row at line 4"},
      {"OneRow", "# one sample only\nt,x\n0,1\n", 2,
       "expected at least 2 rows of samples below the header, found 1"},
      {"LinesCountCommentsAndCrlf", "# header follows\r\n\r\nt,x\r\n# note\r\n0,1\r\n0.001,?\r\n",
       6, "column 'x': expected a number, found '?'"},
  };
}

INSTANTIATE_TEST_SUITE_P(Cases, MalformedCsv, ::testing::ValuesIn(BadCases()),
                         [](const ::testing::TestParamInfo<BadCase>& info) {
                           return info.param.name;
                         });

TEST_F(MeasuredCsv, EmptyFileNamesTheFile) {
  const std::string message = ErrorOf("# nothing but a comment\n\n");
  EXPECT_THAT(message, StartsWith((dir_ / "record.csv").string() + ": expected a header row"));
}

TEST_F(MeasuredCsv, MissingFileNamesThePath) {
  try {
    ReadMeasuredCsv(dir_ / "absent.csv");
    ADD_FAILURE() << "no MeasuredRecordError";
  } catch (const MeasuredRecordError& error) {
    EXPECT_THAT(error.what(), HasSubstr((dir_ / "absent.csv").string() + ": cannot open"));
  }
}

TEST_F(MeasuredCsv, WriterRefusesWhatTheReaderWouldRefuse) {
  MeasuredRecord record;
  record.time_s = {0.0, 1.0};
  record.columns = {"x"};
  record.values = {{1.0}};
  EXPECT_THROW(WriteMeasuredCsv(dir_ / "short.csv", record), MeasuredRecordError);
  record.values = {{1.0, 2.0}};
  record.columns = {"x,y"};
  EXPECT_THROW(WriteMeasuredCsv(dir_ / "comma.csv", record), MeasuredRecordError);
  record.columns = {"t"};
  EXPECT_THROW(WriteMeasuredCsv(dir_ / "time.csv", record), MeasuredRecordError);
  record.columns = {"x", "x"};
  record.values = {{1.0, 2.0}, {3.0, 4.0}};
  EXPECT_THROW(WriteMeasuredCsv(dir_ / "twice.csv", record), MeasuredRecordError);
}

}  // namespace
}  // namespace ambdrop::measured_csv_test
