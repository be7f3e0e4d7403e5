// The [measurement] table: read as written (names resolved to the model's indices), and every
// mistake a ConfigError naming the file, line, key and what was expected.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "io/config/config_loader.hpp"
#include "test_configs.hpp"

namespace ambdrop::config_measurement_test {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

constexpr char kSource[] = "measurement.toml";

std::string Rig() {
  return "base = \"" + testing::ConfigPath("jarroux2019_industrial_pid.toml") + "\"\n";
}

/// A valid table, one line per key so that a case can change one line.
constexpr std::string_view kValid = R"([measurement]
sample_rate_Hz = 20000.0
trigger_time_s = 0.2
[[measurement.channel]]
column = "x_nde"
quantity = "displacement"
sensor = "nde"
axis = "x"
[[measurement.channel]]
column = "i_de_y"
quantity = "current"
amb = "de"
axis = "y"
[[measurement.channel]]
column = "f_de"
quantity = "tdb_normal_force"
tdb = "de"
[[measurement.channel]]
column = "w_nde"
quantity = "tdb_speed"
tdb = "nde"
[[measurement.channel]]
column = "omega"
quantity = "rotor_speed"
)";

/// kValid with the first occurrence of `from` replaced by `to`.
std::string Valid(std::string_view from, std::string_view to) {
  std::string text = Rig() + std::string(kValid);
  const std::size_t pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << "not in the config: " << from;
  if (pos != std::string::npos) text.replace(pos, from.size(), to);
  return text;
}

int LineOf(const std::string& text, std::string_view marker) {
  const auto pos = text.find(marker);
  EXPECT_NE(pos, std::string::npos) << "marker not in the config: " << marker;
  if (pos == std::string::npos) return -1;
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + pos, '\n'));
}

std::string ErrorOf(const std::string& text, const std::vector<std::string>& overrides = {}) {
  try {
    LoadConfigFromString(text, kSource, overrides);
  } catch (const ConfigError& error) {
    return error.what();
  }
  ADD_FAILURE() << "loaded without a ConfigError";
  return {};
}

TEST(ConfigMeasurement, ReadsChannelsWithTheModelsIndices) {
  const LoadedConfig c = LoadConfigFromString(Rig() + std::string(kValid), kSource);
  ASSERT_TRUE(c.measurement.has_value());
  const MeasurementParams& m = *c.measurement;
  EXPECT_EQ(m.sample_rate_Hz, 20000.0);
  EXPECT_EQ(m.trigger_time_s, 0.2);
  EXPECT_FALSE(m.detect_trigger);
  ASSERT_EQ(m.channels.size(), 5U);

  EXPECT_EQ(m.channels[0].column, "x_nde");
  EXPECT_EQ(m.channels[0].quantity, MeasuredQuantity::kDisplacement);
  EXPECT_EQ(c.params.sensors.at(m.channels[0].index).name, "nde");
  EXPECT_EQ(m.channels[0].axis, 0);

  EXPECT_EQ(m.channels[1].quantity, MeasuredQuantity::kCurrent);
  EXPECT_EQ(c.params.ambs.at(m.channels[1].index).name, "de");
  EXPECT_EQ(m.channels[1].axis, 1);

  EXPECT_EQ(m.channels[2].quantity, MeasuredQuantity::kTdbNormalForce);
  EXPECT_EQ(c.params.tdbs.at(m.channels[2].index).name, "de");
  EXPECT_EQ(m.channels[2].axis, -1);

  EXPECT_EQ(m.channels[3].quantity, MeasuredQuantity::kTdbSpeed);
  EXPECT_EQ(c.params.tdbs.at(m.channels[3].index).name, "nde");

  EXPECT_EQ(m.channels[4].quantity, MeasuredQuantity::kRotorSpeed);
  EXPECT_EQ(m.channels[4].index, -1);
  EXPECT_EQ(m.channels[4].axis, -1);

  EXPECT_EQ(m.channels[0].Describe(c.params), "displacement nde x");
  EXPECT_EQ(m.channels[1].Describe(c.params), "current de y");
  EXPECT_EQ(m.channels[2].Describe(c.params), "tdb_normal_force de");
  EXPECT_EQ(m.channels[3].Describe(c.params), "tdb_speed nde");
  EXPECT_EQ(m.channels[4].Describe(c.params), "rotor_speed");
}

