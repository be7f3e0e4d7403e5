// The HIL session on the virtual clock with the in-process controller reproduces the offline
// simulation bit for bit (the same drop from the same inputs), through the periodic loop; the
// watchdog acts on a silent controller.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "controller_if/controller/internal_controller_link.hpp"
#include "controller_if/loop/hil_session.hpp"
#include "controller_if/loop/offline_run.hpp"
#include "controller_if/loop/periodic_loop.hpp"
#include "controller_if/loop/rt_clock.hpp"
#include "malloc_guard.hpp"
#include "test_configs.hpp"

namespace ambdrop::hil_session_test {
namespace {

Model PidRig(double duration_s, std::vector<std::string> overrides = {}) {
  overrides.push_back("simulation.duration_s=" + std::to_string(duration_s));
  overrides.push_back("trigger.time_s=0.1");
  return BuildModel(testing::LoadTestConfig("jarroux2019_industrial_pid.toml", overrides));
}

bool SameObservation(const Observation& a, const Observation& b) {
  return a.time_s == b.time_s && a.spin_speed_rad_s == b.spin_speed_rad_s &&
         std::memcmp(&a.sensor_xy_m, &b.sensor_xy_m, sizeof(a.sensor_xy_m)) == 0 &&
         std::memcmp(&a.tdb_journal_xy_m, &b.tdb_journal_xy_m, sizeof(a.tdb_journal_xy_m)) == 0;
}

// The rig run offline and as a HIL session with the in-process controller on the virtual
// clock: the same observations, bit for bit (both take their steps from one driver).
void ExpectHilMatchesOffline(const Model& model) {
  std::vector<Observation> offline;
  ASSERT_EQ(RunOffline(model, [&](const Observation& o) { offline.push_back(o); }).status,
            StepStatus::kOk);

  const std::int64_t substeps = ControllerSubsteps(model);
  const double period_s = substeps * model.params.simulation.step_s;
  InternalControllerLink link(model, period_s);
  ScheduledTrigger trigger(model.params.trigger.time_s, ScheduledFailure(model));
  auto outputs = std::make_unique<HilSession::OutputRing>();
  HilSession session(model, &link, {&trigger}, HilOptions{}, outputs.get());
  VirtualClock clock;
  PeriodicLoop loop(&clock, std::llround(period_s * 1e9));
  session.Start(clock.Now());
  std::vector<Observation> hil;
  Observation o;
  LoopRunOptions options;
  const LoopResult result = loop.Run(
      [&](const LoopTick& tick) {
        const bool go_on = session.Period(tick.wake_ns);
        while (outputs->TryPop(&o)) hil.push_back(o);  // the test drains on the same thread
        return go_on;
      },
      options);
  EXPECT_EQ(session.stop(), HilStop::kDuration);
  EXPECT_EQ(result.overruns, 0);
  EXPECT_EQ(session.counters().power_events, 1);
  EXPECT_EQ(session.counters().observations_dropped, 0);
  ASSERT_EQ(hil.size(), offline.size());
  for (std::size_t i = 0; i < hil.size(); ++i) {
    ASSERT_TRUE(SameObservation(hil[i], offline[i]))
        << "observation " << i << " at t = " << offline[i].time_s;
  }
  EXPECT_GT(offline.back().tdb[0].normal_force_N, 0.0);  // and it did drop
}

TEST(HilSession, VirtualClockRunMatchesTheOfflineSimulation) {
  ExpectHilMatchesOffline(PidRig(0.15));
}

// The flux decays over 2 ms while a controller period is 10 steps: the power-loss law is
// evaluated at every step in both runs (a session once held it over each period and fell
// behind the offline run by the decay over a period).
TEST(HilSession, VirtualClockRunMatchesTheOfflineSimulationThroughAFluxDecay) {
  const Model model =
      PidRig(0.15, {"amb.nde.flux_decay.enabled=true", "amb.de.flux_decay.enabled=true"});
  ASSERT_GT(ControllerSubsteps(model), 1);
  ExpectHilMatchesOffline(model);
}

TEST(HilSession, PeriodIsAllocationFree) {
  const Model model = PidRig(0.2);
  const double period_s = ControllerSubsteps(model) * model.params.simulation.step_s;
  InternalControllerLink link(model, period_s);
  ScheduledTrigger trigger(0.05, ScheduledFailure(model));
  auto outputs = std::make_unique<HilSession::OutputRing>();
  HilSession session(model, &link, {&trigger}, HilOptions{}, outputs.get());
  session.Start(0);
  Observation o;
  std::int64_t allocations = 0;
  {
    testing::MallocGuard guard;
    for (int k = 0; k < 2000; ++k) {  // 0.1 s: through the trigger and the impacts
      ASSERT_TRUE(session.Period(k * 50'000));
      while (outputs->TryPop(&o)) {
      }
    }
    allocations = guard.allocations();
  }
  EXPECT_EQ(allocations, 0);
}

// A controller that stops talking after a while.
class FallsSilent final : public ControllerLink {
 public:
  explicit FallsSilent(int periods) : periods_(periods) {}
  bool PollCurrents(CurrentsMessage* out) noexcept override {
    if (samples_ > periods_ || !pending_) return false;
    pending_ = false;
    out->current_A[0] = {1.0, 2.0};
    return true;
  }
  void SendSensors(const SensorReadings&, std::int64_t, double) noexcept override {
    ++samples_;  // once per period, and once at the start
    pending_ = true;
  }

 private:
  int periods_;
  int samples_ = 0;
  bool pending_ = false;
};

TEST(HilSession, WatchdogActsOnControllerSilence) {
  const Model model = PidRig(0.05);
  for (SilenceAction action : {SilenceAction::kHold, SilenceAction::kZero, SilenceAction::kStop}) {
    FallsSilent link(100);  // talks for 5 ms, then never again
    HilSession session(model, &link, {}, HilOptions{2e-3, action});
    session.Start(0);
    int periods = 0;
    while (session.Period(static_cast<std::int64_t>(periods) * 50'000)) ++periods;
    EXPECT_EQ(session.watchdog().silence_episodes(), 1) << ToString(action);
    switch (action) {
      case SilenceAction::kHold:
        EXPECT_GT(session.counters().watchdog_hold_periods, 0);
        EXPECT_EQ(session.stop(), HilStop::kDuration);
        break;
      case SilenceAction::kZero:
        EXPECT_GT(session.counters().watchdog_zero_periods, 0);
        EXPECT_EQ(session.stop(), HilStop::kDuration);
        break;
      case SilenceAction::kStop:
        EXPECT_EQ(session.stop(), HilStop::kWatchdog);
        // Silent after period 100; stops once 2 ms (40 periods) have passed.
        EXPECT_NEAR(periods, 100 + 40, 2);
        break;
    }
  }
}

// The session's run state is the whole run: a second session resumed from it mid-run, over
// copies of the link (the reference controller inside it) and the trigger, goes on exactly as the
// first does, through the trigger and the drop, observation for observation.
TEST(HilSession, ASessionResumedFromAnothersRunStateGoesOnBitForBit) {
  const Model model = PidRig(0.15);
  const double period_s = ControllerSubsteps(model) * model.params.simulation.step_s;
  const std::int64_t period_ns = std::llround(period_s * 1e9);
  InternalControllerLink link(model, period_s);
  ScheduledTrigger trigger(model.params.trigger.time_s, ScheduledFailure(model));
  auto outputs = std::make_unique<HilSession::OutputRing>();
  HilSession session(model, &link, {&trigger}, HilOptions{}, outputs.get());
  session.Start(0);
  std::int64_t period = 0;
  Observation o;
  // Half way to the trigger.
  while (session.state().step_index < model.trigger_step / 2) {
    ASSERT_TRUE(session.Period(period++ * period_ns));
    while (outputs->TryPop(&o)) {
    }
  }
  InternalControllerLink link_copy = link;
  ScheduledTrigger trigger_copy = trigger;
  auto outputs_copy = std::make_unique<HilSession::OutputRing>();
  HilSession resumed(model, &link_copy, {&trigger_copy}, HilOptions{}, outputs_copy.get(),
                     &session.run_state());
  std::vector<Observation> first, second;
  bool go_on = true;
  while (go_on) {
    const std::int64_t now_ns = period++ * period_ns;
    go_on = session.Period(now_ns);
    ASSERT_EQ(resumed.Period(now_ns), go_on);
    while (outputs->TryPop(&o)) first.push_back(o);
    while (outputs_copy->TryPop(&o)) second.push_back(o);
  }
  EXPECT_EQ(resumed.stop(), HilStop::kDuration);
  EXPECT_EQ(resumed.counters().power_events, 1);
  ASSERT_EQ(first.size(), second.size());
  for (std::size_t i = 0; i < first.size(); ++i) {
    ASSERT_TRUE(SameObservation(first[i], second[i])) << "t = " << first[i].time_s;
  }
  EXPECT_GT(first.back().tdb[0].normal_force_N + first.back().tdb[1].normal_force_N, 0.0);
}

}  // namespace
}  // namespace ambdrop::hil_session_test
