// LcmEndpoint over memq:// (an in-process LCM bus private to the endpoint's lcm::LCM, so these
// tests touch no network): currents and triggers in, sensors and state out, malformed messages
// counted and dropped, full rings counted, and a real-time side that never allocates.
#include <gtest/gtest.h>
#include <sched.h>

#include <ambdrop_lcm/amb_currents_t.hpp>
#include <ambdrop_lcm/emulator_state_t.hpp>
#include <ambdrop_lcm/plant_description_t.hpp>
#include <ambdrop_lcm/sensor_readings_t.hpp>
#include <ambdrop_lcm/trigger_t.hpp>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "io/lcm/lcm_transport.hpp"
#include "malloc_guard.hpp"

namespace ambdrop::lcm_transport_test {
namespace {

using std::chrono::milliseconds;

/// Polls `done` until it holds or 5 s pass (generous: the VM can pause for milliseconds).
template <typename Predicate>
bool WaitFor(Predicate done) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (!done()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(milliseconds(1));
  }
  return true;
}

std::unique_ptr<LcmEndpoint> MakeEndpoint(LcmEndpointOptions options = {}) {
  options.url = "memq://";
  return std::make_unique<LcmEndpoint>(std::move(options));
}

ambdrop_lcm::amb_currents_t Currents(std::int64_t sequence) {
  ambdrop_lcm::amb_currents_t msg{};
  msg.utime = 1'700'000'000'000'000 + sequence;
  msg.sequence = sequence;
  msg.amb_count = 2;
  msg.current_x_A[0] = 0.25 + static_cast<double>(sequence);
  msg.current_y_A[0] = -1.5;
  msg.current_x_A[1] = 3.0e-3;
  msg.current_y_A[1] = -7.125;
  return msg;
}

ambdrop_lcm::trigger_t Trigger(bool power_on, std::int8_t amb_mask, std::int8_t axis_mask) {
  ambdrop_lcm::trigger_t msg{};
  msg.utime = 42;
  msg.sequence = 7;
  msg.power_on = power_on ? 1 : 0;
  msg.amb_mask = amb_mask;
  msg.axis_mask = axis_mask;
  return msg;
}

/// Subscribes through LCM's C API and decodes into Message. lcm-cpp's member-function
/// subscriptions crash under GCC 12's -fsanitize=vptr (part of the AMBDROP_SANITIZE build), even
/// in a 20-line program, so the tests avoid them as the endpoint itself does.
template <typename Message, typename Sink>
void SubscribeDecoded(lcm::LCM* lcm, const std::string& channel, Sink* sink) {
  lcm_subscribe(
      lcm->getUnderlyingLCM(), channel.c_str(),
      [](const lcm_recv_buf_t* rbuf, const char*, void* user) {
        Message msg;
        if (msg.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) < 0) return;
        static_cast<Sink*>(user)->On(msg);
      },
      sink);
}

/// Collects what the endpoint publishes. Handlers run on the endpoint's receive thread.
struct Collector {
  std::mutex mutex;
  std::vector<ambdrop_lcm::sensor_readings_t> sensors;
  std::vector<ambdrop_lcm::emulator_state_t> states;

  void On(const ambdrop_lcm::sensor_readings_t& msg) {
    std::lock_guard lock(mutex);
    sensors.push_back(msg);
  }
  void On(const ambdrop_lcm::emulator_state_t& msg) {
    std::lock_guard lock(mutex);
    states.push_back(msg);
  }
  std::size_t sensor_count() {
    std::lock_guard lock(mutex);
    return sensors.size();
  }
  std::size_t state_count() {
    std::lock_guard lock(mutex);
    return states.size();
  }
  /// Before Start: handlers are then registered before the receive thread runs.
  void Subscribe(LcmEndpoint* endpoint) {
    SubscribeDecoded<ambdrop_lcm::sensor_readings_t>(&endpoint->lcm(),
                                                     endpoint->options().sensors_channel, this);
    SubscribeDecoded<ambdrop_lcm::emulator_state_t>(&endpoint->lcm(),
                                                    endpoint->options().state_channel, this);
  }
};

HilSensorReadings Readings(std::int64_t step) {
  HilSensorReadings r;
  r.utime_us = 1'700'000'000'000'000 + step;
  r.step_index = step;
  r.time_s = static_cast<double>(step) * 5e-6;
  r.sensor_count = 3;
  for (int i = 0; i < r.sensor_count; ++i) {
    r.position_m[i] = {1e-6 * (i + 1) + 1e-9 * static_cast<double>(step), -2e-6 * (i + 1)};
  }
  return r;
}

