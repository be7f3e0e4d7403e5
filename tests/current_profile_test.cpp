// Current profiles: the decimation that fits a recording into kMaxProfilePoints, and the link
// that drives a rig without a controller from its profiles.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "controller_if/controller/current_profile.hpp"
#include "controller_if/controller/profile_controller_link.hpp"
#include "malloc_guard.hpp"
#include "test_configs.hpp"

namespace ambdrop::current_profile_test {
namespace {

// The largest deviation of the kept points' interpolation from every sample of the series.
double InterpolationError(const CurrentSeries& s, const ProfileDecimation& d) {
  double worst = 0.0;
  for (int a = 0; a < s.ambs; ++a) {
    std::vector<CurrentSample> profile;
    for (std::size_t j : d.kept) {
      profile.push_back({s.time_s[j], s.current_A[j][a][0], s.current_A[j][a][1]});
    }
    for (std::size_t j = 0; j < s.time_s.size(); ++j) {
      const auto i = CurrentAt(profile, s.time_s[j]);
      worst = std::max(worst, std::abs(i[0] - s.current_A[j][a][0]));
      worst = std::max(worst, std::abs(i[1] - s.current_A[j][a][1]));
    }
  }
  return worst;
}

TEST(DecimateCurrents, KeepsExactlyTheKinksOfAPiecewiseLinearSeries) {
  // Two AMBs, kinks at different samples: x of AMB 0 at 250 and 700, y of AMB 1 at 400.
  CurrentSeries s;
  s.ambs = 2;
  for (int j = 0; j < 1000; ++j) {
    const double t = j * 1e-4;
    std::array<std::array<double, 2>, kMaxAmbs> i{};
    i[0][0] = j < 250 ? 0.01 * j : (j < 700 ? 2.5 - 0.02 * (j - 250) : -6.5);
    i[0][1] = 1.4;
    i[1][0] = -0.3 + 0.001 * j;
    i[1][1] = j < 400 ? 1.0 : 1.0 + 0.005 * (j - 400);
    s.time_s.push_back(t);
    s.current_A.push_back(i);
  }
  const ProfileDecimation d = DecimateCurrents(s, 1024);
  EXPECT_EQ(d.kept, (std::vector<std::size_t>{0, 250, 400, 700, 999}));
  EXPECT_LT(d.max_error_A, 1e-12);
  EXPECT_LT(InterpolationError(s, d), 1e-12);
}

TEST(DecimateCurrents, KeepsTheBudgetAndReportsTheErrorItLeaves) {
  // A levitating current with controller jitter: 5000 samples, no two alike.
  CurrentSeries s;
  s.ambs = 1;
  std::uint64_t lcg = 12345;
  for (int j = 0; j < 5000; ++j) {
    lcg = lcg * 6364136223846793005ULL + 1442695040888963407ULL;
    const double jitter = static_cast<double>(lcg >> 11) * 0x1.0p-53 - 0.5;
    const double t = j * 5e-5;
    s.time_s.push_back(t);
    s.current_A.push_back({});
    s.current_A.back()[0] = {0.2 * std::sin(2 * M_PI * 40 * t) + 0.05 * jitter,
                             1.4 + 0.05 * jitter};
  }
  double previous = INFINITY;
  for (std::size_t budget : {16u, 100u, 1024u}) {
    const ProfileDecimation d = DecimateCurrents(s, budget);
    ASSERT_EQ(d.kept.size(), budget);
    EXPECT_EQ(d.kept.front(), 0u);
    EXPECT_EQ(d.kept.back(), 4999u);
    EXPECT_TRUE(std::is_sorted(d.kept.begin(), d.kept.end()));
    // The reported error is the real one, and more points never make it worse.
    EXPECT_DOUBLE_EQ(d.max_error_A, InterpolationError(s, d)) << budget;
    EXPECT_LE(d.max_error_A, previous);
    previous = d.max_error_A;
  }
  // 1024 points follow the 40 Hz swing; what is left is the jitter (+-0.025 A).
  EXPECT_LT(previous, 0.05);
}

TEST(ProfileControllerLink, SendsTheProfileAtTheTimeOfTheLastSampleWithoutAllocating) {
  ModelParams params = testing::LoadTestConfig(
      "jarroux2019_industrial_pid.toml",
      {"controller.kind=\"none\"", "amb.de.current_profile=[[0.0, 0.0, 1.0], [0.01, 2.0, 3.0]]"});
  const Model model = BuildModel(params);
  ProfileControllerLink link(model);
  CurrentsMessage m;
  ASSERT_TRUE(link.PollCurrents(&m));
  EXPECT_EQ(m.current_A[0], (std::array<double, 2>{0.0, 1.0}));
  EXPECT_EQ(m.current_A[1], (std::array<double, 2>{0.0, 0.0}));  // no profile: none
  EXPECT_FALSE(link.PollCurrents(&m));
  SensorReadings readings{};
  testing::MallocGuard guard;
  for (int n = 1; n <= 4000; ++n) {
    link.SendSensors(readings, n, n * 5e-6);
    ASSERT_TRUE(link.PollCurrents(&m));
    EXPECT_DOUBLE_EQ(m.current_A[0][0], std::min(2.0, 2.0 * n * 5e-6 / 0.01));
    EXPECT_DOUBLE_EQ(m.current_A[0][1], std::min(3.0, 1.0 + 2.0 * n * 5e-6 / 0.01));
  }
  if (testing::MallocGuard::Available()) {
    EXPECT_EQ(guard.allocations(), 0);
  }
}

}  // namespace
}  // namespace ambdrop::current_profile_test