TEST(ConfigMeasurement, ReadsUnitsWindowsAndTheTimeColumn) {
  const std::string text = Valid("trigger_time_s = 0.2",
                                 "trigger_time_s = 0.2\ntime_column = "
                                 "\"time_ms\"\ntime_unit = \"ms\"");
  std::string more = text;
  more.replace(more.find("axis = \"x\""), 10,
               "axis = \"x\"\nunit = \"um\"\nwindow = "
               "\"after_trigger\"\nfrom_s = 0.001\nto_s = 0.05");
  more.replace(more.find("axis = \"y\""), 10, "axis = \"y\"\nscale = 2.5e-3");
  more.replace(more.find("quantity = \"rotor_speed\""), 24,
               "quantity = \"rotor_speed\"\nunit = \"rpm\"");
  const LoadedConfig c = LoadConfigFromString(more, kSource);
  const MeasurementParams& m = *c.measurement;
  EXPECT_EQ(m.time_column, "time_ms");
  EXPECT_EQ(m.time_scale_s, 1e-3);
  EXPECT_EQ(m.channels[0].scale, 1e-6);
  EXPECT_EQ(m.channels[0].unit, "um");
  EXPECT_EQ(m.channels[0].window, ChannelWindow::kAfterTrigger);
  EXPECT_EQ(m.channels[0].from_s, 0.001);
  EXPECT_EQ(m.channels[0].to_s, 0.05);
  EXPECT_TRUE(m.channels[0].InWindow(0.2011, 0.2));
  EXPECT_FALSE(m.channels[0].InWindow(0.2005, 0.2));
  EXPECT_FALSE(m.channels[0].InWindow(0.25, 0.2));
  EXPECT_EQ(m.channels[1].scale, 2.5e-3);
  EXPECT_TRUE(m.channels[1].unit.empty());
  EXPECT_NEAR(m.channels[4].scale, 2.0 * 3.141592653589793 / 60.0, 1e-15);
  // SI and the whole record by default.
  EXPECT_EQ(m.channels[2].scale, 1.0);
  EXPECT_FALSE(m.channels[2].Windowed());
  const LoadedConfig plain = LoadConfigFromString(Rig() + std::string(kValid), kSource);
  EXPECT_EQ(plain.measurement->time_column, "t");
  EXPECT_EQ(plain.measurement->time_scale_s, 1.0);
}

TEST(ConfigMeasurement, DetectedTriggerHasNoTime) {
  const LoadedConfig c =
      LoadConfigFromString(Valid("trigger_time_s = 0.2", "trigger = \"detect\""), kSource);
  ASSERT_TRUE(c.measurement.has_value());
  EXPECT_TRUE(c.measurement->detect_trigger);
  EXPECT_FALSE(c.measurement->trigger_time_s.has_value());
}

TEST(ConfigMeasurement, AbsentTableIsEmpty) {
  EXPECT_FALSE(LoadConfigFromString(Rig(), kSource).measurement.has_value());
}

TEST(ConfigMeasurement, OverridesReachTheTable) {
  const LoadedConfig c = LoadConfigFromString(Rig() + std::string(kValid), kSource,
                                              {"measurement.channel[0].sensor=de"});
  EXPECT_EQ(c.params.sensors.at(c.measurement->channels[0].index).name, "de");
  EXPECT_THAT(ErrorOf(Rig() + std::string(kValid), {"measurement.sample_rate_Hz=0"}),
              HasSubstr("--set measurement.sample_rate_Hz=0: key 'measurement.sample_rate_Hz': "
                        "expected a positive number (Hz), found 0"));
}

