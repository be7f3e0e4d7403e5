// The LCM adapter of `ambdrop hil --controller lcm --trigger lcm`: trigger_t messages become the
// power events the session applies (full failure, one AMB's axis, restore), currents arrive in
// order with their values, and lock step waits for the answer to each sample sent. Over memq://
// (in process, no network). And the run live on LCM: the states a subscriber sees, and the power
// events.
#include <gtest/gtest.h>

#include <algorithm>
#include <ambdrop_lcm/amb_currents_t.hpp>
#include <ambdrop_lcm/emulator_state_t.hpp>
#include <ambdrop_lcm/power_event_t.hpp>
#include <ambdrop_lcm/trigger_t.hpp>
#include <chrono>
#include <cmath>
#include <lcm/lcm-cpp.hpp>
#include <mutex>
#include <thread>
#include <vector>

#include "controller_if/controller/internal_controller_link.hpp"
#include "controller_if/loop/hil_session.hpp"
#include "controller_if/loop/periodic_loop.hpp"
#include "controller_if/loop/recorder_tee.hpp"
#include "controller_if/loop/rt_clock.hpp"
#include "io/lcm/lcm_transport.hpp"
#include "malloc_guard.hpp"
#include "test_configs.hpp"
#include "tools/hil/lcm_controller_link.hpp"
#include "tools/hil/lcm_live_state.hpp"

