// The missed-period policy of the HIL loop, on the virtual clock: when the loop wakes so late that
// it skips deadlines, the session still advances the physics through the skipped periods, so
// simulated time equals the wall (clock) time elapsed, and only the current period's sensor
// sample is sent.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "controller_if/controller/internal_controller_link.hpp"
#include "controller_if/loop/hil_session.hpp"
#include "controller_if/loop/periodic_loop.hpp"
#include "controller_if/loop/rt_clock.hpp"
#include "malloc_guard.hpp"
#include "test_configs.hpp"

namespace ambdrop::hil_catch_up_test {
namespace {

Model PidRig(double duration_s, double trigger_s) {
  return BuildModel(testing::LoadTestConfig("jarroux2019_industrial_pid.toml",
                                            {"simulation.duration_s=" + std::to_string(duration_s),
                                             "trigger.time_s=" + std::to_string(trigger_s)}));
}

// Counts what the session sends, and forwards to the in-process controller.
class CountingLink final : public ControllerLink {
 public:
  CountingLink(const Model& model, double period_s) : inner_(model, period_s) {}
  bool PollCurrents(CurrentsMessage* out) noexcept override { return inner_.PollCurrents(out); }
  void SendSensors(const SensorReadings& readings, std::int64_t step,
                   double time_s) noexcept override {
    steps_sent.push_back(step);
    last_reading_y_m = readings.reading_m[0][1];
    inner_.SendSensors(readings, step, time_s);
  }
  std::vector<std::int64_t> steps_sent;  // reserved by the test: no allocation in the loop
  double last_reading_y_m = 0.0;         // sensor 0, vertical