TEST(ConfigMeasurement, FromRecordDrivesWithCoilCurrentsOnly) {
  const std::string text =
      Valid("trigger_time_s = 0.2", "trigger_time_s = 0.2\npower_loss = \"from_record\"");
  const LoadedConfig magnet =
      LoadConfigFromString(text, kSource, {"amb.de.bias_source=permanent_magnet"});
  ASSERT_TRUE(magnet.measurement);
  EXPECT_EQ(magnet.measurement->power_loss, PowerLossSource::kFromRecord);
  for (const MeasurementChannel& ch : magnet.measurement->channels) {
    EXPECT_EQ(magnet.measurement->Drives(ch), ch.quantity == MeasuredQuantity::kCurrent)
        << ch.column;
  }
  const LoadedConfig decaying =
      LoadConfigFromString(text, kSource, {"amb.de.flux_decay.enabled=true"});
  EXPECT_EQ(decaying.measurement->power_loss, PowerLossSource::kFromRecord);
  // A controller's command keeps answering the falling rotor: it never drives after the cut.
  std::string commands = text;
  commands.replace(commands.find("quantity = \"current\""), 20,
                   "quantity = \"controller_command\"");
  EXPECT_THAT(ErrorOf(commands), HasSubstr("at least one channel with quantity = \"current\""));
  // The seed rig's AMBs are of the equivalent law: stiffness and damping, no coil current.
  std::string equivalent = text;
  equivalent.replace(0, Rig().size(),
                     "base = \"" + testing::ConfigPath("jarroux2019_industrial.toml") + "\"\n");
  EXPECT_THAT(ErrorOf(equivalent), HasSubstr("its law \"equivalent\" takes no coil current"));
}

struct RuleCase {
  std::string name;
  std::string toml;
  std::string line_marker;  ///< text that starts on the line the error must point at
  std::string key;          ///< the dotted key in the message, quoted
  std::string expected;     ///< text that must follow the key
  std::string found = {};   ///< optional text after "found "
};

void PrintTo(const RuleCase& rule, std::ostream* out) {
  *out << rule.name;
}

class MeasurementRule : public ::testing::TestWithParam<RuleCase> {};

TEST_P(MeasurementRule, ErrorNamesFileLineKeyAndExpectation) {
  const RuleCase& rule = GetParam();
  const std::string message = ErrorOf(rule.toml);
  const std::string location =
      std::string(kSource) + ":" + std::to_string(LineOf(rule.toml, rule.line_marker)) + ":";
  EXPECT_THAT(message, StartsWith(location));
  EXPECT_THAT(message, HasSubstr("'" + rule.key + "'"));
  EXPECT_THAT(message, HasSubstr(rule.expected));
  if (!rule.found.empty()) {
    EXPECT_THAT(message, HasSubstr("found " + rule.found));
  }
}