TEST(LcmEndpoint, CurrentsRoundTripIntoThePoppedRecord) {
  auto endpoint = MakeEndpoint();
  endpoint->Start();
  ambdrop_lcm::amb_currents_t msg = Currents(11);
  msg.axial_valid = 1;
  msg.axial_current_A = 0.5;
  ASSERT_EQ(endpoint->lcm().publish(endpoint->options().currents_channel, &msg), 0);

  HilCurrents got;
  ASSERT_TRUE(WaitFor([&] { return endpoint->TryPopCurrents(&got); }));
  EXPECT_EQ(got.utime_us, msg.utime);
  EXPECT_EQ(got.sequence, 11);
  EXPECT_EQ(got.amb_count, 2);
  EXPECT_EQ(got.current_A[0][0], msg.current_x_A[0]);  // exact: doubles travel bit for bit
  EXPECT_EQ(got.current_A[0][1], msg.current_y_A[0]);
  EXPECT_EQ(got.current_A[1][0], msg.current_x_A[1]);
  EXPECT_EQ(got.current_A[1][1], msg.current_y_A[1]);
  EXPECT_EQ(got.current_A[2][0], 0.0);
  EXPECT_TRUE(got.axial_valid);
  EXPECT_EQ(got.axial_current_A, 0.5);
  EXPECT_FALSE(endpoint->TryPopCurrents(&got));

  const LcmEndpointCounters c = endpoint->counters();
  EXPECT_EQ(c.currents_received, 1u);
  EXPECT_EQ(c.malformed_decode + c.malformed_range + c.malformed_non_finite, 0u);
}

// A controller that starts late, or restarts, asks for the plant description (any message on
// the request channel) and gets it again, the same text; before one was given, a request is
// counted and nothing is sent.
TEST(LcmEndpoint, ThePlantDescriptionGoesOutAtTheStartAndOnRequest) {
  auto endpoint = MakeEndpoint();
  std::mutex mutex;
  std::vector<ambdrop_lcm::plant_description_t> got;
  struct Handler {
    std::mutex* mutex;
    std::vector<ambdrop_lcm::plant_description_t>* got;
    void On(const lcm::ReceiveBuffer*, const std::string&,
            const ambdrop_lcm::plant_description_t* m) {
      std::lock_guard lock(*mutex);
      got->push_back(*m);
    }
  } handler{&mutex, &got};
  endpoint->lcm().subscribe(endpoint->options().plant_channel, &Handler::On, &handler);
  endpoint->Start();
  const auto received = [&] {
    std::lock_guard lock(mutex);
    return got.size();
  };
  const std::uint8_t anything[3] = {1, 2, 3};
  const auto request = [&] {
    ASSERT_EQ(endpoint->lcm().publish(endpoint->options().plant_request_channel, anything, 3), 0);
  };
  request();
  ASSERT_TRUE(WaitFor([&] { return endpoint->counters().plant_requests == 1; }));
  EXPECT_EQ(endpoint->counters().plant_published, 0u);
  const std::string json = R"({"schema_version": 1, "ambs": [{"index": 0, "name": "de"}]})";
  endpoint->PublishPlantDescription(json, 1);
  ASSERT_TRUE(WaitFor([&] { return received() == 1; }));
  request();
  ASSERT_TRUE(WaitFor([&] { return received() == 2; }));
  endpoint->Stop();
  for (const ambdrop_lcm::plant_description_t& m : got) {
    EXPECT_EQ(m.json, json);
    EXPECT_EQ(m.schema_version, 1);
    EXPECT_GT(m.utime, 0);
  }
  const LcmEndpointCounters c = endpoint->counters();
  EXPECT_EQ(c.plant_requests, 2u);
  EXPECT_EQ(c.plant_published, 2u);
}

TEST(LcmEndpoint, EntriesBeyondTheAmbCountAreIgnored) {
  auto endpoint = MakeEndpoint();
  endpoint->Start();
  ambdrop_lcm::amb_currents_t msg = Currents(0);
  msg.amb_count = 1;
  msg.current_x_A[3] = std::numeric_limits<double>::quiet_NaN();  // unused slot
  ASSERT_EQ(endpoint->lcm().publish(endpoint->options().currents_channel, &msg), 0);
  HilCurrents got;
  ASSERT_TRUE(WaitFor([&] { return endpoint->TryPopCurrents(&got); }));
  EXPECT_EQ(got.amb_count, 1);
  EXPECT_EQ(got.current_A[1][0], 0.0);
  EXPECT_EQ(got.current_A[3][0], 0.0);
}

