// A declared model that cannot run the record is refused, not judged: its unreached samples
// would score a full range off, and its sensitivity to the step, measured from a run as broken,
// once widened the agreement limit past that residual ("no_effect_needed").
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "test_configs.hpp"
#include "tools/fit/fit_record.hpp"
#include "tools/fit/measured_record_maker.hpp"
#include "tools/fit/simulate_on_record.hpp"

namespace ambdrop::fit_declared_model_stops_test {
namespace {

constexpr const char* kRig = "jarroux2019_industrial_pid.toml";

TEST(FitDeclaredModelStops, AModelThatStopsAtItsFirstImpactIsRefusedWithWhereAndWhy) {
  const std::vector<std::string> timing = {"simulation.duration_s=0.25", "trigger.time_s=0.1"};
  const SyntheticMeasurement made =
      MakeMeasuredRecord(testing::LoadTestConfig(kRig, timing), MeasureOptions{});
  // Contacts too stiff for the step: the levitated time runs, the first impact does not.
  std::vector<std::string> stiff = timing;
  stiff.push_back("tdb.de.contact_law.bearing_stiffness_N_per_m=1e13");
  stiff.push_back("tdb.nde.contact_law.bearing_stiffness_N_per_m=1e13");
  const ConfigVariants declared = testing::LoadTestVariants(kRig, stiff);
  FitRecordOptions options;
  options.rules.threads = 2;
  try {
    const auto fit = FitRecord(declared, made.measurement, made.record, options);
    FAIL() << "fitted a model that stops early: " << fit->selection.verdict << " ("
           << fit->selection.reason << ")";
  } catch (const DeclaredModelStopped& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("does not run to the record's end"), std::string::npos) << what;
    EXPECT_NE(what.find("state after the failing step"), std::string::npos) << what;
  }
  // The same declared model without the stiff contacts runs and is judged.
  const auto fit =
      FitRecord(testing::LoadTestVariants(kRig, timing), made.measurement, made.record, options);
  EXPECT_EQ(fit->selection.verdict, "no_effect_needed") << fit->selection.reason;
}

}  // namespace
}  // namespace ambdrop::fit_declared_model_stops_test