std::vector<RuleCase> TableCases() {
  return {
      {"NotATable", Rig() + "measurement = 3\n", "measurement = 3", "measurement",
       "expected a table ([measurement])", "3"},
      {"UnknownKey", Valid("trigger_time_s = 0.2", "trigger_time_s = 0.2\nrate_Hz = 1"),
       "rate_Hz = 1", "measurement.rate_Hz",
       "(allowed here: sample_rate_Hz, trigger_time_s, trigger, time_column, time_unit, "
       "power_loss, trigger_state, channel)"},
      {"SampleRateMissing", Valid("sample_rate_Hz = 20000.0\n", ""), "[measurement]",
       "measurement.sample_rate_Hz",
       "missing key 'measurement.sample_rate_Hz': expected a "
       "positive number (Hz)"},
      {"SampleRateNotPositive", Valid("sample_rate_Hz = 20000.0", "sample_rate_Hz = -1.0"),
       "sample_rate_Hz", "measurement.sample_rate_Hz", "expected a positive number (Hz)", "-1"},
      {"SampleRateNotNumber", Valid("sample_rate_Hz = 20000.0", "sample_rate_Hz = \"fast\""),
       "sample_rate_Hz", "measurement.sample_rate_Hz", "expected a positive number (Hz)",
       "\"fast\""},
      {"TriggerTimeNegative", Valid("trigger_time_s = 0.2", "trigger_time_s = -0.1"),
       "trigger_time_s", "measurement.trigger_time_s", "expected a non-negative number (s)",
       "-0.1"},
      {"TriggerBoth", Valid("trigger_time_s = 0.2", "trigger_time_s = 0.2\ntrigger = \"detect\""),
       "trigger =", "measurement.trigger", "expected no trigger with trigger_time_s", "\"detect\""},
      {"TriggerNeither", Valid("trigger_time_s = 0.2\n", ""), "[measurement]",
       "measurement.trigger_time_s", "expected a non-negative number (s), or trigger = \"detect\""},
      {"TriggerUnknown", Valid("trigger_time_s = 0.2", "trigger = \"auto\""),
       "trigger =", "measurement.trigger", "expected one of \"detect\"", "\"auto\""},
      {"NoChannel", Rig() + "[measurement]\nsample_rate_Hz = 1e3\ntrigger_time_s = 0.1\n",
       "[measurement]", "measurement.channel", "expected at least one [[measurement.channel]]"},
      {"EmptyChannelArray",
       Rig() + "[measurement]\nsample_rate_Hz = 1e3\ntrigger_time_s = 0.1\nchannel = []\n",
       "channel = []", "measurement.channel", "expected at least one [[measurement.channel]]",
       "[]"},
      {"PowerLossUnknown", Valid("trigger_time_s = 0.2", "trigger_time_s = 0.2\npower_loss = 1"),
       "power_loss", "measurement.power_loss", "expected one of \"declared\", \"from_record\"",
       "1"},
      // The PID rig's electromagnet bias, without a declared decay.
      {"FromRecordNeedsTheBiasLaw",
       Valid("trigger_time_s = 0.2", "trigger_time_s = 0.2\npower_loss = \"from_record\""),
       "power_loss", "measurement.power_loss",
       "or amb.de.flux_decay enabled: with an electromagnet bias the record's control current "
       "('i_de_y') rides on a bias current that the record does not carry"},
      {"TriggerStateUnknown",
       Valid("trigger_time_s = 0.2", "trigger_time_s = 0.2\ntrigger_state = \"estimate\""),
       "trigger_state", "measurement.trigger_state", "expected one of \"model\", \"record\"",
       "\"estimate\""},
      {"ChannelNotTables",
       Rig() + "[measurement]\nsample_rate_Hz = 1e3\ntrigger_time_s = 0.1\nchannel = 3\n",
       "channel = 3", "measurement.channel", "expected an array of tables", "3"},
  };
}