TEST(LcmEndpoint, PartialFailureAndRestoreTriggers) {
  auto endpoint = MakeEndpoint();
  endpoint->Start();
  // AMB 1 loses its y coils, then gets them back; then the full power failure.
  const ambdrop_lcm::trigger_t sent[] = {
      Trigger(false, 0b0010, ambdrop_lcm::trigger_t::AXIS_Y),
      Trigger(true, 0b0010, ambdrop_lcm::trigger_t::AXIS_Y),
      Trigger(false, ambdrop_lcm::trigger_t::ALL_AMBS, ambdrop_lcm::trigger_t::ALL_AXES)};
  for (const auto& msg : sent) {
    ASSERT_EQ(endpoint->lcm().publish(endpoint->options().trigger_channel, &msg), 0);
  }
  std::vector<HilTrigger> got;
  ASSERT_TRUE(WaitFor([&] {
    HilTrigger t;
    while (endpoint->TryPopTrigger(&t)) got.push_back(t);
    return got.size() == 3;
  }));
  EXPECT_FALSE(got[0].power_on);
  EXPECT_EQ(got[0].amb_mask, 0b0010);
  EXPECT_EQ(got[0].axis_mask, kAxisY);
  EXPECT_TRUE(got[1].power_on);
  EXPECT_EQ(got[1].amb_mask, 0b0010);
  EXPECT_FALSE(got[2].power_on);
  EXPECT_EQ(got[2].amb_mask, kAllAmbs);
  EXPECT_EQ(got[2].axis_mask, kAllAxes);
  EXPECT_EQ(got[2].utime_us, 42);
  EXPECT_EQ(got[2].sequence, 7);
  EXPECT_EQ(endpoint->counters().triggers_received, 3u);
}

TEST(LcmEndpoint, PushedSensorsAndStateArePublished) {
  auto endpoint = MakeEndpoint();
  Collector collector;
  collector.Subscribe(endpoint.get());
  endpoint->Start();

  for (int step = 0; step < 3; ++step) ASSERT_TRUE(endpoint->TryPushSensors(Readings(step)));
  HilEmulatorState state;
  state.utime_us = 99;
  state.step_index = 40000;
  state.time_s = 0.2;
  state.power_on = false;
  state.powered_axes = {kAllAxes, kAxisX, 0, 0};
  state.spin_speed_rad_s = 680.678;
  state.spin_angle_rad = 1234.5;
  state.mode_count = 12;
  for (int i = 0; i < state.mode_count; ++i) {
    state.q[i] = 1e-5 * (i + 1);
    state.q_dot[i] = -1e-3 * (i + 1);
  }
  state.tdb_count = 2;
  state.tdb[1] = {.normal_force_N = 1500.0,
                  .tangential_force_N = 150.0,
                  .penetration_m = 2e-6,
                  .race_speed_rad_s = 300.0,
                  .journal_xy_m = {1e-4, -2.5e-4}};
  state.fault_count = 3;
  ASSERT_TRUE(endpoint->TryPushState(state));

  ASSERT_TRUE(
      WaitFor([&] { return collector.sensor_count() == 3 && collector.state_count() == 1; }));
  const LcmEndpointCounters c = endpoint->counters();
  EXPECT_EQ(c.sensors_published, 3u);
  EXPECT_EQ(c.states_published, 1u);
  EXPECT_EQ(c.publish_errors, 0u);

  std::lock_guard lock(collector.mutex);
  for (int step = 0; step < 3; ++step) {
    const HilSensorReadings want = Readings(step);
    const ambdrop_lcm::sensor_readings_t& got = collector.sensors[step];
    EXPECT_EQ(got.step_index, step);
    EXPECT_EQ(got.utime, want.utime_us);
    EXPECT_EQ(got.time_s, want.time_s);
    EXPECT_EQ(got.sensor_count, 3);
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(got.x_m[i], want.position_m[i][0]);
      EXPECT_EQ(got.y_m[i], want.position_m[i][1]);
    }
    EXPECT_EQ(got.x_m[3], 0.0);
    EXPECT_EQ(got.counts_valid, 0);
  }
  const ambdrop_lcm::emulator_state_t& got = collector.states[0];
  EXPECT_EQ(got.step_index, 40000);
  EXPECT_EQ(got.power_on, 0);
  EXPECT_EQ(got.powered_axes[0], kAllAxes);
  EXPECT_EQ(got.powered_axes[1], kAxisX);
  EXPECT_EQ(got.spin_speed_rad_s, 680.678);
  EXPECT_EQ(got.mode_count, 12);
  EXPECT_EQ(got.q[11], state.q[11]);
  EXPECT_EQ(got.q_dot[0], state.q_dot[0]);
  EXPECT_EQ(got.q[12], 0.0);
  EXPECT_EQ(got.tdb_count, 2);
  EXPECT_EQ(got.tdb_normal_force_N[1], 1500.0);
  EXPECT_EQ(got.tdb_penetration_m[1], 2e-6);
  EXPECT_EQ(got.tdb_journal_y_m[1], -2.5e-4);
  EXPECT_EQ(got.fault_count, 3);
}