 private:
  InternalControllerLink inner_;
};

struct CatchUpRun {
  LoopResult loop;
  std::int64_t step_index = 0;
  HilCounters counters;
  std::vector<std::int64_t> steps_sent;
  double last_reading_y_m = 0.0;
};

// Runs `periods` clock periods; the wake-ups at the deadlines in `late` come `late_periods`
// periods late. With `pass_missed` false the callback ignores LoopTick::missed_before (the
// policy off), to show the check below can fail.
CatchUpRun RunWithLateWakeUps(const Model& model, std::int64_t periods,
                              const std::set<std::int64_t>& late, double late_periods,
                              bool pass_missed) {
  const std::int64_t substeps = ControllerSubsteps(model);
  const double period_s = substeps * model.params.simulation.step_s;
  const std::int64_t period_ns = std::llround(period_s * 1e9);
  CountingLink link(model, period_s);
  link.steps_sent.reserve(static_cast<std::size_t>(periods) + 2);
  ScheduledTrigger trigger(model.params.trigger.time_s, ScheduledFailure(model));
  HilSession session(model, &link, {&trigger}, HilOptions{});
  VirtualClock clock;
  clock.SetLatenessHook([&](std::int64_t deadline) -> std::int64_t {
    return late.contains(deadline / period_ns) ? std::llround(late_periods * period_ns) : 0;
  });
  PeriodicLoop loop(&clock, period_ns);
  LoopRunOptions options;
  options.max_periods = periods;
  options.first_deadline_ns = period_ns;  // deadline k = (k + 1) periods: index = deadline / P - 1
  session.Start(0);
  CatchUpRun out;
  out.loop = loop.Run(
      [&](const LoopTick& tick) {
        return session.Period(tick.wake_ns, pass_missed ? tick.missed_before : 0);
      },
      options);
  out.step_index = session.state().step_index;
  out.counters = session.counters();
  out.steps_sent = link.steps_sent;
  out.last_reading_y_m = link.last_reading_y_m;
  return out;
}

TEST(HilCatchUp, SimulatedTimeTracksClockTimeThroughMissedPeriods) {
  const Model model = PidRig(0.05, 0.01);  // 1000 periods at 20 kHz; the drop at period 200
  const std::int64_t substeps = ControllerSubsteps(model);
  constexpr std::int64_t kPeriods = 400;
  // Five wake-ups 2.5 periods late (each skips 2 deadlines); the one at deadline 199 makes the
  // loop skip periods 199 and 200, so the power failure (period 200) falls in a catch-up.
  const std::set<std::int64_t> late = {20, 101, 199, 250, 333};
  const CatchUpRun run = RunWithLateWakeUps(model, kPeriods, late, 2.5, true);

  ASSERT_EQ(run.loop.periods, kPeriods);
  EXPECT_EQ(run.loop.overruns, 5);
  EXPECT_EQ(run.loop.missed_periods, 5 * 2);
  EXPECT_EQ(run.loop.cycles + run.loop.missed_periods, kPeriods);
  // The physics ran every clock period, missed ones included: simulated time = clock time.
  EXPECT_EQ(run.step_index, kPeriods * substeps);
  EXPECT_EQ(run.counters.catch_up_periods, run.loop.missed_periods);
  EXPECT_EQ(run.counters.periods, run.loop.cycles);
  EXPECT_EQ(run.counters.power_events, 1);  // fired inside the catch-up, not lost
  // One sample per period run (plus Start's), none for the skipped periods, in step order.
  EXPECT_EQ(run.counters.sensor_samples_sent, run.loop.cycles + 1);
  ASSERT_EQ(static_cast<std::int64_t>(run.steps_sent.size()), run.loop.cycles + 1);
  for (std::size_t i = 1; i < run.steps_sent.size(); ++i) {
    const std::int64_t gap = run.steps_sent[i] - run.steps_sent[i - 1];
    EXPECT_TRUE(gap == substeps || gap == 3 * substeps) << "sample " << i << ": gap " << gap;
  }
}

TEST(HilCatchUp, MatchesAnOnTimeRunUpToTheSkippedExchanges) {
  // The catch-up keeps the rotor where an on-time run puts it in time: same step count, and a
  // levitated rotor stays levitated (the held currents over 2 periods do not upset it).
  const Model model = PidRig(0.05, 1.0);  // no drop in this run
  const CatchUpRun on_time = RunWithLateWakeUps(model, 600, {}, 0.0, true);
  const CatchUpRun late = RunWithLateWakeUps(model, 600, {50, 150, 250, 350, 450}, 2.5, true);
  EXPECT_EQ(late.step_index, on_time.step_index);
  EXPECT_EQ(late.counters.catch_up_periods, 10);
  EXPECT_EQ(on_time.counters.catch_up_periods, 0);
  // Both end levitated near the centre (the clearance is hundreds of um).
  EXPECT_LT(std::abs(on_time.last_reading_y_m), 20e-6);
  EXPECT_LT(std::abs(late.last_reading_y_m), 20e-6);
}

TEST(HilCatchUp, WithoutThePolicySimulatedTimeFallsBehind) {
  // The check above can fail: ignoring missed_before loses 2 periods per late wake-up.
  const Model model = PidRig(0.05, 1.0);
  const std::int64_t substeps = ControllerSubsteps(model);
  const CatchUpRun run = RunWithLateWakeUps(model, 400, {20, 101}, 2.5, false);
  EXPECT_EQ(run.loop.missed_periods, 4);
  EXPECT_EQ(run.step_index, (400 - 4) * substeps);
  EXPECT_EQ(run.counters.catch_up_periods, 0);
}

TEST(HilCatchUp, CatchUpStopsAtTheEndOfTheRun) {
  // Periods skipped across the configured duration end the run there, not past it.
  const Model model = PidRig(0.005, 1.0);  // 100 periods
  const CatchUpRun run = RunWithLateWakeUps(model, 1000, {98}, 5.5, true);
  EXPECT_EQ(run.step_index, model.total_steps);
}

TEST(HilCatchUp, CatchingUpDoesNotAllocate) {
  if (!testing::MallocGuard::Available()) GTEST_SKIP() << "no malloc hooks in sanitizer builds";
  const Model model = PidRig(0.05, 0.01);
  const double period_s = ControllerSubsteps(model) * model.params.simulation.step_s;
  InternalControllerLink link(model, period_s);
  ScheduledTrigger trigger(model.params.trigger.time_s, ScheduledFailure(model));
  HilSession session(model, &link, {&trigger}, HilOptions{});
  session.Start(0);
  std::int64_t allocations = 0;
  {
    testing::MallocGuard guard;
    for (int k = 0; k < 300; ++k) {  // through the trigger at period 200
      ASSERT_TRUE(session.Period(k * 150'000, 2));
    }
    allocations = guard.allocations();
  }
  EXPECT_EQ(allocations, 0);
  EXPECT_EQ(session.counters().catch_up_periods, 600);
}

}  // namespace
}  // namespace ambdrop::hil_catch_up_test
