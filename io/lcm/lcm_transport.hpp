#pragma once
#include <sys/types.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "io/lcm/lcm_records.hpp"
#include "rt_core/spsc_ring.hpp"

namespace lcm {
class LCM;
}

namespace ambdrop {

/// Where and how an LcmEndpoint talks.
struct LcmEndpointOptions {
  /// LCM URL. ttl=0 keeps udpm multicast on this host; memq:// is an in-process bus private to
  /// the endpoint's own lcm::LCM (tests publish and subscribe through LcmEndpoint::lcm()).
  std::string url = "udpm://239.255.76.67:7667?ttl=0";
  std::string currents_channel = "AMBDROP_CURRENTS";  ///< in: ambdrop_lcm::amb_currents_t
  std::string trigger_channel = "AMBDROP_TRIGGER";    ///< in: ambdrop_lcm::trigger_t
  std::string sensors_channel = "AMBDROP_SENSORS";    ///< out: ambdrop_lcm::sensor_readings_t
  std::string state_channel = "AMBDROP_STATE";        ///< out: ambdrop_lcm::emulator_state_t
  std::string power_channel = "AMBDROP_POWER";        ///< out: ambdrop_lcm::power_event_t
  std::string plant_channel = "AMBDROP_PLANT";        ///< out: ambdrop_lcm::plant_description_t
  std::string plant_request_channel = "AMBDROP_PLANT_REQUEST";  ///< in: any message
  /// Longest wait of one lcm.handleTimeout call of the receive thread: it bounds how long Stop
  /// waits for that thread, not the receive latency (a message wakes it at once).
  std::chrono::milliseconds receive_timeout{20};
  /// 0: each TryPushSensors/TryPushState wakes the publish thread (a futex wake when the thread
  /// is asleep, ~1 us; lowest latency). > 0: the publish thread polls at this period instead and
  /// the real-time pushes make no system call at all, at the cost of up to one period of latency.
  std::chrono::microseconds publish_poll_period{0};
  /// Per AMB: a current (x or y) of larger magnitude is rejected and counted, as a NaN is. A
  /// finite 1e300 A would otherwise reach the force law (`ambdrop hil` sets a multiple of the
  /// AMB's current_limit_A).
  std::array<double, kMaxAmbs> current_bound_A = [] {
    std::array<double, kMaxAmbs> bound{};
    bound.fill(std::numeric_limits<double>::infinity());
    return bound;
  }();
};

/// Counter snapshot. Every message or record is counted exactly once per line below, so e.g.
/// currents messages arriving = currents_received + malformed messages on that channel.
struct LcmEndpointCounters {
  std::uint64_t currents_received = 0;     ///< valid currents messages (ring-full drops included)
  std::uint64_t triggers_received = 0;     ///< valid trigger messages (ring-full drops included)
  std::uint64_t malformed_decode = 0;      ///< not decodable as the channel's type (bad hash, size)
  std::uint64_t malformed_range = 0;       ///< count or mask out of range
  std::uint64_t malformed_non_finite = 0;  ///< NaN or infinite current
  std::uint64_t malformed_current_bound = 0;  ///< finite current beyond current_bound_A
  std::uint64_t currents_sequence_jumps = 0;  ///< sequence != previous + 1 (loss or restart)
  std::uint64_t currents_ring_full = 0;       ///< valid currents dropped: the real-time side lagged
  std::uint64_t triggers_ring_full = 0;       ///< valid triggers dropped: the real-time side lagged
  std::uint64_t sensors_published = 0;
  std::uint64_t states_published = 0;
  std::uint64_t sensors_ring_full = 0;  ///< TryPushSensors refused: the publish thread lagged
  std::uint64_t states_ring_full = 0;   ///< TryPushState refused: the publish thread lagged
  std::uint64_t power_events_published = 0;
  std::uint64_t power_events_ring_full = 0;  ///< TryPushPowerEvent refused
  std::uint64_t plant_requests = 0;          ///< messages on the plant request channel
  std::uint64_t plant_published = 0;         ///< plant descriptions published
  std::uint64_t publish_rejected = 0;        ///< records with counts out of range, not published
  std::uint64_t publish_errors = 0;          ///< lcm publish calls that failed
  std::uint64_t receive_errors = 0;          ///< lcm handleTimeout calls that failed
};

/// The LCM side of the HIL link, kept off the real-time thread.
///
/// A receive thread runs lcm.handleTimeout, decodes amb_currents_t and trigger_t messages,
/// validates them and pushes them as HilCurrents / HilTrigger into SPSC rings that the real-time
/// thread pops. A publish thread pops the HilSensorReadings / HilEmulatorState records the
/// real-time thread pushed, encodes them into buffers sized at construction and publishes them.
/// Malformed messages are counted and dropped. When a ring is full the newest record is dropped
/// and counted (neither side ever blocks on the other).
///
/// Lifecycle: the constructor (configure) and Start (activate) may allocate and throw; the
/// Try* calls are the real-time API: noexcept, allocation-free, lock-free, and each must be
/// used by one thread only (the real-time loop). Stop (or the destructor) joins both threads
/// after publishing what the real-time side had pushed.
///
/// The object is large (the rings are inline): create it with std::make_unique.
class LcmEndpoint {
 public:
  static constexpr std::size_t kCurrentsCapacity = 64;  ///< controller cycles buffered
  static constexpr std::size_t kTriggerCapacity = 16;
  static constexpr std::size_t kSensorsCapacity = 256;  ///< output intervals buffered
  static constexpr std::size_t kStateCapacity = 64;
  static constexpr std::size_t kPowerCapacity = 16;