TEST(LcmEndpoint, MalformedMessagesAreCountedAndDropped) {
  auto endpoint = MakeEndpoint();
  endpoint->Start();
  lcm::LCM& bus = endpoint->lcm();
  const std::string& currents = endpoint->options().currents_channel;
  const std::string& trigger = endpoint->options().trigger_channel;

  // Not decodable: junk bytes, an empty payload, a truncated message, a trigger_t on the
  // currents channel, and a valid message with trailing bytes.
  const std::uint8_t junk[] = {0xde, 0xad, 0xbe, 0xef, 1, 2, 3, 4, 5, 6, 7, 8, 9};
  ASSERT_EQ(bus.publish(currents, junk, sizeof(junk)), 0);
  ASSERT_EQ(bus.publish(currents, junk, 0), 0);
  const ambdrop_lcm::amb_currents_t good = Currents(1);
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(good.getEncodedSize()) + 1, 0);
  ASSERT_EQ(good.encode(bytes.data(), 0, good.getEncodedSize()), good.getEncodedSize());
  ASSERT_EQ(bus.publish(currents, bytes.data(), bytes.size() - 9), 0);
  ASSERT_EQ(bus.publish(currents, bytes.data(), bytes.size()), 0);
  const ambdrop_lcm::trigger_t wrong_type = Trigger(false, 1, 1);
  ASSERT_EQ(bus.publish(currents, &wrong_type), 0);
  // Out of range: AMB count, empty and oversized masks.
  ambdrop_lcm::amb_currents_t too_many = Currents(2);
  too_many.amb_count = 5;
  ASSERT_EQ(bus.publish(currents, &too_many), 0);
  too_many.amb_count = -1;
  ASSERT_EQ(bus.publish(currents, &too_many), 0);
  const ambdrop_lcm::trigger_t no_amb = Trigger(false, 0, 1);
  const ambdrop_lcm::trigger_t amb_4 = Trigger(false, 0b10000, 1);
  const ambdrop_lcm::trigger_t no_axis = Trigger(false, 1, 0);
  const ambdrop_lcm::trigger_t axis_8 = Trigger(false, 1, 8);
  for (const auto* msg : {&no_amb, &amb_4, &no_axis, &axis_8}) {
    ASSERT_EQ(bus.publish(trigger, msg), 0);
  }
  // Non-finite currents in used slots.
  ambdrop_lcm::amb_currents_t nan = Currents(3);
  nan.current_y_A[1] = std::numeric_limits<double>::quiet_NaN();
  ASSERT_EQ(bus.publish(currents, &nan), 0);
  ambdrop_lcm::amb_currents_t inf = Currents(4);
  inf.axial_valid = 1;
  inf.axial_current_A = -std::numeric_limits<double>::infinity();
  ASSERT_EQ(bus.publish(currents, &inf), 0);
  // The endpoint still works afterwards.
  ASSERT_EQ(bus.publish(currents, &good), 0);

  HilCurrents got;
  ASSERT_TRUE(WaitFor([&] { return endpoint->TryPopCurrents(&got); }));
  EXPECT_EQ(got.sequence, 1);
  EXPECT_FALSE(endpoint->TryPopCurrents(&got));
  HilTrigger ignored;
  EXPECT_FALSE(endpoint->TryPopTrigger(&ignored));
  const LcmEndpointCounters c = endpoint->counters();
  EXPECT_EQ(c.malformed_decode, 5u);
  EXPECT_EQ(c.malformed_range, 6u);
  EXPECT_EQ(c.malformed_non_finite, 2u);
  EXPECT_EQ(c.currents_received, 1u);
  EXPECT_EQ(c.triggers_received, 0u);
}

