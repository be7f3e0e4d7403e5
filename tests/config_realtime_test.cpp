// The [realtime] table: defaults, values, and each rule's error with file, line and key.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "io/config/config_loader.hpp"
#include "test_configs.hpp"

namespace ambdrop::config_realtime_test {
namespace {

using ::testing::HasSubstr;

const std::string& kRigid = testing::kSmallRigidRotor;

using testing::ConfigErrorOf;

TEST(ConfigRealtime, DefaultsWithoutTheTable) {
  const RealtimeConfig r = LoadConfigFromString(kRigid, "test.toml").realtime;
  EXPECT_EQ(r.priority, 0);
  EXPECT_EQ(r.cpu, -1);
  EXPECT_EQ(r.spin_s, 0.0);
  EXPECT_FALSE(r.enforce);
}

TEST(ConfigRealtime, ValuesLoad) {
  const RealtimeConfig r = LoadConfigFromString(kRigid + R"(
[realtime]
priority = 80
cpu = 1
spin_s = 20e-6
enforce = true
)",
                                                "test.toml")
                               .realtime;
  EXPECT_EQ(r.priority, 80);
  EXPECT_EQ(r.cpu, 1);
  EXPECT_EQ(r.spin_s, 20e-6);
  EXPECT_TRUE(r.enforce);
}

TEST(ConfigRealtime, OverridesApply) {
  const RealtimeConfig r =
      LoadConfigFromString(kRigid, "test.toml", {"realtime.priority=50"}).realtime;
  EXPECT_EQ(r.priority, 50);
}

TEST(ConfigRealtime, Rules) {
  EXPECT_THAT(ConfigErrorOf(kRigid + "[realtime]\npriority = 100\n"),
              HasSubstr("test.toml:10: key 'realtime.priority'"));
  EXPECT_THAT(ConfigErrorOf(kRigid + "[realtime]\npriority = 1.5\n"),
              HasSubstr("key 'realtime.priority'"));
  EXPECT_THAT(ConfigErrorOf(kRigid + "[realtime]\ncpu = -2\n"),
              HasSubstr("test.toml:10: key 'realtime.cpu'"));
  EXPECT_THAT(ConfigErrorOf(kRigid + "[realtime]\nspin_s = -1e-6\n"),
              HasSubstr("test.toml:10: key 'realtime.spin_s'"));
  EXPECT_THAT(ConfigErrorOf(kRigid + "[realtime]\nspin_s = 0.5\n"),
              HasSubstr("key 'realtime.spin_s'"));
  EXPECT_THAT(ConfigErrorOf(kRigid + "[realtime]\nenforce = 1\n"),
              HasSubstr("test.toml:10: key 'realtime.enforce'"));
  EXPECT_THAT(ConfigErrorOf(kRigid + "[realtime]\nspin_us = 20\n"),
              HasSubstr("unknown key 'realtime.spin_us'"));
}

}  // namespace
}  // namespace ambdrop::config_realtime_test
