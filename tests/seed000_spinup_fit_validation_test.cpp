// Issue 6, published summary numbers: seed 000's Table 3 measured spin-up times after a drop at
// 6500 rpm (DE 0.11 s, NDE 0.129 s). ambdrop's rig gives DE 0.105 s and NDE 0.121 s; which
// single parameter change explains the difference? Every candidate is fitted and printed (the
// README's table). Both of ambdrop's times are short, so a change on one TDB can only fix that
// TDB: each TDB's own drag torque must bring its time within 1 %. The best single change must
// halve the RMS error and bring both times within 3 %.
#include <gtest/gtest.h>

#include <cstdio>

#include "test_configs.hpp"
#include "tools/fit/spinup_fit.hpp"

namespace ambdrop::seed000_spinup_fit_validation_test {
namespace {

TEST(Seed000SpinUpFit, OneParameterExplainsTheMeasuredSpinUpTimes) {
  const ModelParams rig =
      testing::LoadTestConfig("jarroux2019_industrial.toml", {"simulation.duration_s=0.45"});
  const std::map<std::string, double> measured = {{"de", 0.11}, {"nde", 0.129}};
  const std::vector<SpinUpCandidate> candidates = ExplainSpinUpTimes(rig, measured);
  ASSERT_FALSE(candidates.empty());
  std::printf("| candidate | declared | fitted | DE (s) | NDE (s) | RMS error |\n");
  for (const SpinUpCandidate& c : candidates) {
    std::printf("| %s | %.4g | %.4g | %.4f | %.4f | %.1f %% -> %.2f %% |\n", c.name.c_str(),
                c.declared, c.fitted, c.times_s.at("de"), c.times_s.at("nde"), 100 * c.rms_before,
                100 * c.rms_after);
  }
  const SpinUpCandidate& best = candidates.front();
  EXPECT_GE(best.rms_before, 2.0 * best.rms_after) << best.name;
  EXPECT_NEAR(best.times_s.at("de"), 0.11, 0.03 * 0.11) << best.name;
  EXPECT_NEAR(best.times_s.at("nde"), 0.129, 0.03 * 0.129) << best.name;
  for (const SpinUpCandidate& c : candidates) {
    for (const auto& [tdb, target] : measured) {
      if (c.name == "tdb_drag_torque:" + tdb) {
        EXPECT_NEAR(c.times_s.at(tdb), target, 0.01 * target) << c.name;
      }
    }
  }
}

}  // namespace
}  // namespace ambdrop::seed000_spinup_fit_validation_test
