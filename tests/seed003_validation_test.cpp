// Seed 003 (double-decker catcher bearing, Sec. 2.4 and 3): the rotor dropped at 200 Hz onto
// DDCBs (ddcb_rigid.toml) and SDCBs (sdcb_rigid.toml), 0.2 s after the drop, through the case
// `ambdrop validate` runs (tools/validation/seed003_cases.cpp), each quantity the median over
// 8 unbalance phases at the drop (the paper's drop state is not given):
//  - the DDCB lowers the peak rotor / inner-race contact force by 10-35 % (paper: 15-27 %);
//  - the DDCB lowers the vibration amplitude by at least 20 % (paper: at least 28 %); amplitude
//    here is the RMS distance of the journal from its mean position from first contact on (a
//    known failure);
//  - the intermediate race spins up to a fraction (5-50 %) of the inner race's speed (paper's
//    experiment: 17 %).
// A check marked as a known failure (an open issue explains it) makes its test skip with that
// reason after every other check has been asserted; AMBDROP_RUN_KNOWN_FAILURES=1 asserts it too.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "rt_core/catcher_bearing_tdb.hpp"
#include "rt_core/model.hpp"
#include "test_configs.hpp"
#include "tools/validation/validation_cases.hpp"
#include "validation_asserts.hpp"

namespace ambdrop::seed003_validation_test {
namespace {

using Seed003 = testing::ValidationCaseTest<&Seed003DoubleDecker>;

TEST_F(Seed003, DoubleDeckerLowersThePeakContactForce) {
  testing::AssertChecks(About("peak contact force"), 1);
}

TEST_F(Seed003, IntermediateRaceTakesAFractionOfTheInnerRaceSpeed) {
  testing::AssertChecks(About("race speed"), 1);
  // The speed ratio is the DDCB's; the SDCB it is compared with must have no intermediate race,
  // or the comparison is between two double-deckers.
  for (const auto& [config, decks] : {std::pair{"ddcb_rigid.toml", 2}, {"sdcb_rigid.toml", 1}}) {
    const Model model = BuildModel(testing::LoadTestConfig(config));
    for (const auto& tdb : model.tdbs) {
      const auto* catcher = dynamic_cast<const CatcherBearingTdb*>(tdb.get());
      ASSERT_NE(catcher, nullptr) << config;
      EXPECT_EQ(catcher->intermediate_offset() >= 0, decks == 2) << config;
    }
  }
}

TEST_F(Seed003, DoubleDeckerLowersTheVibrationAmplitude) {
  testing::AssertChecks(About("vibration amplitude"), 1);
}

}  // namespace
}  // namespace ambdrop::seed003_validation_test
