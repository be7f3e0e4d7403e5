// Jarroux 2016 (seed 001), Sec. 3, trends of a rigid rotor dropped at speed onto 4-DOF TDBs with
// the cross-coupled ribbon (Eq. (1)) and the quadratic bearing law (configs/jarroux2016_rigid),
// through the case `ambdrop validate` runs (tools/validation/seed001_cases.cpp):
//  - "increasing rotor to inner race clearance ... increase the TDB load": doubling the
//    clearance raises the peak rotor / inner-race load at both TDBs by at least 10 %;
//  - after the transient the rotor either rocks (RM) or whirls backward (BWM); friction
//    transfers spin energy into the backward whirl: with the rig's friction and ribbon damping
//    the journal rocks, with mu 0.35 and a tenth of the ribbon (support) damping it whirls
//    backward (a known failure).
// The whirl kind is RunSummary's classification (tools/fit/whirl_classifier.hpp) of the journal
// orbit over the second half of the time after the drop.
// A check marked as a known failure (an open issue explains it) makes its test skip with that
// reason after every other check has been asserted; AMBDROP_RUN_KNOWN_FAILURES=1 asserts it too.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "test_configs.hpp"
#include "tools/validation/offline_drop.hpp"
#include "tools/validation/validation_cases.hpp"
#include "validation_asserts.hpp"

namespace ambdrop::seed001_validation_test {
namespace {

using Seed001 = testing::ValidationCaseTest<&Seed001Trends>;

TEST_F(Seed001, DoublingTheClearanceRaisesThePeakTdbLoad) {
  testing::AssertChecks(About("peak load, clearance doubled"), 2);
}

TEST_F(Seed001, HighFrictionAndLowSupportDampingTurnRockingIntoBackwardWhirl) {
  testing::AssertChecks(About("motion"), 4);
}

// Not a validate check: the paper's two outcomes, over the friction range of its study, with the
// rig's (G2.5) unbalance. Sec. 3: "after transient motions ... two types of motion can appear".
TEST_F(Seed001, AfterTheTransientTheRotorRocksOrWhirlsBackward) {
  for (const char* mu : {"0.2", "0.35", "0.5"}) {
    const OfflineDrop d = RunOfflineDrop(testing::ConfigPath("jarroux2016_rigid.toml"),
                                         {std::string("tdb.de.friction.coefficient=") + mu,
                                          std::string("tdb.nde.friction.coefficient=") + mu});
    EXPECT_TRUE(d.ok) << "mu " << mu << ": " << d.failure_message;
    ASSERT_EQ(d.whirl.size(), d.tdbs.size());
    for (std::size_t i = 0; i < d.tdbs.size(); ++i) {
      SCOPED_TRACE(d.tdbs[i].name + " mu " + mu);
      std::printf("mu %-5s %-3s peak rotor/race %8.0f N  %-14s f/spin %+7.3f (%+.1f turns)\n", mu,
                  d.tdbs[i].name.c_str(), d.tdbs[i].normal_N, WhirlName(d.whirl[i].kind),
                  d.whirl[i].frequency_ratio, d.whirl[i].revolutions);
      EXPECT_TRUE(d.whirl[i].kind == WhirlKind::kRocking ||
                  d.whirl[i].kind == WhirlKind::kBackwardWhirl)
          << WhirlName(d.whirl[i].kind);
    }
  }
}

}  // namespace
}  // namespace ambdrop::seed001_validation_test