  /// Creates the lcm::LCM for options.url and subscribes. Throws std::invalid_argument for
  /// empty or repeated channel names, std::runtime_error when LCM rejects the URL.
  explicit LcmEndpoint(LcmEndpointOptions options);
  ~LcmEndpoint();
  LcmEndpoint(const LcmEndpoint&) = delete;
  LcmEndpoint& operator=(const LcmEndpoint&) = delete;

  /// Starts the receive and publish threads. Throws std::logic_error if already started.
  void Start();
  /// Publishes the records already pushed, then joins both threads. Idempotent.
  void Stop() noexcept;
  /// Runs the receive and publish threads, and LCM's own reading thread, under SCHED_FIFO at
  /// `priority` (1-99), after Start(), and, when the real-time loop is pinned to `loop_cpu`
  /// (>= 0), on the other CPUs. A real-time loop's messages pass through them: left to the
  /// ordinary scheduler, a busy machine holds the controller's answers back past the loop's
  /// watchdog. Returns an empty string, or why the kernel refused.
  std::string RaiseIoThreads(int priority, int loop_cpu = -1);
  bool running() const noexcept { return running_; }

  // --- Real-time side ---------------------------------------------------------------------
  /// Oldest controller currents not yet taken. False when none arrived.
  bool TryPopCurrents(HilCurrents* out) noexcept { return currents_.TryPop(out); }
  /// Controller currents received and not yet taken.
  std::size_t pending_currents() const noexcept { return currents_.size(); }
  /// Oldest trigger not yet taken. False when none arrived.
  bool TryPopTrigger(HilTrigger* out) noexcept { return triggers_.TryPop(out); }
  /// Queues readings for publishing. False (counted) when the ring is full.
  bool TryPushSensors(const HilSensorReadings& readings) noexcept {
    const bool pushed = sensors_.TryPush(readings);
    if (pushed) WakePublisher();
    return pushed;
  }
  /// Queues a state for publishing. False (counted) when the ring is full.
  bool TryPushState(const HilEmulatorState& state) noexcept {
    const bool pushed = states_.TryPush(state);
    if (pushed) WakePublisher();
    return pushed;
  }
  /// Queues a power event for publishing. False (counted) when the ring is full.
  bool TryPushPowerEvent(const HilPowerEvent& event) noexcept {
    const bool pushed = power_.TryPush(event);
    if (pushed) WakePublisher();
    return pushed;
  }

