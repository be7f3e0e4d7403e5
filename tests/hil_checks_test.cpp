// The checks every `ambdrop hil` run is held to (tools/cli/hil_checks.hpp), on HIL sessions of
// the PID rig on the virtual clock: the reference controller levitates the rotor within a small
// fraction of the clearance and answers every sample, so every default check passes; a link
// that loses two answers in three is caught by the answered fraction and counted period by
// period; bounds on the drop's peak load and spin-up hold the figures the run reached.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "controller_if/controller/internal_controller_link.hpp"
#include "controller_if/loop/hil_session.hpp"
#include "controller_if/loop/periodic_loop.hpp"
#include "controller_if/loop/rt_clock.hpp"
#include "test_configs.hpp"
#include "tools/cli/hil_checks.hpp"

namespace ambdrop::hil_checks_test {
namespace {

// The reference controller whose answers reach the emulator only for every `keep`-th sample:
// the others are lost on the way (a lossy link, not a slow controller).
class LossyLink final : public ControllerLink {
 public:
  LossyLink(const Model& model, double period_s, int keep) : inner_(model, period_s), keep_(keep) {}
  bool PollCurrents(CurrentsMessage* out) noexcept override {
    if (!inner_.PollCurrents(out)) return false;
    return polls_++ % keep_ == 0;
  }
  void SendSensors(const SensorReadings& r, std::int64_t step, double time_s) noexcept override {
    inner_.SendSensors(r, step, time_s);
  }

 private:
  InternalControllerLink inner_;
  int keep_;
  std::int64_t polls_ = 0;
};

struct CheckedRun {
  HilCounters counters;
  HilChecks checks;
  HilRunFacts facts;
};

CheckedRun RunSession(const Model& model, ControllerLink* link) {
  ScheduledTrigger trigger(model.params.trigger.time_s, ScheduledFailure(model));
  auto outputs = std::make_unique<HilSession::OutputRing>();
  HilSession session(model, link, {&trigger}, HilOptions{}, outputs.get());
  VirtualClock clock;
  PeriodicLoop loop(&clock, std::llround(session.period_s() * 1e9));
  CheckedRun run;
  session.Start(clock.Now());
  Observation o;
  loop.Run(
      [&](const LoopTick& tick) {
        const bool go_on = session.Period(tick.wake_ns);
        while (outputs->TryPop(&o)) run.checks.Add(o);
        return go_on;
      },
      LoopRunOptions{});
  EXPECT_EQ(session.stop(), HilStop::kDuration);
  run.counters = session.counters();
  run.facts.first_power_event_s =
      static_cast<double>(run.counters.first_power_event_step) * model.params.simulation.step_s;
  run.facts.levitated_fraction = run.counters.levitated_fraction;
  run.facts.answers = run.counters.currents_received;
  run.facts.samples_sent = run.counters.sensor_samples_sent;
  run.facts.external = true;  // judged as an outside controller would be
  return run;
}

Model PidRig() {
  return BuildModel(testing::LoadTestConfig("jarroux2019_industrial_pid.toml",
                                            {"simulation.duration_s=0.15", "trigger.time_s=0.1"}));
}

TEST(HilChecks, TheReferenceControllerPassesEveryDefaultCheck) {
  const Model model = PidRig();
  const double period_s = ControllerSubsteps(model) * model.params.simulation.step_s;
  InternalControllerLink link(model, period_s);
  const CheckedRun run = RunSession(model, &link);
  // Levitated on its static-load currents: the journals sit within 1 % of the 250 um clearance
  // (at most a few um off centre while the PID settles).
  EXPECT_GT(run.counters.levitated_fraction, 0.0);
  EXPECT_LT(run.counters.levitated_fraction, 0.01);
  EXPECT_EQ(run.counters.periods_without_currents, 0);
  EXPECT_EQ(run.checks.Failures(run.facts, HilCheckBounds{}), "");
  // It dropped: the first contact comes after the failure.
  ASSERT_TRUE(run.checks.first_contact_s().has_value());
  EXPECT_GT(*run.checks.first_contact_s(), 0.1);
  EXPECT_GT(run.checks.peak_tdb_load_N(), 0.0);
  EXPECT_GT(run.checks.max_penetration_m(), 0.0);
  EXPECT_GT(run.checks.max_race_speed_rad_s(), 0.0);
  // A bound below a figure the run reached fails, and says which.
  HilCheckBounds tight;
  tight.levitated_fraction = 0.5 * run.counters.levitated_fraction;
  tight.max_tdb_load_N = 0.5 * run.checks.peak_tdb_load_N();
  tight.max_race_speed_rad_s = 0.5 * run.checks.max_race_speed_rad_s();
  const std::string failures = run.checks.Failures(run.facts, tight);
  EXPECT_NE(failures.find("of its clearance off centre"), std::string::npos) << failures;
  EXPECT_NE(failures.find("peak load"), std::string::npos) << failures;
  EXPECT_NE(failures.find("spun up"), std::string::npos) << failures;
}

TEST(HilChecks, ALinkThatLosesTwoAnswersInThreeFailsTheAnsweredFraction) {
  const Model model = PidRig();
  const double period_s = ControllerSubsteps(model) * model.params.simulation.step_s;
  LossyLink link(model, period_s, 3);
  const CheckedRun run = RunSession(model, &link);
  const double answered = static_cast<double>(run.facts.answers) / run.facts.samples_sent;
  EXPECT_NEAR(answered, 1.0 / 3.0, 0.01);
  // Two periods in three closed with no new currents.
  EXPECT_NEAR(static_cast<double>(run.counters.periods_without_currents) /
                  static_cast<double>(run.counters.periods),
              2.0 / 3.0, 0.01);
  const std::string failures = run.checks.Failures(run.facts, HilCheckBounds{});
  EXPECT_NE(failures.find("the controller answered"), std::string::npos) << failures;
  HilCheckBounds lenient;
  lenient.answered_fraction = 0.3;
  EXPECT_EQ(run.checks.Failures(run.facts, lenient).find("answered"), std::string::npos);
}

}  // namespace
}  // namespace ambdrop::hil_checks_test