TEST(LcmEndpoint, FullIncomingRingDropsTheNewestAndCounts) {
  auto endpoint = MakeEndpoint();
  endpoint->Start();
  constexpr int kExtra = 10;
  constexpr int kSent = static_cast<int>(LcmEndpoint::kCurrentsCapacity) + kExtra;
  for (int i = 0; i < kSent; ++i) {
    const ambdrop_lcm::amb_currents_t msg = Currents(i);
    ASSERT_EQ(endpoint->lcm().publish(endpoint->options().currents_channel, &msg), 0);
  }
  // Nobody pops until all have been handled.
  ASSERT_TRUE(WaitFor([&] { return endpoint->counters().currents_received == kSent; }));
  EXPECT_EQ(endpoint->counters().currents_ring_full, static_cast<std::uint64_t>(kExtra));
  HilCurrents got;
  for (int i = 0; i < static_cast<int>(LcmEndpoint::kCurrentsCapacity); ++i) {
    ASSERT_TRUE(endpoint->TryPopCurrents(&got));
    EXPECT_EQ(got.sequence, i);  // the oldest are kept, in order
  }
  EXPECT_FALSE(endpoint->TryPopCurrents(&got));
  EXPECT_EQ(endpoint->counters().currents_sequence_jumps, 0u);
}

TEST(LcmEndpoint, FullOutgoingRingRefusesAndCounts) {
  auto endpoint = MakeEndpoint();
  // Not started: the publish thread does not drain, so the ring fills.
  constexpr int kExtra = 5;
  int refused = 0;
  for (int i = 0; i < static_cast<int>(LcmEndpoint::kSensorsCapacity) + kExtra; ++i) {
    if (!endpoint->TryPushSensors(Readings(i))) ++refused;
  }
  EXPECT_EQ(refused, kExtra);
  EXPECT_EQ(endpoint->counters().sensors_ring_full, static_cast<std::uint64_t>(kExtra));
  // Stop publishes what was queued before it returns.
  endpoint->Start();
  endpoint->Stop();
  EXPECT_EQ(endpoint->counters().sensors_published, LcmEndpoint::kSensorsCapacity);
}

TEST(LcmEndpoint, RecordsWithCountsOutOfRangeAreRejected) {
  auto endpoint = MakeEndpoint();
  endpoint->Start();
  HilSensorReadings bad = Readings(0);
  bad.sensor_count = kMaxSensors + 1;
  ASSERT_TRUE(endpoint->TryPushSensors(bad));
  HilEmulatorState state;
  state.mode_count = kMaxModes + 1;
  ASSERT_TRUE(endpoint->TryPushState(state));
  endpoint->Stop();
  const LcmEndpointCounters c = endpoint->counters();
  EXPECT_EQ(c.publish_rejected, 2u);
  EXPECT_EQ(c.sensors_published + c.states_published, 0u);
}

TEST(LcmEndpoint, SequenceJumpsAreCounted) {
  auto endpoint = MakeEndpoint();
  endpoint->Start();
  for (std::int64_t seq : {0, 1, 2, 5, 6, 3}) {  // a gap of two, then a step back
    const ambdrop_lcm::amb_currents_t msg = Currents(seq);
    ASSERT_EQ(endpoint->lcm().publish(endpoint->options().currents_channel, &msg), 0);
  }
  ASSERT_TRUE(WaitFor([&] { return endpoint->counters().currents_received == 6; }));
  EXPECT_EQ(endpoint->counters().currents_sequence_jumps, 2u);
}

TEST(LcmEndpoint, PollingPublisherAlsoDelivers) {
  LcmEndpointOptions options;
  options.publish_poll_period = std::chrono::microseconds(200);
  auto endpoint = MakeEndpoint(options);
  Collector collector;
  collector.Subscribe(endpoint.get());
  endpoint->Start();
  for (int step = 0; step < 20; ++step) ASSERT_TRUE(endpoint->TryPushSensors(Readings(step)));
  ASSERT_TRUE(WaitFor([&] { return collector.sensor_count() == 20; }));
}