  // --- Setup (not the real-time thread) ---------------------------------------------------
  /// Keeps the plant description (`json`, its `schema_version`) and publishes it now; the
  /// receive thread publishes it again on each request. Thread-safe; allocates.
  void PublishPlantDescription(std::string json, int schema_version);

  // --- Any thread -------------------------------------------------------------------------
  LcmEndpointCounters counters() const noexcept;
  const LcmEndpointOptions& options() const noexcept { return options_; }
  /// The underlying LCM instance, for in-process peers on memq:// and extra subscriptions
  /// (subscribe before Start; handlers run on the receive thread). Publishing is thread-safe.
  lcm::LCM& lcm() noexcept { return *lcm_; }

 private:
  struct Callbacks;  // C callback thunks, defined in the .cpp (keeps LCM headers out of here)

  void ReceiveLoop() noexcept;
  void PublishLoop() noexcept;
  void HandleCurrents(const void* data, std::size_t size) noexcept;
  void HandleTrigger(const void* data, std::size_t size) noexcept;
  void HandlePlantRequest() noexcept;
  void PublishPlant() noexcept;
  void PublishSensors(const HilSensorReadings& readings) noexcept;
  void PublishState(const HilEmulatorState& state) noexcept;
  void PublishPowerEvent(const HilPowerEvent& event) noexcept;
  void WakePublisher() noexcept {
    if (options_.publish_poll_period.count() > 0) return;
    publish_signal_.fetch_add(1, std::memory_order_release);
    publish_signal_.notify_one();
  }

  LcmEndpointOptions options_;
  std::unique_ptr<lcm::LCM> lcm_;
  // LCM's own threads (udpm reads its socket in a thread of its own, which hands each message
  // to lcm_handle): the tasks that appeared while lcm_ was created and subscribed.
  std::vector<pid_t> lcm_library_tasks_;
  std::vector<std::uint8_t> sensors_buffer_;  ///< encoded sensor_readings_t (fixed size)
  std::vector<std::uint8_t> state_buffer_;    ///< encoded emulator_state_t (fixed size)
  std::vector<std::uint8_t> power_buffer_;    ///< encoded power_event_t (fixed size)

  SpscRing<HilCurrents, kCurrentsCapacity> currents_;
  SpscRing<HilTrigger, kTriggerCapacity> triggers_;
  SpscRing<HilSensorReadings, kSensorsCapacity> sensors_;
  SpscRing<HilEmulatorState, kStateCapacity> states_;
  SpscRing<HilPowerEvent, kPowerCapacity> power_;

  std::atomic<bool> stop_{false};
  std::atomic<std::uint32_t> publish_signal_{0};  ///< bumped per push; the publisher waits on it
  bool running_ = false;
  std::thread receive_thread_;
  std::thread publish_thread_;

  // Receive-thread state (written by the receive thread only, read by counters()).
  bool have_sequence_ = false;
  std::int64_t last_sequence_ = 0;
  std::atomic<std::uint64_t> currents_received_{0};
  std::atomic<std::uint64_t> triggers_received_{0};
  std::atomic<std::uint64_t> malformed_decode_{0};
  std::atomic<std::uint64_t> malformed_range_{0};
  std::atomic<std::uint64_t> malformed_non_finite_{0};
  std::atomic<std::uint64_t> malformed_current_bound_{0};
  std::atomic<std::uint64_t> currents_sequence_jumps_{0};
  std::atomic<std::uint64_t> receive_errors_{0};
  // Publish-thread counters.
  std::atomic<std::uint64_t> sensors_published_{0};
  std::atomic<std::uint64_t> states_published_{0};
  std::atomic<std::uint64_t> power_events_published_{0};
  std::atomic<std::uint64_t> plant_requests_{0};
  std::atomic<std::uint64_t> plant_published_{0};
  std::mutex plant_mutex_;  ///< guards the two below (setup and receive threads)
  std::string plant_json_;  ///< "": none yet
  int plant_schema_version_ = 0;
  std::atomic<std::uint64_t> publish_rejected_{0};
  std::atomic<std::uint64_t> publish_errors_{0};
};

}  // namespace ambdrop
