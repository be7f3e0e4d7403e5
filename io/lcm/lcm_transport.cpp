#include "io/lcm/lcm_transport.hpp"

#include <pthread.h>
#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <ambdrop_lcm/amb_currents_t.hpp>
#include <ambdrop_lcm/emulator_state_t.hpp>
#include <ambdrop_lcm/plant_description_t.hpp>
#include <ambdrop_lcm/power_event_t.hpp>
#include <ambdrop_lcm/sensor_readings_t.hpp>
#include <ambdrop_lcm/trigger_t.hpp>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iterator>
#include <lcm/lcm-cpp.hpp>
#include <stdexcept>
#include <utility>

namespace ambdrop {

// The wire arrays are sized by literals in the .lcm files (lcm-gen takes no named constants):
// they must match the compile-time capacities.
static_assert(sizeof(ambdrop_lcm::amb_currents_t::current_x_A) / sizeof(double) == kMaxAmbs);
static_assert(sizeof(ambdrop_lcm::sensor_readings_t::x_m) / sizeof(double) == kMaxSensors);
static_assert(sizeof(ambdrop_lcm::emulator_state_t::q) / sizeof(double) == kMaxModes);
static_assert(sizeof(ambdrop_lcm::emulator_state_t::powered_axes) == kMaxAmbs);
static_assert(sizeof(ambdrop_lcm::emulator_state_t::tdb_normal_force_N) / sizeof(double) ==
              kMaxTdbs);
static_assert(ambdrop_lcm::trigger_t::AXIS_X == kAxisX &&
              ambdrop_lcm::trigger_t::AXIS_Y == kAxisY &&
              ambdrop_lcm::trigger_t::AXIS_AXIAL == kAxisAxial &&
              ambdrop_lcm::trigger_t::ALL_AXES == kAllAxes &&
              ambdrop_lcm::trigger_t::ALL_AMBS == kAllAmbs);

struct LcmEndpoint::Callbacks {
  static void Currents(const lcm_recv_buf_t* rbuf, const char* /*channel*/, void* user) {
    static_cast<LcmEndpoint*>(user)->HandleCurrents(rbuf->data, rbuf->data_size);
  }
  static void Trigger(const lcm_recv_buf_t* rbuf, const char* /*channel*/, void* user) {
    static_cast<LcmEndpoint*>(user)->HandleTrigger(rbuf->data, rbuf->data_size);
  }
  static void PlantRequest(const lcm_recv_buf_t*, const char* /*channel*/, void* user) {
    static_cast<LcmEndpoint*>(user)->HandlePlantRequest();
  }
};

namespace {

/// Decodes a whole payload: a short, long or foreign-type payload is a failure. lcm-cpp's typed
/// handlers would print to stderr and drop silently; we count instead.
template <typename Message>
bool DecodeExactly(const void* data, std::size_t size, Message* msg) {
  if (size > static_cast<std::size_t>(INT_MAX)) return false;
  const int length = static_cast<int>(size);
  return msg->decode(data, 0, length) == length;
}

/// Encodes into the preallocated buffer (no per-message heap use) and publishes raw bytes.
template <typename Message>
bool EncodeAndPublish(const Message& msg, const std::string& channel, lcm::LCM* lcm,
                      std::vector<std::uint8_t>* buffer) {
  const int size = static_cast<int>(buffer->size());
  if (msg.encode(buffer->data(), 0, size) != size) return false;
  return lcm->publish(channel, buffer->data(), static_cast<unsigned int>(size)) == 0;
}

/// This process's tasks (threads), by id, sorted.
std::vector<pid_t> TaskIds() {
  std::vector<pid_t> ids;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator("/proc/self/task", error)) {
    const std::string name = entry.path().filename().string();
    char* end = nullptr;
    const long id = std::strtol(name.c_str(), &end, 10);
    if (end != name.c_str() && *end == '\0' && id > 0) ids.push_back(static_cast<pid_t>(id));
  }
  std::sort(ids.begin(), ids.end());
  return ids;
}

void NameThread(std::thread* thread, const char* name) {
  // Best effort: names show in top/ps/gdb and help when pinning threads on a HIL host.
  pthread_setname_np(thread->native_handle(), name);
}

}  // namespace