namespace ambdrop::lcm_controller_link_test {
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

// What the session hands a recorder at each output step, kept to compare with what went out.
struct StateCapture final : RunRecorder {
  struct Kept {
    State state;
    Observation observation;
  };
  std::vector<Kept> states;  // in step order; reserved, so capturing allocates nothing
  std::vector<RecordedPower> power;
  const Kept* At(std::int64_t step) const {
    const auto it =
        std::lower_bound(states.begin(), states.end(), step,
                         [](const Kept& k, std::int64_t s) { return k.state.step_index < s; });
    return it != states.end() && it->state.step_index == step ? &*it : nullptr;
  }
  void OnStart(const RecordedStart&) noexcept override {}
  void OnInput(const RecordedInput&) noexcept override {}
  void OnPower(const RecordedPower& p) noexcept override { power.push_back(p); }
  void OnSensors(const RecordedSensors&) noexcept override {}
  void OnState(const State& state, const Observation& o) noexcept override {
    states.push_back({state, o});
  }
};

// The subscriber's side: handlers run on the endpoint's receive thread.
struct LiveSubscriber {
  std::mutex mutex;
  std::vector<ambdrop_lcm::emulator_state_t> states;
  std::vector<ambdrop_lcm::power_event_t> power;
  void OnState(const lcm::ReceiveBuffer*, const std::string&,
               const ambdrop_lcm::emulator_state_t* m) {
    std::lock_guard<std::mutex> lock(mutex);
    states.push_back(*m);
  }
  void OnPower(const lcm::ReceiveBuffer*, const std::string&, const ambdrop_lcm::power_event_t* m) {
    std::lock_guard<std::mutex> lock(mutex);
    power.push_back(*m);
  }
};

// `ambdrop hil --controller lcm --state-interval-s`: a monitor on AMBDROP_STATE sees the run
// every interval, each state exactly as the session had it (the generalized coordinates, spin
// and TDB forces bit for bit), and on AMBDROP_POWER the scheduled power failure (a source that is
// not LCM) at the step it applied, with the state right after it. The drop shows in them: no TDB
// force while levitated, contact after the failure.
TEST(LcmLiveState, AMonitorSeesTheRunAndItsPowerEventsAsTheyHappen) {
  const Model model = BuildModel(testing::LoadTestConfig(
      "jarroux2019_industrial_pid.toml", {"simulation.duration_s=0.16", "trigger.time_s=0.1"}));
  const double step_s = model.params.simulation.step_s;
  LcmEndpointOptions options;
  options.url = "memq://";
  LcmEndpoint endpoint(options);
  LiveSubscriber subscriber;
  endpoint.lcm().subscribe(options.state_channel, &LiveSubscriber::OnState, &subscriber);
  endpoint.lcm().subscribe(options.power_channel, &LiveSubscriber::OnPower, &subscriber);
  endpoint.Start();
  // 7 ms: not a divisor of the trigger time, so the state after the failure is off the grid.
  constexpr double kInterval_s = 7e-3;
  LcmLiveState live(&endpoint, model, kInterval_s);
  StateCapture capture;
  capture.states.reserve(static_cast<std::size_t>(model.total_steps) + 1);
  capture.power.reserve(4);
  RecorderTee tee(&capture, &live);
  HilOptions hil;
  hil.recorder = &tee;
  const std::int64_t substeps = ControllerSubsteps(model);
  InternalControllerLink link(model, substeps * step_s);
  ScheduledTrigger trigger(model.params.trigger.time_s, ScheduledFailure(model));
  HilSession session(model, &link, {&trigger}, hil);
  VirtualClock clock;
  PeriodicLoop loop(&clock, std::llround(substeps * step_s * 1e9));
  session.Start(clock.Now());
  {
    // The live state is pushed from the real-time thread: no allocation there.
    testing::MallocGuard guard;
    loop.Run([&](const LoopTick& tick) { return session.Period(tick.wake_ns); }, LoopRunOptions{});
    if (testing::MallocGuard::Available()) {
      EXPECT_EQ(guard.allocations(), 0);
    }
  }
  ASSERT_EQ(session.stop(), HilStop::kDuration);
  const std::int64_t pushed = live.states_pushed();
  ASSERT_TRUE(WaitFor([&] {
    std::lock_guard<std::mutex> lock(subscriber.mutex);
    return static_cast<std::int64_t>(subscriber.states.size()) == pushed &&
           subscriber.power.size() == 1;
  })) << "states pushed "
      << pushed;
  endpoint.Stop();
  const LcmEndpointCounters counters = endpoint.counters();
  EXPECT_EQ(counters.states_ring_full, 0u);
  EXPECT_EQ(counters.power_events_published, 1u);

  ASSERT_EQ(capture.power.size(), 1u);
  const std::int64_t event_step = capture.power.front().step;
  EXPECT_EQ(event_step, std::llround(model.params.trigger.time_s / step_s));
  const ambdrop_lcm::power_event_t& e = subscriber.power.front();
  EXPECT_EQ(e.sequence, 0);
  EXPECT_EQ(e.step_index, event_step);
  EXPECT_EQ(e.time_s, static_cast<double>(event_step) * step_s);
  EXPECT_FALSE(e.power_on);
  EXPECT_TRUE(e.motor);
  EXPECT_EQ(e.amb_mask, 0b11);  // both AMBs of the rig
  EXPECT_EQ(e.axis_mask, ambdrop_lcm::trigger_t::AXIS_X | ambdrop_lcm::trigger_t::AXIS_Y);
  for (int a = 0; a < 4; ++a) EXPECT_EQ(e.powered_axes[a], 0) << a;

  const std::int64_t every = std::llround(kInterval_s / step_s);
  const std::int64_t output_every =
      std::llround(model.params.simulation.output_interval_s / step_s);
  const int modes = model.modes();
  std::int64_t previous = -1;
  bool after_event_seen = false;
  for (const ambdrop_lcm::emulator_state_t& m : subscriber.states) {
    SCOPED_TRACE(m.step_index);
    const StateCapture::Kept* kept = capture.At(m.step_index);
    ASSERT_NE(kept, nullptr) << "published a state the session never had";
    const State& state = kept->state;
    const Observation& o = kept->observation;
    // On the interval's grid, but for the first state after the power event.
    if (previous < 0) {
      EXPECT_EQ(m.step_index, 0);
    } else if (previous <= event_step && m.step_index > event_step) {
      // The state at the event's step was taken before it applied (the event acts on the next
      // step): the first one after it is the next output step.
      EXPECT_LE(m.step_index, event_step + output_every);
      after_event_seen = true;
    } else {
      EXPECT_EQ(m.step_index % every, 0);
      EXPECT_LE(m.step_index - previous, every);
    }
    previous = m.step_index;
    EXPECT_EQ(m.time_s, static_cast<double>(m.step_index) * step_s);
    ASSERT_EQ(m.mode_count, modes);
    for (int i = 0; i < modes; ++i) {
      EXPECT_EQ(m.q[i], state.y[i]);
      EXPECT_EQ(m.q_dot[i], state.y[modes + i]);
    }
    EXPECT_EQ(m.spin_speed_rad_s, o.spin_speed_rad_s);
    ASSERT_EQ(m.tdb_count, 2);
    const bool powered = m.step_index <= event_step;
    EXPECT_EQ(m.power_on != 0, powered);
    for (int a = 0; a < 2; ++a) EXPECT_EQ(m.powered_axes[a], powered ? 3 : 0);
    for (int t = 0; t < 2; ++t) {
      EXPECT_EQ(m.tdb_normal_force_N[t], o.tdb[t].normal_force_N);
      EXPECT_EQ(m.tdb_journal_x_m[t], o.tdb_journal_xy_m[t][0]);
      if (powered) {
        EXPECT_EQ(m.tdb_normal_force_N[t], 0.0) << "contact while levitated";
      }
    }
  }
  EXPECT_TRUE(after_event_seen);
  // The gaps: 0.16 s at 7 ms with one extra state at the failure.
  EXPECT_EQ(static_cast<std::int64_t>(subscriber.states.size()), model.total_steps / every + 1 + 1);
  // It dropped: the last state shows the journals on their TDBs.
  const ambdrop_lcm::emulator_state_t& last = subscriber.states.back();
  EXPECT_GT(std::max(last.tdb_normal_force_N[0], last.tdb_normal_force_N[1]), 0.0);
}

}  // namespace
}  // namespace ambdrop::lcm_controller_link_test
