// `ambdrop hil --controller lcm` refuses what a controller must not send, and says so: messages
// that do not decode, a current that is not finite or beyond the bound MakeHilLinks derives from
// the AMB's current_limit_A, each counted by kind in summary.json's "lcm" block and in
// RejectedControllerMessages (which makes hil's status not ok). Over memq:// (in process).
#include <gtest/gtest.h>

#include <ambdrop_lcm/amb_currents_t.hpp>
#include <chrono>
#include <cstdint>
#include <lcm/lcm-cpp.hpp>
#include <limits>
#include <string>
#include <thread>

#include "io/config/config_loader.hpp"
#include "io/files/json_writer.hpp"
#include "test_configs.hpp"
#include "tools/hil/hil_links.hpp"

namespace ambdrop::hil_lcm_rejects_test {
namespace {

ambdrop_lcm::amb_currents_t Currents(std::int64_t sequence, double x_A) {
  ambdrop_lcm::amb_currents_t m{};
  m.sequence = sequence;
  m.amb_count = 2;
  m.current_x_A[0] = x_A;
  return m;
}

TEST(HilLcmRejects, EachKindIsCountedAndReported) {
  LoadedConfig config = LoadConfig(testing::ConfigPath("jarroux2019_industrial_pid.toml"));
  config.params.ambs[0].current_limit_A = 12.0;  // the bound: 10 x 12 A
  const Model model = BuildModel(config.params);
  HilLinks links = MakeHilLinks(config, model, "lcm:memq://", "");
  ASSERT_TRUE(links.lcm);
  lcm::LCM& bus = links.lcm->lcm();
  const std::string channel = links.lcm->options().currents_channel;

  const std::uint8_t garbage[] = {1, 2, 3, 4, 5};
  ASSERT_EQ(bus.publish(channel, garbage, sizeof garbage), 0);  // not an amb_currents_t
  auto nan = Currents(1, std::numeric_limits<double>::quiet_NaN());
  ASSERT_EQ(bus.publish(channel, &nan), 0);
  auto absurd = Currents(2, 1e300);  // finite, and no coil carries it
  ASSERT_EQ(bus.publish(channel, &absurd), 0);
  auto beyond = Currents(3, -121.0);  // just beyond 10 x the limit
  ASSERT_EQ(bus.publish(channel, &beyond), 0);
  auto fine = Currents(4, 100.0);  // beyond the limit (the model clips it) but within the bound
  ASSERT_EQ(bus.publish(channel, &fine), 0);

  LcmEndpointCounters c{};
  for (int i = 0; i < 2000; ++i) {
    c = links.lcm->counters();
    if (c.currents_received + c.malformed_decode + c.malformed_non_finite +
            c.malformed_current_bound ==
        5) {
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  EXPECT_EQ(c.malformed_decode, 1u);
  EXPECT_EQ(c.malformed_non_finite, 1u);
  EXPECT_EQ(c.malformed_current_bound, 2u);
  EXPECT_EQ(c.currents_received, 1u);
  EXPECT_EQ(links.RejectedControllerMessages(), 4u);
  HilCurrents taken;
  ASSERT_TRUE(links.lcm->TryPopCurrents(&taken));
  EXPECT_EQ(taken.current_A[0][0], 100.0);
  EXPECT_FALSE(links.lcm->TryPopCurrents(&taken));

  links.Stop();
  JsonWriter json;
  json.BeginObject();
  links.WriteSummary(json);
  json.EndObject();
  const std::string text = json.str();
  for (const char* expected :
       {"\"lcm\": {", "\"malformed_decode\": 1", "\"malformed_non_finite\": 1",
        "\"malformed_current_bound\": 2", "\"currents_received\": 1"}) {
    EXPECT_NE(text.find(expected), std::string::npos) << expected << " not in " << text;
  }
}

}  // namespace
}  // namespace ambdrop::hil_lcm_rejects_test