LcmEndpoint::LcmEndpoint(LcmEndpointOptions options) : options_(std::move(options)) {
  const std::string* channels[] = {&options_.currents_channel,     &options_.trigger_channel,
                                   &options_.sensors_channel,      &options_.state_channel,
                                   &options_.power_channel,        &options_.plant_channel,
                                   &options_.plant_request_channel};
  for (int i = 0; i < 7; ++i) {
    if (channels[i]->empty()) throw std::invalid_argument("LCM channel names must not be empty");
    // A shared name would loop our own output back in as (malformed) input.
    for (int j = 0; j < i; ++j) {
      if (*channels[i] == *channels[j]) {
        throw std::invalid_argument("LCM channel '" + *channels[i] + "' is used twice");
      }
    }
  }
  if (options_.receive_timeout.count() <= 0) {
    throw std::invalid_argument("LCM receive_timeout must be > 0 ms");
  }

  const std::vector<pid_t> tasks_before = TaskIds();
  lcm_ = std::make_unique<lcm::LCM>(options_.url);
  if (!lcm_->good()) {
    // udpm's creation self-test fails when multicast has no route (e.g. loopback only).
    throw std::runtime_error("LCM: cannot open URL '" + options_.url +
                             "': bad URL, or udpm multicast is not routable (on one host: "
                             "ip route add 239.0.0.0/8 dev lo)");
  }
  lcm_t* c_lcm = lcm_->getUnderlyingLCM();
  // Raw C subscriptions: we decode ourselves into stack objects (fixed-size types, no heap) and
  // count failures.
  if (lcm_subscribe(c_lcm, options_.currents_channel.c_str(), &Callbacks::Currents, this) ==
          nullptr ||
      lcm_subscribe(c_lcm, options_.trigger_channel.c_str(), &Callbacks::Trigger, this) ==
          nullptr ||
      lcm_subscribe(c_lcm, options_.plant_request_channel.c_str(), &Callbacks::PlantRequest,
                    this) == nullptr) {
    throw std::runtime_error("LCM: cannot subscribe");
  }
  const std::vector<pid_t> tasks_after = TaskIds();
  std::set_difference(tasks_after.begin(), tasks_after.end(), tasks_before.begin(),
                      tasks_before.end(), std::back_inserter(lcm_library_tasks_));

  // Encoded sizes are constant for fixed-size types: size the buffers once.
  sensors_buffer_.resize(
      static_cast<std::size_t>(ambdrop_lcm::sensor_readings_t{}.getEncodedSize()));
  state_buffer_.resize(static_cast<std::size_t>(ambdrop_lcm::emulator_state_t{}.getEncodedSize()));
  power_buffer_.resize(static_cast<std::size_t>(ambdrop_lcm::power_event_t{}.getEncodedSize()));
}

LcmEndpoint::~LcmEndpoint() {
  Stop();
}

void LcmEndpoint::Start() {
  if (running_) throw std::logic_error("LcmEndpoint::Start: already started");
  stop_.store(false, std::memory_order_release);
  receive_thread_ = std::thread([this] { ReceiveLoop(); });
  try {
    publish_thread_ = std::thread([this] { PublishLoop(); });
  } catch (...) {
    stop_.store(true, std::memory_order_release);
    receive_thread_.join();
    throw;
  }
  NameThread(&receive_thread_, "ambdrop-lcm-rx");
  NameThread(&publish_thread_, "ambdrop-lcm-tx");
  running_ = true;
}

std::string LcmEndpoint::RaiseIoThreads(int priority, int loop_cpu) {
  if (!running_) return "the endpoint is not started";
  // Off the loop's CPU: a saturated loop there would starve them, and the kernel's RT
  // throttling, counted per CPU, would stop them with it.
  cpu_set_t others;
  CPU_ZERO(&others);
  const long cpus = sysconf(_SC_NPROCESSORS_ONLN);
  for (int c = 0; c < cpus && c < CPU_SETSIZE; ++c) {
    if (c != loop_cpu) CPU_SET(c, &others);
  }
  const bool move = loop_cpu >= 0 && CPU_COUNT(&others) > 0;
  sched_param param{};
  param.sched_priority = priority;
  for (std::thread* t : {&receive_thread_, &publish_thread_}) {
    if (move) {
      const int error = pthread_setaffinity_np(t->native_handle(), sizeof(others), &others);
      if (error != 0)
        return std::string("moving off CPU ") + std::to_string(loop_cpu) +
               " refused: " + std::strerror(error);
    }
    const int error = pthread_setschedparam(t->native_handle(), SCHED_FIFO, &param);
    if (error != 0) return std::string("SCHED_FIFO refused: ") + std::strerror(error);
  }
  // udpm's reading thread carries every answer to the receive thread: left at normal priority
  // it was the loop's bottleneck (`ambdrop hil` at 2 kHz with --record beside 8 busy loops: 4
  // runs of 5 touched down while levitated; with it raised too, tests/cli/hil_lcm_netns.sh
  // passed 6 times of 6 there).
  for (const pid_t task : lcm_library_tasks_) {
    if (move && sched_setaffinity(task, sizeof(others), &others) != 0 && errno != ESRCH) {
      return std::string("moving LCM's thread off CPU ") + std::to_string(loop_cpu) +
             " refused: " + std::strerror(errno);
    }
    if (sched_setscheduler(task, SCHED_FIFO, &param) != 0 && errno != ESRCH) {
      return std::string("SCHED_FIFO for LCM's thread refused: ") + std::strerror(errno);
    }
  }
  return {};
}

