// Record → replay: a recorded run re-run from its recorded inputs is the same run, bit for bit
// (sim and a HIL session on the virtual clock, watchdog included); the log is a valid LCM event
// log (liblcm's own reader reads it); damaged logs replay up to the damage and say where; a
// changed config gives a difference that starts where the physics says it must.
#include <gtest/gtest.h>
#include <lcm/eventlog.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

#include "controller_if/controller/internal_controller_link.hpp"
#include "controller_if/loop/hil_session.hpp"
#include "controller_if/loop/offline_run.hpp"
#include "controller_if/loop/replay_run.hpp"
#include "io/files/event_log.hpp"
#include "scratch_directory.hpp"
#include "test_configs.hpp"
#include "tools/record/run_record_reader.hpp"
#include "tools/record/run_record_writer.hpp"
#include "tools/record/sensor_diff.hpp"

namespace ambdrop::run_record_test {
namespace {

namespace fs = std::filesystem;

LoadedConfig PidConfig(double duration_s, std::vector<std::string> extra = {}) {
  std::vector<std::string> overrides = {"simulation.duration_s=" + std::to_string(duration_s),
                                        "trigger.time_s=0.05"};
  overrides.insert(overrides.end(), extra.begin(), extra.end());
  return LoadConfig(testing::ConfigPath("jarroux2019_industrial_pid.toml"), overrides);
}

RecordHeaderInfo SimHeader(const LoadedConfig& config, const Model& model) {
  RecordHeaderInfo h;
  h.source = "sim";
  h.controller = "internal";
  h.config_toml = config.effective_toml;
  h.sensor_every_steps = ControllerSubsteps(model);
  h.output_every_steps = 10;
  h.total_steps = model.total_steps;
  return h;
}

bool Same(const Observation& a, const Observation& b) {
  return std::memcmp(&a.time_s, &b.time_s, sizeof a.time_s) == 0 &&
         std::memcmp(&a.spin_speed_rad_s, &b.spin_speed_rad_s, sizeof a.spin_speed_rad_s) == 0 &&
         std::memcmp(&a.sensor_xy_m, &b.sensor_xy_m, sizeof a.sensor_xy_m) == 0 &&
         std::memcmp(&a.tdb_journal_xy_m, &b.tdb_journal_xy_m, sizeof a.tdb_journal_xy_m) == 0;
}

struct Recorded {
  std::vector<Observation> observations;
  RecordCounts produced;
  std::int64_t steps = 0;
};

Recorded RecordSim(const LoadedConfig& config, const Model& model, const fs::path& path) {
  Recorded r;
  RunRecordWriter writer(path, model, SimHeader(config, model));
  const OfflineRunResult result = RunOffline(
      model, [&](const Observation& o) { r.observations.push_back(o); }, {}, &writer);
  EXPECT_EQ(result.status, StepStatus::kOk);
  writer.Finish("ok", result.steps);
  r.produced = writer.produced();
  r.steps = result.steps;
  return r;
}

struct Replayed {
  std::vector<Observation> observations;
  ReplayResult result;
  SensorDiff* diff = nullptr;
};

std::vector<std::string> SensorNames(const Model& model) {
  std::vector<std::string> names;
  for (const SensorParams& s : model.params.sensors) names.push_back(s.name);
  return names;
}

TEST(RunRecord, SimReplayIsBitIdentical) {
  const testing::ScratchDirectory scratch("ambdrop_rr");
  const LoadedConfig config = PidConfig(0.12);
  const Model model = BuildModel(config.params);
  const fs::path path = scratch.File("sim.lcm");
  const Recorded live = RecordSim(config, model, path);

  const RunRecordFile file = ReadRunRecord(path);
  EXPECT_TRUE(file.warnings.empty()) << file.warnings.front();
  EXPECT_FALSE(file.damaged);
  EXPECT_EQ(file.header.source, "sim");
  EXPECT_EQ(file.header.config_hash, RunRecordWriter::ConfigHash(config.effective_toml));
  ASSERT_TRUE(file.footer.has_value());
  // Nothing lost: the footer's written counts are what the run produced, and what was read.
  EXPECT_EQ(file.footer->produced, live.produced);
  EXPECT_EQ(file.footer->written, live.produced);
  EXPECT_EQ(static_cast<std::int64_t>(file.run.inputs.size()), live.produced.inputs);
  EXPECT_EQ(static_cast<std::int64_t>(file.sensors.size()), live.produced.sensors);
  ASSERT_EQ(file.run.power.size(), 1U);  // the scheduled failure
  EXPECT_EQ(file.run.power[0].step, model.trigger_step);
  EXPECT_EQ(file.run.end_step, live.steps);

  // The replay rebuilds the model from the recorded config text, as `ambdrop replay` does.
  const Model replay_model =
      BuildModel(LoadConfigFromString(file.header.config_toml, "record").params);
  std::vector<Observation> replayed;
  SensorDiff diff(file.sensors, SensorNames(replay_model));
  const ReplayResult result = ReplayRun(
      replay_model, file.run, [&](const Observation& o) { replayed.push_back(o); },
      [&](const RecordedSensors& s) { diff.Add(s); });
  EXPECT_EQ(result.status, StepStatus::kOk);
  EXPECT_TRUE(diff.identical()) << diff.Describe(model.params.simulation.step_s);
  EXPECT_EQ(diff.compared(), live.produced.sensors);
  ASSERT_EQ(replayed.size(), live.observations.size());
  for (std::size_t i = 0; i < replayed.size(); ++i) {
    ASSERT_TRUE(Same(replayed[i], live.observations[i])) << "observation " << i;
  }
  EXPECT_GT(live.observations.back().tdb[0].normal_force_N, 0.0);  // it did drop
}

TEST(RunRecord, RecordingTheSameRunTwiceGivesTheSameBytes) {
  const testing::ScratchDirectory scratch("ambdrop_rr");
  const LoadedConfig config = PidConfig(0.03);
  const Model model = BuildModel(config.params);
  RecordSim(config, model, scratch.File("a.lcm"));
  RecordSim(config, model, scratch.File("b.lcm"));
  std::ifstream a(scratch.File("a.lcm"), std::ios::binary),
      b(scratch.File("b.lcm"), std::ios::binary);
  const std::vector<char> bytes_a((std::istreambuf_iterator<char>(a)), {});
  const std::vector<char> bytes_b((std::istreambuf_iterator<char>(b)), {});
  EXPECT_GT(bytes_a.size(), 1000U);
  EXPECT_TRUE(bytes_a == bytes_b);
}

TEST(RunRecord, LcmsOwnEventLogReaderReadsTheRecord) {
  const testing::ScratchDirectory scratch("ambdrop_rr");
  const LoadedConfig config = PidConfig(0.02);
  const Model model = BuildModel(config.params);
  const fs::path path = scratch.File("lcm.lcm");
  RecordSim(config, model, path);
  lcm_eventlog_t* log = lcm_eventlog_create(path.c_str(), "r");
  ASSERT_NE(log, nullptr);
  std::int64_t events = 0, sensors = 0;
  std::string first;
  while (lcm_eventlog_event_t* e = lcm_eventlog_read_next_event(log)) {
    const std::string channel(e->channel, e->channellen);
    if (events == 0) first = channel;
    if (channel == "AMBDROP_SENSORS") ++sensors;
    EXPECT_EQ(e->eventnum, events);
    ++events;
    lcm_eventlog_free_event(e);
  }
  lcm_eventlog_destroy(log);
  EXPECT_EQ(first, "AMBDROP_RECORD_HEADER");
  EXPECT_EQ(sensors, ReadRunRecord(path).footer->written.sensors);
  // Both readers see every event.
  EventLogReader ours(path);
  LogEvent event;
  std::int64_t our_events = 0;
  while (ours.Next(&event) == LogReadStatus::kEvent) ++our_events;
  EXPECT_EQ(events, our_events);
  EXPECT_EQ(ours.offset(), ours.file_size());
  EXPECT_GT(events, 100);
}

/// Replays a record and returns how far it got and whether all it compared was identical.
struct DamagedReplay {
  RunRecordFile file;
  ReplayResult result;
  bool identical_so_far = false;
  std::int64_t compared = 0;
};

DamagedReplay ReplayDamaged(const fs::path& path) {
  DamagedReplay d;
  d.file = ReadRunRecord(path);
  const Model model = BuildModel(LoadConfigFromString(d.file.header.config_toml, "r").params);
  SensorDiff diff(d.file.sensors, SensorNames(model));
  d.result = ReplayRun(model, d.file.run, {}, [&](const RecordedSensors& s) { diff.Add(s); });
  d.identical_so_far = diff.differing() == 0;
  d.compared = diff.compared();
  return d;
}

TEST(RunRecord, TruncatedLogReplaysUpToTheCutAndSaysWhere) {
  const testing::ScratchDirectory scratch("ambdrop_rr");
  const LoadedConfig config = PidConfig(0.06);
  const Model model = BuildModel(config.params);
  const fs::path path = scratch.File("full.lcm");
  const Recorded live = RecordSim(config, model, path);
  const auto size = static_cast<std::int64_t>(fs::file_size(path));
  for (const double fraction : {0.3, 0.61, 0.97}) {
    const fs::path cut = scratch.File("cut.lcm");
    fs::copy_file(path, cut, fs::copy_options::overwrite_existing);
    const auto cut_at = static_cast<std::int64_t>(fraction * static_cast<double>(size)) + 7;
    fs::resize_file(cut, static_cast<std::uintmax_t>(cut_at));
    const DamagedReplay d = ReplayDamaged(cut);
    EXPECT_TRUE(d.file.damaged) << fraction;
    ASSERT_FALSE(d.file.warnings.empty());
    EXPECT_NE(d.file.warnings.front().find("truncated"), std::string::npos)
        << d.file.warnings.front();
    EXPECT_NE(d.file.warnings.front().find("byte"), std::string::npos);
    // Up to the cut: roughly the fraction of the run, and identical to the live run.
    EXPECT_TRUE(d.identical_so_far) << fraction;
    EXPECT_NEAR(static_cast<double>(d.result.steps) / static_cast<double>(live.steps), fraction,
                0.1);
    EXPECT_GT(d.compared, 0);
  }
  // Cut inside the header: nothing usable, a clear error rather than a crash.
  fs::resize_file(scratch.File("cut.lcm"), 40);
  EXPECT_THROW(ReadRunRecord(scratch.File("cut.lcm")), std::runtime_error);
}

TEST(RunRecord, CorruptedLogStopsBeforeTheBadBlock) {
  const testing::ScratchDirectory scratch("ambdrop_rr");
  const LoadedConfig config = PidConfig(0.06);
  const Model model = BuildModel(config.params);
  const fs::path path = scratch.File("good.lcm");
  const Recorded live = RecordSim(config, model, path);
  const auto size = static_cast<std::int64_t>(fs::file_size(path));
  for (const double fraction : {0.25, 0.5, 0.8}) {
    const fs::path bad = scratch.File("bad.lcm");
    fs::copy_file(path, bad, fs::copy_options::overwrite_existing);
    const auto at = static_cast<std::int64_t>(fraction * static_cast<double>(size));
    {
      std::fstream f(bad, std::ios::in | std::ios::out | std::ios::binary);
      f.seekg(at);
      char c = 0;
      f.read(&c, 1);
      c = static_cast<char>(c ^ 0x5A);
      f.seekp(at);
      f.write(&c, 1);
    }
    const DamagedReplay d = ReplayDamaged(bad);
    EXPECT_TRUE(d.file.damaged) << fraction;
    ASSERT_FALSE(d.file.warnings.empty());
    EXPECT_NE(d.file.warnings.front().find("corrupt"), std::string::npos)
        << d.file.warnings.front();
    EXPECT_NE(d.file.warnings.front().find("byte"), std::string::npos);
    EXPECT_TRUE(d.identical_so_far) << fraction;  // nothing corrupt was used
    EXPECT_LT(d.result.steps, live.steps);
    EXPECT_GT(static_cast<double>(d.result.steps), (fraction - 0.1) * live.steps);
  }
}

TEST(RunRecord, HilSessionReplayIsBitIdenticalWatchdogIncluded) {
  const testing::ScratchDirectory scratch("ambdrop_rr");
  // The controller falls silent after 20 ms; the watchdog zeroes the currents; then the power
  // fails: every kind of input event is in the record.
  const LoadedConfig config = PidConfig(0.08);
  const Model model = BuildModel(config.params);
  const std::int64_t substeps = ControllerSubsteps(model);
  const double period_s = substeps * model.params.simulation.step_s;

  class SilentAfter final : public ControllerLink {
   public:
    SilentAfter(const Model& m, double period_s, int periods)
        : inner_(m, period_s), left_(periods) {}
    bool PollCurrents(CurrentsMessage* out) noexcept override {
      return left_-- > 0 && inner_.PollCurrents(out);
    }
    void SendSensors(const SensorReadings& r, std::int64_t step, double t) noexcept override {
      inner_.SendSensors(r, step, t);
    }

   private:
    InternalControllerLink inner_;
    int left_;
  } link(model, period_s, static_cast<int>(0.02 / period_s));

  const fs::path path = scratch.File("hil.lcm");
  RecordHeaderInfo header = SimHeader(config, model);
  header.source = "hil";
  RunRecordWriter writer(path, model, header);
  ScheduledTrigger trigger(model.params.trigger.time_s, ScheduledFailure(model));
  HilOptions options;
  options.watchdog_timeout_s = 2e-3;
  options.silence_action = SilenceAction::kZero;
  options.recorder = &writer;
  HilSession session(model, &link, {&trigger}, options);
  session.Start(0);
  std::int64_t n = 0;
  while (session.Period(n * std::llround(period_s * 1e9))) ++n;
  writer.Finish("ok", session.state().step_index);
  EXPECT_EQ(session.stop(), HilStop::kDuration);
  EXPECT_GT(session.counters().watchdog_zero_periods, 0);

  const RunRecordFile file = ReadRunRecord(path);
  ASSERT_FALSE(file.damaged);
  const auto zero = std::count_if(file.run.inputs.begin(), file.run.inputs.end(), [](auto& in) {
    return in.kind == RecordedInputKind::kWatchdogZero;
  });
  EXPECT_EQ(zero, 1);
  SensorDiff diff(file.sensors, SensorNames(model));
  const ReplayResult result =
      ReplayRun(model, file.run, {}, [&](const RecordedSensors& s) { diff.Add(s); });
  EXPECT_EQ(result.steps, session.state().step_index);
  EXPECT_TRUE(diff.identical()) << diff.Describe(model.params.simulation.step_s);
  EXPECT_EQ(diff.compared(), session.counters().sensor_samples_sent);
  EXPECT_EQ(std::memcmp(result.final_state.y.data(), session.state().y.data(),
                        sizeof(double) * session.state().y.size()),
            0);
}

TEST(RunRecord, ChangedFrictionDiffersOnlyFromTheFirstContactOn) {
  const testing::ScratchDirectory scratch("ambdrop_rr");
  const LoadedConfig config = PidConfig(0.12);
  const Model model = BuildModel(config.params);
  const fs::path path = scratch.File("friction.lcm");
  const Recorded live = RecordSim(config, model, path);
  double first_contact_s = -1.0;
  for (const Observation& o : live.observations) {
    if (first_contact_s < 0 && (o.tdb[0].normal_force_N > 0 || o.tdb[1].normal_force_N > 0)) {
      first_contact_s = o.time_s;
    }
  }
  ASSERT_GT(first_contact_s, model.params.trigger.time_s);

  const RunRecordFile file = ReadRunRecord(path);
  const std::string& de = model.params.tdbs[0].name;
  const Model changed = BuildModel(LoadConfigFromString(file.header.config_toml, "record",
                                                        {"tdb." + de + ".friction.coefficient=0.3"})
                                       .params);
  SensorDiff diff(file.sensors, SensorNames(changed));
  ReplayRun(changed, file.run, {}, [&](const RecordedSensors& s) { diff.Add(s); });
  ASSERT_FALSE(diff.identical());
  const std::string text = diff.Describe(model.params.simulation.step_s);
  EXPECT_NE(text.find("first at step"), std::string::npos) << text;
  // Friction acts only in contact: the outputs agree up to the first contact (observations are
  // every 10 steps, hence one output interval of slack).
  const std::int64_t contact_step =
      std::llround(first_contact_s / model.params.simulation.step_s) - 10;
  EXPECT_GE(diff.first_difference_step(), contact_step) << text;
}

}  // namespace
}  // namespace ambdrop::run_record_test
