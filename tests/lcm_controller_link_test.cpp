// The LCM adapter of `ambdrop hil --controller lcm --trigger lcm`: trigger_t messages become the
// power events the session applies (full failure, one AMB's axis, restore), currents arrive in
// order with their values, and lock step waits for the answer to each sample sent. Over memq://
// (in process, no network).
#include <gtest/gtest.h>

#include <ambdrop_lcm/amb_currents_t.hpp>
#include <ambdrop_lcm/trigger_t.hpp>
#include <chrono>
#include <lcm/lcm-cpp.hpp>
#include <thread>

#include "io/lcm/lcm_transport.hpp"
#include "tools/hil/lcm_controller_link.hpp"

namespace ambdrop {
namespace {

template <typename F>
bool WaitFor(F done) {
  for (int i = 0; i < 2000; ++i) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return false;
}

ambdrop_lcm::trigger_t Trigger(bool power_on, std::int8_t ambs, std::int8_t axes) {
  ambdrop_lcm::trigger_t t{};
  t.power_on = power_on;
  t.amb_mask = ambs;
  t.axis_mask = axes;
  return t;
}

TEST(LcmControllerLink, TriggerMessagesBecomePowerEvents) {
  LcmEndpointOptions options;
  options.url = "memq://";
  LcmEndpoint endpoint(options);
  endpoint.Start();
  LcmControllerLink link(&endpoint, 2);
  const ambdrop_lcm::trigger_t sent[] = {
      Trigger(false, 0b10, ambdrop_lcm::trigger_t::AXIS_Y),  // AMB 1 loses its y coils
      Trigger(true, 0b10, ambdrop_lcm::trigger_t::AXIS_Y),   // and gets them back
      Trigger(false, ambdrop_lcm::trigger_t::ALL_AMBS, ambdrop_lcm::trigger_t::ALL_AXES)};
  for (const auto& t : sent) ASSERT_EQ(endpoint.lcm().publish(options.trigger_channel, &t), 0);
  std::vector<PowerEvent> got;
  ASSERT_TRUE(WaitFor([&] {
    PowerEvent e;
    while (link.Poll(0.0, &e)) got.push_back(e);
    return got.size() == 3;
  }));
  EXPECT_FALSE(got[0].restore);
  EXPECT_EQ(got[0].amb_mask, 0b10u);
  EXPECT_FALSE(got[0].axis_x);
  EXPECT_TRUE(got[0].axis_y);
  EXPECT_FALSE(got[0].motor);  // a partial failure leaves the drive on
  EXPECT_TRUE(got[1].restore);
  EXPECT_FALSE(got[2].restore);
  EXPECT_TRUE(got[2].axis_x && got[2].axis_y);
  EXPECT_TRUE(got[2].motor);  // everything: the drive too
  endpoint.Stop();
}

TEST(LcmControllerLink, LockStepWaitsForTheAnswerToTheLastSample) {
  LcmEndpointOptions options;
  options.url = "memq://";
  LcmEndpoint endpoint(options);
  endpoint.Start();
  LcmControllerLink link(&endpoint, 2);
  EXPECT_TRUE(link.AwaitAnswer(std::chrono::milliseconds(1)));  // nothing sent: nothing due
  link.SendSensors(SensorReadings{}, 0, 0.0);
  // No controller answers: the wait times out.
  EXPECT_FALSE(link.AwaitAnswer(std::chrono::milliseconds(20)));
  ambdrop_lcm::amb_currents_t answer{};
  answer.amb_count = 2;
  answer.sequence = 1;
  answer.current_x_A[0] = 0.25;
  answer.current_y_A[1] = -1.5;
  const auto now_ns = [] {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
  };
  const std::int64_t before_ns = now_ns();
  ASSERT_EQ(endpoint.lcm().publish(options.currents_channel, &answer), 0);
  EXPECT_TRUE(link.AwaitAnswer(std::chrono::seconds(2)));
  const std::int64_t after_ns = now_ns();
  CurrentsMessage m;
  ASSERT_TRUE(link.PollCurrents(&m));
  // Its arrival on the monotonic clock the CAN link stamps with (a record wrote 0 here).
  EXPECT_GE(m.receive_ns, before_ns);
  EXPECT_LE(m.receive_ns, after_ns);
  EXPECT_EQ(m.current_A[0][0], 0.25);
  EXPECT_EQ(m.current_A[1][1], -1.5);
  EXPECT_EQ(m.sequence, 1u);
  EXPECT_TRUE(link.AwaitAnswer(std::chrono::milliseconds(1)));  // answered already
  endpoint.Stop();
}

}  // namespace
}  // namespace ambdrop