void LcmEndpoint::Stop() noexcept {
  if (!running_) return;
  stop_.store(true, std::memory_order_release);
  publish_signal_.fetch_add(1, std::memory_order_release);
  publish_signal_.notify_all();
  publish_thread_.join();
  receive_thread_.join();
  running_ = false;
}

LcmEndpointCounters LcmEndpoint::counters() const noexcept {
  constexpr auto kRelaxed = std::memory_order_relaxed;
  LcmEndpointCounters c;
  c.currents_received = currents_received_.load(std::memory_order_acquire);
  c.triggers_received = triggers_received_.load(kRelaxed);
  c.malformed_decode = malformed_decode_.load(kRelaxed);
  c.malformed_range = malformed_range_.load(kRelaxed);
  c.malformed_non_finite = malformed_non_finite_.load(kRelaxed);
  c.malformed_current_bound = malformed_current_bound_.load(kRelaxed);
  c.currents_sequence_jumps = currents_sequence_jumps_.load(kRelaxed);
  c.currents_ring_full = currents_.dropped();
  c.triggers_ring_full = triggers_.dropped();
  c.sensors_published = sensors_published_.load(kRelaxed);
  c.states_published = states_published_.load(kRelaxed);
  c.sensors_ring_full = sensors_.dropped();
  c.states_ring_full = states_.dropped();
  c.power_events_published = power_events_published_.load(kRelaxed);
  c.power_events_ring_full = power_.dropped();
  c.plant_requests = plant_requests_.load(kRelaxed);
  c.plant_published = plant_published_.load(kRelaxed);
  c.publish_rejected = publish_rejected_.load(kRelaxed);
  c.publish_errors = publish_errors_.load(kRelaxed);
  c.receive_errors = receive_errors_.load(kRelaxed);
  return c;
}

// --- Receive thread ---------------------------------------------------------------------------

void LcmEndpoint::ReceiveLoop() noexcept {
  const int timeout_ms = static_cast<int>(options_.receive_timeout.count());
  while (!stop_.load(std::memory_order_acquire)) {
    if (lcm_->handleTimeout(timeout_ms) < 0) {
      receive_errors_.fetch_add(1, std::memory_order_relaxed);
      // Do not spin on a broken socket; keep trying, a transient error may clear.
      std::this_thread::sleep_for(options_.receive_timeout);
    }
  }
}

