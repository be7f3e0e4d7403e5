#pragma once
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <variant>

#include "controller_if/loop/run_record.hpp"
#include "io/files/event_log.hpp"
#include "rt_core/model.hpp"
#include "rt_core/spsc_ring.hpp"

namespace ambdrop {

/// What goes into the record's header event.
struct RecordHeaderInfo {
  std::string source;      ///< "sim" or "hil"
  std::string controller;  ///< internal, lcm:..., can:..., profile
  std::string config_toml;
  std::int64_t sensor_every_steps = 0;
  std::int64_t output_every_steps = 1;
  std::int64_t total_steps = 0;
};

struct RecordWriterOptions {
  /// Event timestamps and utime fields: wall clock (live runs) or the event's simulated time
  /// (offline runs: the log is then the same, byte for byte, on every run).
  bool wall_clock = false;
  /// Offline runs wait for the writer when the ring is full instead of dropping (nothing lost).
  bool wait_when_full = true;
  std::int64_t check_every_events = 256;
};

/// Counts per event kind.
struct RecordCounts {
  std::int64_t inputs = 0, power = 0, sensors = 0, states = 0;
  bool operator==(const RecordCounts&) const = default;
};

/// Records a run into an LCM event log (tools/record/record_channels.hpp). The run's thread
/// hands events over through a lock-free ring (allocation-free, non-blocking unless
/// wait_when_full); a writer thread encodes and writes them. Finish() writes the footer with the
/// counts produced and written: equal unless the ring overflowed.
class RunRecordWriter final : public RunRecorder {
 public:
  RunRecordWriter(const std::filesystem::path& path, const Model& model,
                  const RecordHeaderInfo& header, const RecordWriterOptions& options = {});
  ~RunRecordWriter() override;

  void OnStart(const RecordedStart& start) noexcept override;
  void OnInput(const RecordedInput& input) noexcept override;
  void OnPower(const RecordedPower& power) noexcept override;
  void OnSensors(const RecordedSensors& sensors) noexcept override;
  void OnState(const State& state, const Observation& observation) noexcept override;

  /// Drains the ring, writes the last check and the footer, closes the file. Throws on an I/O
  /// error (also one the writer thread met earlier).
  void Finish(const std::string& status, std::int64_t final_step);

  const RecordCounts& produced() const noexcept { return produced_; }
  RecordCounts written() const;
  std::int64_t dropped() const noexcept { return dropped_.load(); }
  std::int64_t events_written() const noexcept { return events_written_.load(); }

  /// FNV-1a 64 of a config text as 16 lowercase hex digits (the header's config_hash).
  static std::string ConfigHash(const std::string& config_toml);

 private:
  struct StateSample {
    std::int64_t step = 0;
    double time_s = 0.0;
    bool power_on = true;
    int modes = 0;
    std::array<double, kMaxModes> q{};
    std::array<double, kMaxModes> q_dot{};
    Observation observation;
    std::int64_t faults = 0;
  };
  using Payload =
      std::variant<RecordedStart, RecordedInput, RecordedPower, RecordedSensors, StateSample>;
  struct Slot {
    std::int64_t utime_us = 0;
    Payload payload;
  };
  using Ring = SpscRing<Slot, 4096>;

  void Push(const Slot& slot, std::int64_t* produced) noexcept;
  std::int64_t Stamp(double time_s) const noexcept;
  void WriterLoop();
  void WriteSlot(const Slot& slot);
  void WriteEvent(const char* channel, std::int64_t utime_us,
                  const std::vector<std::uint8_t>& data);
  void WriteCheck();

  const Model& model_;
  RecordWriterOptions options_;
  EventLogWriter log_;
  std::unique_ptr<Ring> ring_;
  RecordCounts produced_;
  std::atomic<std::int64_t> dropped_{0};
  std::atomic<std::int64_t> events_written_{0};
  // Writer-thread side.
  RecordCounts written_;
  std::int64_t check_first_event_ = 0;
  std::int64_t check_events_ = 0;
  std::uint64_t check_hash_ = kFnv1a64Basis;
  std::int64_t last_utime_us_ = 0;
  std::string error_;
  std::atomic<bool> done_{false};
  std::thread thread_;
  bool finished_ = false;
};

}  // namespace ambdrop