std::vector<RuleCase> ChannelCases() {
  return {
      {"UnknownChannelKey", Valid("axis = \"x\"", "axis = \"x\"\ngain = 2"), "gain",
       "measurement.channel[0].gain",
       "(allowed here: column, quantity, sensor, amb, tdb, axis, unit, scale, window, from_s, "
       "to_s)"},
      {"ColumnMissing", Valid("column = \"x_nde\"\n", ""), "[[measurement.channel]]",
       "measurement.channel[0].column", "expected a string"},
      {"ColumnNotString", Valid("column = \"x_nde\"", "column = 3"), "column = 3",
       "measurement.channel[0].column", "expected a string", "3"},
      {"ColumnEmpty", Valid("column = \"x_nde\"", "column = \"\""), "column = \"\"",
       "measurement.channel[0].column", "expected a non-empty CSV column name", "\"\""},
      {"ColumnIsTime", Valid("column = \"x_nde\"", "column = \"t\""), "column = \"t\"",
       "measurement.channel[0].column", "expected a column other than \"t\"", "\"t\""},
      {"ColumnDuplicate", Valid("column = \"w_nde\"", "column = \"i_de_y\""),
       "column = \"i_de_y\"\nquantity = \"tdb_speed\"", "measurement.channel[3].column",
       "expected a column no other channel reads (measurement.channel[1] reads it)", "\"i_de_y\""},
      {"QuantityMissing", Valid("quantity = \"rotor_speed\"\n", ""),
       "[[measurement.channel]]\n"
       "column = \"omega\"",
       "measurement.channel[4].quantity",
       "missing key 'measurement.channel[4].quantity': expected one of \"displacement\", "
       "\"current\", \"controller_command\", \"tdb_normal_force\", \"tdb_support_force\", "
       "\"tdb_speed\", \"rotor_speed\""},
      {"QuantityUnknown", Valid("quantity = \"rotor_speed\"", "quantity = \"speed\""),
       "quantity = \"speed\"", "measurement.channel[4].quantity",
       "expected one of \"displacement\", \"current\"", "\"speed\""},
      {"SensorMissing", Valid("sensor = \"nde\"\n", ""), "[[measurement.channel]]",
       "measurement.channel[0].sensor",
       "expected the name of one of the rig's sensors (\"de\", \"nde\")"},
      {"SensorUnknown", Valid("sensor = \"nde\"", "sensor = \"middle\""), "sensor = \"middle\"",
       "measurement.channel[0].sensor",
       "expected the name of one of the rig's sensors (\"de\", \"nde\")", "\"middle\""},
      {"SensorNotString", Valid("sensor = \"nde\"", "sensor = 1"), "sensor = 1",
       "measurement.channel[0].sensor", "expected the name of one of the rig's sensors", "1"},
      {"AmbUnknown", Valid("amb = \"de\"", "amb = \"middle\""), "amb = \"middle\"",
       "measurement.channel[1].amb", "expected the name of one of the rig's AMBs (\"de\", \"nde\")",
       "\"middle\""},
      {"AmbMissing", Valid("amb = \"de\"\n", ""), "[[measurement.channel]]\ncolumn = \"i_de_y\"",
       "measurement.channel[1].amb", "missing key 'measurement.channel[1].amb'"},
      {"TdbUnknown", Valid("tdb = \"de\"", "tdb = \"middle\""), "tdb = \"middle\"",
       "measurement.channel[2].tdb", "expected the name of one of the rig's TDBs (\"de\", \"nde\")",
       "\"middle\""},
      {"TdbMissing", Valid("tdb = \"nde\"\n", ""), "[[measurement.channel]]\ncolumn = \"w_nde\"",
       "measurement.channel[3].tdb", "missing key 'measurement.channel[3].tdb'"},
      {"AxisMissing", Valid("axis = \"y\"\n", ""), "[[measurement.channel]]\ncolumn = \"i_de_y\"",
       "measurement.channel[1].axis", "expected one of \"x\", \"y\""},
      {"AxisUnknown", Valid("axis = \"x\"", "axis = \"z\""), "axis = \"z\"",
       "measurement.channel[0].axis", "expected one of \"x\", \"y\"", "\"z\""},
      {"AxisBoth", Valid("axis = \"x\"", "axis = \"both\""), "axis = \"both\"",
       "measurement.channel[0].axis", "expected one of \"x\", \"y\"", "\"both\""},
      // A key the quantity does not take: the message says which quantity takes it. The values
      // are unique in the text so that the marker finds their line.
      {"AmbOnDisplacement", Valid("sensor = \"nde\"", "amb = \"rear\""), "amb = \"rear\"",
       "measurement.channel[0].amb",
       "expected no amb for displacement (only current and controller_command take amb)",
       "\"rear\""},
      {"SensorOnCurrent", Valid("amb = \"de\"", "amb = \"de\"\nsensor = \"rear\""),
       "sensor = \"rear\"", "measurement.channel[1].sensor",
       "expected no sensor for current (only displacement takes sensor)", "\"rear\""},
      {"SensorOnTdbSpeed", Valid("tdb = \"nde\"", "sensor = \"rear\""), "sensor = \"rear\"",
       "measurement.channel[3].sensor",
       "expected no sensor for tdb_speed (only displacement takes sensor)"},
      {"TdbOnRotorSpeed",
       Valid("quantity = \"rotor_speed\"", "quantity = \"rotor_speed\"\ntdb = \"rear\""),
       "tdb = \"rear\"", "measurement.channel[4].tdb",
       "expected no tdb for rotor_speed (only tdb_normal_force, tdb_support_force and tdb_speed "
       "take tdb)"},
      {"TdbOnCurrent", Valid("amb = \"de\"", "amb = \"de\"\ntdb = \"rear\""), "tdb = \"rear\"",
       "measurement.channel[1].tdb",
       "expected no tdb for current (only tdb_normal_force, tdb_support_force and tdb_speed take "
       "tdb)"},
      {"AxisOnTdbForce", Valid("tdb = \"de\"", "tdb = \"de\"\naxis = \"left\""), "axis = \"left\"",
       "measurement.channel[2].axis",
       "expected no axis for tdb_normal_force (only displacement, current, controller_command and "
       "tdb_support_force take axis)",
       "\"left\""},
      {"AxisOnRotorSpeed",
       Valid("quantity = \"rotor_speed\"", "quantity = \"rotor_speed\"\naxis = \"left\""),
       "axis = \"left\"", "measurement.channel[4].axis",
       "expected no axis for rotor_speed (only displacement, current, controller_command and "
       "tdb_support_force take axis)"},
      // Units, windows and the time column.
      {"UnitOfAnotherDimension", Valid("axis = \"y\"", "axis = \"y\"\nunit = \"mm\""),
       "unit = \"mm\"", "measurement.channel[1].unit",
       "expected a unit of current for current (one of \"A\", \"mA\")",
       "\"mm\" (a unit of length)"},
      {"UnitUnknown",
       Valid("quantity = \"rotor_speed\"", "quantity = \"rotor_speed\"\nunit = \"rps\""),
       "unit = \"rps\"", "measurement.channel[4].unit",
       "expected a unit of speed for rotor_speed (one of \"rad/s\", \"rpm\", \"Hz\", \"rev/s\")",
       "\"rps\""},
      {"UnitAndScale", Valid("axis = \"x\"", "axis = \"x\"\nunit = \"um\"\nscale = 1e-6"),
       "scale = 1e-6", "measurement.channel[0].scale", "expected no scale with unit"},
      {"ScaleZero", Valid("axis = \"x\"", "axis = \"x\"\nscale = 0.0"), "scale = 0.0",
       "measurement.channel[0].scale", "expected a finite, non-zero number (m per record unit)",
       "0"},
      {"ScaleNotFinite", Valid("axis = \"x\"", "axis = \"x\"\nscale = inf"), "scale = inf",
       "measurement.channel[0].scale", "expected a finite, non-zero number (m per record unit)"},
      {"WindowUnknown", Valid("axis = \"x\"", "axis = \"x\"\nwindow = \"levitated\""),
       "window = \"levitated\"", "measurement.channel[0].window",
       "expected one of \"all\", \"before_trigger\", \"after_trigger\"", "\"levitated\""},
      {"WindowToBeforeFrom", Valid("axis = \"x\"", "axis = \"x\"\nfrom_s = 0.02\nto_s = 0.01"),
       "to_s = 0.01", "measurement.channel[0].to_s", "expected a time after from_s (0.02 s)",
       "0.01"},
      {"WindowEmptyAfterTrigger",
       Valid("axis = \"x\"", "axis = \"x\"\nwindow = \"after_trigger\"\nto_s = -0.01"),
       "to_s = -0.01", "measurement.channel[0].to_s",
       "expected a bound that leaves the window \"after_trigger\" some time"},
      {"TimeUnitUnknown",
       Valid("trigger_time_s = 0.2", "trigger_time_s = 0.2\ntime_unit = \"min\""), "time_unit",
       "measurement.time_unit", "expected one of \"s\", \"ms\", \"us\"", "\"min\""},
      {"ColumnIsNamedTime",
       Valid("trigger_time_s = 0.2", "trigger_time_s = 0.2\ntime_column = \"x_nde\""),
       "column = \"x_nde\"\nquantity", "measurement.channel[0].column",
       "expected a column other than \"x_nde\" (the record's time)"},
  };
}

std::vector<RuleCase> AllCases() {
  std::vector<RuleCase> cases = TableCases();
  for (RuleCase& c : ChannelCases()) cases.push_back(std::move(c));
  return cases;
}

INSTANTIATE_TEST_SUITE_P(Rules, MeasurementRule, ::testing::ValuesIn(AllCases()),
                         [](const ::testing::TestParamInfo<RuleCase>& info) {
                           return info.param.name;
                         });

}  // namespace
}  // namespace ambdrop::config_measurement_test