void LcmEndpoint::HandleCurrents(const void* data, std::size_t size) noexcept {
  ambdrop_lcm::amb_currents_t msg;
  if (!DecodeExactly(data, size, &msg)) {
    malformed_decode_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  if (msg.amb_count < 0 || msg.amb_count > kMaxAmbs) {
    malformed_range_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  HilCurrents currents;
  // Stamped as decoded: the record's arrival time of the currents (a run record written 0 here).
  currents.receive_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                            std::chrono::steady_clock::now().time_since_epoch())
                            .count();
  currents.utime_us = msg.utime;
  currents.sequence = msg.sequence;
  currents.amb_count = msg.amb_count;
  bool finite = true;
  for (int i = 0; i < msg.amb_count; ++i) {
    currents.current_A[i] = {msg.current_x_A[i], msg.current_y_A[i]};
    finite = finite && std::isfinite(msg.current_x_A[i]) && std::isfinite(msg.current_y_A[i]);
  }
  currents.axial_valid = msg.axial_valid != 0;
  if (currents.axial_valid) {
    currents.axial_current_A = msg.axial_current_A;
    finite = finite && std::isfinite(msg.axial_current_A);
  }
  // A NaN current would poison the state within one step: never let one through.
  if (!finite) {
    malformed_non_finite_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  for (int i = 0; i < msg.amb_count; ++i) {
    const double bound = options_.current_bound_A[i];
    if (std::abs(msg.current_x_A[i]) > bound || std::abs(msg.current_y_A[i]) > bound) {
      malformed_current_bound_.fetch_add(1, std::memory_order_relaxed);
      return;
    }
  }

  if (have_sequence_ && msg.sequence != last_sequence_ + 1) {
    currents_sequence_jumps_.fetch_add(1, std::memory_order_relaxed);
  }
  have_sequence_ = true;
  last_sequence_ = msg.sequence;
  currents_.TryPush(currents);  // full: dropped and counted by the ring
  // Counted once pushed, with release: whoever reads the count (acquire) can pop the sample.
  // Counted before the push, a reader under TSan saw the count and found the ring empty.
  currents_received_.fetch_add(1, std::memory_order_release);
}

void LcmEndpoint::HandleTrigger(const void* data, std::size_t size) noexcept {
  ambdrop_lcm::trigger_t msg;
  if (!DecodeExactly(data, size, &msg)) {
    malformed_decode_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  const auto amb_mask = static_cast<std::uint8_t>(msg.amb_mask);
  const auto axis_mask = static_cast<std::uint8_t>(msg.axis_mask);
  // A mask naming nothing, or a slot that does not exist, is a sender bug: acting on part of it
  // would emulate a failure nobody asked for.
  if (amb_mask == 0 || (amb_mask & ~kAllAmbs) != 0 || axis_mask == 0 ||
      (axis_mask & ~kAllAxes) != 0) {
    malformed_range_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  HilTrigger trigger;
  trigger.utime_us = msg.utime;
  trigger.sequence = msg.sequence;
  trigger.power_on = msg.power_on != 0;
  trigger.amb_mask = amb_mask;
  trigger.axis_mask = axis_mask;
  triggers_received_.fetch_add(1, std::memory_order_relaxed);
  triggers_.TryPush(trigger);  // full: dropped and counted by the ring
}

// --- Publish thread ---------------------------------------------------------------------------

void LcmEndpoint::PublishLoop() noexcept {
  HilSensorReadings readings;
  HilEmulatorState state;
  HilPowerEvent power;
  while (true) {
    // Read the signal before draining: a push after the drain bumps it and the wait returns.
    const std::uint32_t seen = publish_signal_.load(std::memory_order_acquire);
    const bool stopping = stop_.load(std::memory_order_acquire);
    while (sensors_.TryPop(&readings)) PublishSensors(readings);
    while (power_.TryPop(&power)) PublishPowerEvent(power);
    while (states_.TryPop(&state)) PublishState(state);
    if (stopping) return;  // everything pushed before Stop has been published
    if (options_.publish_poll_period.count() > 0) {
      std::this_thread::sleep_for(options_.publish_poll_period);
    } else {
      publish_signal_.wait(seen, std::memory_order_acquire);
    }
  }
}

void LcmEndpoint::PublishSensors(const HilSensorReadings& readings) noexcept {
  if (readings.sensor_count < 0 || readings.sensor_count > kMaxSensors) {
    publish_rejected_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  ambdrop_lcm::sensor_readings_t msg{};
  msg.utime = readings.utime_us;
  msg.step_index = readings.step_index;
  msg.time_s = readings.time_s;
  msg.sensor_count = static_cast<std::int8_t>(readings.sensor_count);
  msg.counts_valid = readings.counts_valid ? 1 : 0;
  // Entries beyond the count go out as zero, as the message definition promises.
  for (int i = 0; i < readings.sensor_count; ++i) {
    msg.x_m[i] = readings.position_m[i][0];
    msg.y_m[i] = readings.position_m[i][1];
    if (readings.counts_valid) {
      msg.x_counts[i] = readings.counts[i][0];
      msg.y_counts[i] = readings.counts[i][1];
    }
  }
  const bool ok = EncodeAndPublish(msg, options_.sensors_channel, lcm_.get(), &sensors_buffer_);
  (ok ? sensors_published_ : publish_errors_).fetch_add(1, std::memory_order_relaxed);
}

void LcmEndpoint::PublishState(const HilEmulatorState& state) noexcept {
  if (state.mode_count < 0 || state.mode_count > kMaxModes || state.tdb_count < 0 ||
      state.tdb_count > kMaxTdbs) {
    publish_rejected_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  ambdrop_lcm::emulator_state_t msg{};
  msg.utime = state.utime_us;
  msg.step_index = state.step_index;
  msg.time_s = state.time_s;
  msg.power_on = state.power_on ? 1 : 0;
  for (int i = 0; i < kMaxAmbs; ++i) {
    msg.powered_axes[i] = static_cast<std::int8_t>(state.powered_axes[i] & kAllAxes);
  }
  msg.spin_speed_rad_s = state.spin_speed_rad_s;
  msg.spin_angle_rad = state.spin_angle_rad;
  msg.mode_count = static_cast<std::int8_t>(state.mode_count);
  for (int i = 0; i < state.mode_count; ++i) {
    msg.q[i] = state.q[i];
    msg.q_dot[i] = state.q_dot[i];
  }
  msg.tdb_count = static_cast<std::int8_t>(state.tdb_count);
  for (int i = 0; i < state.tdb_count; ++i) {
    const HilTdbState& tdb = state.tdb[i];
    msg.tdb_normal_force_N[i] = tdb.normal_force_N;
    msg.tdb_tangential_force_N[i] = tdb.tangential_force_N;
    msg.tdb_penetration_m[i] = tdb.penetration_m;
    msg.tdb_race_speed_rad_s[i] = tdb.race_speed_rad_s;
    msg.tdb_journal_x_m[i] = tdb.journal_xy_m[0];
    msg.tdb_journal_y_m[i] = tdb.journal_xy_m[1];
  }
  msg.fault_count = state.fault_count;
  const bool ok = EncodeAndPublish(msg, options_.state_channel, lcm_.get(), &state_buffer_);
  (ok ? states_published_ : publish_errors_).fetch_add(1, std::memory_order_relaxed);
}

void LcmEndpoint::PublishPowerEvent(const HilPowerEvent& event) noexcept {
  ambdrop_lcm::power_event_t msg{};
  msg.utime = event.utime_us;
  msg.sequence = event.sequence;
  msg.step_index = event.step_index;
  msg.time_s = event.time_s;
  msg.power_on = event.power_on ? 1 : 0;
  msg.amb_mask = static_cast<std::int8_t>(event.amb_mask & kAllAmbs);
  msg.axis_mask = static_cast<std::int8_t>(event.axis_mask & kAllAxes);
  msg.motor = event.motor ? 1 : 0;
  for (int i = 0; i < kMaxAmbs; ++i) {
    msg.powered_axes[i] = static_cast<std::int8_t>(event.powered_axes[i] & kAllAxes);
  }
  const bool ok = EncodeAndPublish(msg, options_.power_channel, lcm_.get(), &power_buffer_);
  (ok ? power_events_published_ : publish_errors_).fetch_add(1, std::memory_order_relaxed);
}

// --- Plant description (setup and receive threads, never the real-time one) -----------------

void LcmEndpoint::PublishPlantDescription(std::string json, int schema_version) {
  {
    std::lock_guard<std::mutex> lock(plant_mutex_);
    plant_json_ = std::move(json);
    plant_schema_version_ = schema_version;
  }
  PublishPlant();
}

void LcmEndpoint::HandlePlantRequest() noexcept {
  plant_requests_.fetch_add(1, std::memory_order_relaxed);
  PublishPlant();
}

void LcmEndpoint::PublishPlant() noexcept {
  try {
    ambdrop_lcm::plant_description_t msg;
    {
      std::lock_guard<std::mutex> lock(plant_mutex_);
      if (plant_json_.empty()) return;
      msg.json = plant_json_;
      msg.schema_version = plant_schema_version_;
    }
    msg.utime = std::chrono::duration_cast<std::chrono::microseconds>(
                    std::chrono::system_clock::now().time_since_epoch())
                    .count();
    const bool ok = lcm_->publish(options_.plant_channel, &msg) == 0;
    (ok ? plant_published_ : publish_errors_).fetch_add(1, std::memory_order_relaxed);
  } catch (...) {
    // A description too large for the transport, or no memory: counted, the run goes on.
    publish_errors_.fetch_add(1, std::memory_order_relaxed);
  }
}

}  // namespace ambdrop