// The real-time side of a running endpoint, with traffic in both directions, never allocates.
TEST(LcmEndpoint, RealTimeSideDoesNotAllocate) {
  auto endpoint = MakeEndpoint();
  endpoint->Start();
  std::atomic<bool> done{false};
  std::thread controller([&] {
    for (std::int64_t seq = 0; !done.load(); ++seq) {
      const ambdrop_lcm::amb_currents_t msg = Currents(seq);
      endpoint->lcm().publish(endpoint->options().currents_channel, &msg);
      std::this_thread::sleep_for(std::chrono::microseconds(100));
    }
  });

  HilSensorReadings readings = Readings(0);
  HilEmulatorState state;
  HilCurrents currents;
  HilTrigger trigger;
  int popped = 0;
  std::int64_t allocations = 0;
  {
    testing::MallocGuard guard;
    // At least 200 ms, and on until a message has come through (under TSan on a loaded machine
    // none did in 200 ms), at most 10 s.
    const auto start = std::chrono::steady_clock::now();
    while (std::chrono::steady_clock::now() < start + milliseconds(200) ||
           (popped == 0 && std::chrono::steady_clock::now() < start + milliseconds(10000))) {
      while (endpoint->TryPopCurrents(&currents)) ++popped;
      endpoint->TryPopTrigger(&trigger);
      ++readings.step_index;
      endpoint->TryPushSensors(readings);
      if (readings.step_index % 10 == 0) endpoint->TryPushState(state);
      std::this_thread::sleep_for(std::chrono::microseconds(50));
    }
    allocations = guard.allocations();
  }
  done = true;
  controller.join();
  endpoint->Stop();
  EXPECT_EQ(allocations, 0);
  EXPECT_GT(popped, 0);
  EXPECT_GT(endpoint->counters().sensors_published, 0u);
}

// Scheduling policy (field 41) and real-time priority (field 40) of this process's thread
// named `name`, from /proc/self/task/TID/stat; {-1, -1} when there is no such thread.
std::pair<int, int> ThreadPolicyAndPriority(const std::string& name) {
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task")) {
    std::ifstream comm(task.path() / "comm");
    std::string thread_name;
    std::getline(comm, thread_name);
    if (thread_name != name) continue;
    std::ifstream stat_file(task.path() / "stat");
    const std::string stat((std::istreambuf_iterator<char>(stat_file)),
                           std::istreambuf_iterator<char>());
    std::istringstream fields(stat.substr(stat.rfind(')') + 2));  // field 3 on
    std::vector<std::string> f{std::istream_iterator<std::string>(fields), {}};
    if (f.size() < 39) return {-1, -1};
    return {std::stoi(f[41 - 3]), std::stoi(f[40 - 3])};
  }
  return {-1, -1};
}

TEST(LcmEndpoint, IoThreadsRunUnderSchedFifoWhenRaised) {
  auto endpoint = MakeEndpoint();
  EXPECT_NE(endpoint->RaiseIoThreads(10), "");  // no threads before Start
  endpoint->Start();
  const std::string refused = endpoint->RaiseIoThreads(10);
  if (!refused.empty()) {
    endpoint->Stop();
    GTEST_SKIP() << "SCHED_FIFO needs root or CAP_SYS_NICE here: " << refused;
  }
  for (const char* name : {"ambdrop-lcm-rx", "ambdrop-lcm-tx"}) {
    const auto [policy, priority] = ThreadPolicyAndPriority(name);
    EXPECT_EQ(policy, SCHED_FIFO) << name;
    EXPECT_EQ(priority, 10) << name;
  }
  endpoint->Stop();
}

TEST(LcmEndpoint, RejectsBadSetup) {
  LcmEndpointOptions same;
  same.sensors_channel = same.currents_channel;
  EXPECT_THROW(MakeEndpoint(same), std::invalid_argument);
  LcmEndpointOptions empty;
  empty.trigger_channel.clear();
  EXPECT_THROW(MakeEndpoint(empty), std::invalid_argument);
  LcmEndpointOptions bad_url;
  bad_url.url = "nosuchprovider://";
  EXPECT_THROW(std::make_unique<LcmEndpoint>(bad_url), std::runtime_error);
  auto endpoint = MakeEndpoint();
  endpoint->Start();
  EXPECT_THROW(endpoint->Start(), std::logic_error);
  endpoint->Stop();
  endpoint->Stop();  // idempotent
  EXPECT_FALSE(endpoint->running());
}

}  // namespace
}  // namespace ambdrop::lcm_transport_test
