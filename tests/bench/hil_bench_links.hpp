#pragma once
// The links of hil_timing_bench: the emulator's side of CAN (over the in-memory CAN bus double)
// and of LCM, each with a controller stand-in that answers every sensor sample with the
// reference PID's currents at once, and the logs that time one exchange end to end:
//
//   controller sends currents (seq n) ─► emulator wakes, polls them ─► physics ─► sensors out
//        send_ns[n]                          wake_ns[k]    (seq n)                sent_ns[k]
//   ─► controller receives sample k (recv_ns[k]) and answers it with seq n + 1 ...
//
// Every time is CLOCK_MONOTONIC in one process, so differences need no clock sync. Logs are
// preallocated arrays written by one thread each and read after the run.
#include <ambdrop_lcm/amb_currents_t.hpp>
#include <ambdrop_lcm/sensor_readings_t.hpp>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "controller_if/controller/pid_controller.hpp"
#include "controller_if/loop/controller_link.hpp"
#include "controller_if/loop/rt_clock.hpp"
#include "io/can/can_bus_double.hpp"
#include "io/config/config_can.hpp"
#include "io/lcm/lcm_transport.hpp"
#include "rt_core/model.hpp"

namespace ambdrop::bench {

inline std::int64_t NowNs() noexcept {
  static MonotonicClock clock;
  return clock.Now();
}

/// What one side saw, indexed by emulator sample (step / substeps) or by currents sequence.
struct ExchangeLog {
  explicit ExchangeLog(std::size_t samples)
      : wake_ns(samples, -1),
        sent_ns(samples, -1),
        consumed_seq(samples, -1),
        recv_ns(samples, -1),
        send_ns(samples, -1),
        answers_sample(samples, -1) {}
  // Emulator side, per sample k (the one sent at the end of the period producing it).
  std::vector<std::int64_t> wake_ns;       ///< the period's wake-up
  std::vector<std::int64_t> sent_ns;       ///< sample handed to the link
  std::vector<std::int64_t> consumed_seq;  ///< newest currents polled in that period, -1: none
  // Controller side.
  std::vector<std::int64_t> recv_ns;         ///< per sample k: arrival at the controller
  std::vector<std::int64_t> send_ns;         ///< per currents seq n: sent
  std::vector<std::int64_t> answers_sample;  ///< per currents seq n: the sample it answers
};

/// The emulator's link with timing: records, per period, which currents it consumed and when
/// the sample left. `substeps` maps steps to samples.
class TimedLink final : public ControllerLink {
 public:
  TimedLink(ControllerLink* inner, ExchangeLog* log, std::int64_t substeps)
      : inner_(inner), log_(log), substeps_(substeps) {}
  bool PollCurrents(CurrentsMessage* out) noexcept override {
    if (!inner_->PollCurrents(out)) return false;
    consumed_ = static_cast<std::int64_t>(out->sequence);
    return true;
  }
  void SendSensors(const SensorReadings& readings, std::int64_t step,
                   double time_s) noexcept override {
    inner_->SendSensors(readings, step, time_s);
    const std::size_t k = static_cast<std::size_t>(step / substeps_);
    if (k < log_->sent_ns.size()) {
      log_->sent_ns[k] = NowNs();
      log_->wake_ns[k] = wake_ns_;
      log_->consumed_seq[k] = consumed_;
    }
    consumed_ = -1;
  }
  void SetWake(std::int64_t wake_ns) noexcept { wake_ns_ = wake_ns; }

 private:
  ControllerLink* inner_;
  ExchangeLog* log_;
  std::int64_t substeps_;
  std::int64_t consumed_ = -1;
  std::int64_t wake_ns_ = -1;
};

// ---------------------------------------------------------------------------------------------
// CAN: one FD frame each way at the controller rate (classic CAN carries ~7 400 frames/s at
// 1 Mbit/s, too few for 20 kHz). Sensors: each sensor's x and y as 4-byte signed counts of
// 10 nm, then the step counter; currents: each AMB's x and y as 2-byte signed mA.

inline constexpr std::uint32_t kCurrentsId = 0x100;
inline constexpr std::uint32_t kSensorsId = 0x200;
inline constexpr double kSensorScale_m = 1e-8;
inline constexpr double kCurrentScale_A = 1e-3;
/// Bench plumbing beyond the frame map's signals (which ignore these bytes): the controller's
/// frame number, so a frame lost on the bus cannot mismatch the timings.
inline constexpr CanSignalLayout kSequenceLayout{kCurrentsId, false, 16, 4, false};
inline constexpr std::uint8_t kCurrentsLen = 20;  // an FD length holding 4 AMBs and the sequence

// The double has no wire: frames arrive as soon as written. A real bus does not carry this
// exchange at 20 kHz: at 1 Mbit/s arbitration and 8 Mbit/s data the two 20-byte FD frames take up
// to 112 us (the config check allows 8.9 kHz), so the table's CAN round trips lack ~2 x 56 us of
// wire time, and exchange_rate_Hz below only satisfies that check.
inline std::string CanTableFor(const Model& model) {
  std::string t =
      "[can]\ninterface = \"vcan0\"\nfd = true\nbit_rate_switch = true\nbitrate_bps = 1000000\n"
      "data_bitrate_bps = 8000000\nexchange_rate_Hz = 8000\n";
  const auto& p = model.params;
  for (std::size_t a = 0; a < p.ambs.size(); ++a) {
    for (int axis = 0; axis < 2; ++axis) {
      t += "[can.currents_in." + p.ambs[a].name + "." + (axis == 0 ? "x" : "y") + "]\n" +
           "id = 0x100\nbyte_offset = " + std::to_string(4 * a + 2 * axis) +
           "\nwidth_bytes = 2\nsigned = true\nscale_A_per_count = 0.001\n";
    }
  }
  for (std::size_t s = 0; s < p.sensors.size(); ++s) {
    for (int axis = 0; axis < 2; ++axis) {
      t += "[can.sensors_out." + p.sensors[s].name + "." + (axis == 0 ? "x" : "y") + "]\n" +
           "id = 0x200\nbyte_offset = " + std::to_string(8 * s + 4 * axis) +
           "\nwidth_bytes = 4\nsigned = true\nscale_m_per_count = 1e-8\n";
    }
  }
  t += "[can.status_out.step_counter]\nid = 0x200\nbyte_offset = " +
       std::to_string(8 * p.sensors.size()) + "\nwidth_bytes = 4\n";
  return t;
}

/// The emulator's side of CAN: decodes currents frames (each frame a new sequence number, in
/// arrival order), encodes the sample into the sensors frame.
class BenchCanLink final : public ControllerLink {
 public:
  BenchCanLink(CanBus* bus, const FrameMap* map) : bus_(bus), map_(map) {}
  bool PollCurrents(CurrentsMessage* out) noexcept override {
    CanFrame frame;
    bool any = false;
    while (bus_->Receive(&frame, std::chrono::nanoseconds(0)) == CanStatus::kOk) {
      if (map_->Decode(frame, &command_, &counters_) == DecodeResult::kApplied) {
        sequence_ = static_cast<std::uint64_t>(
            ReadRaw(kSequenceLayout, std::span<const std::uint8_t, kCanFdMaxLen>(frame.data)));
        any = true;
      }
    }
    if (!any) return false;
    out->current_A = command_.current_A;
    out->sequence = sequence_;
    return true;
  }
  const FrameMapCounters& counters() const noexcept { return counters_; }
  void SendSensors(const SensorReadings& readings, std::int64_t step, double) noexcept override {
    EmulatorOutputs outputs;
    outputs.sensor_xy_m = readings.reading_m;
    outputs.step = static_cast<std::uint64_t>(step);
    const std::size_t n = map_->Encode(outputs, frames_out_, &counters_);
    for (std::size_t i = 0; i < n; ++i) (void)bus_->Send(frames_out_[i]);
  }

 private:
  CanBus* bus_;
  const FrameMap* map_;
  CanCommand command_;
  FrameMapCounters counters_;
  std::uint64_t sequence_ = 0;
  std::array<CanFrame, 4> frames_out_{};
};

/// The controller's side of CAN: answers each sensors frame with a currents frame. Serve()
/// handles what has arrived (waiting up to `timeout`); call it from one thread.
class CanControllerStandIn {
 public:
  /// `malformed_every` > 0: after every that many answers a malformed currents frame (the
  /// currents id, 3 bytes: too short for its signals) follows on the bus.
  CanControllerStandIn(const Model& model, double period_s, CanBus* bus, ExchangeLog* log,
                       std::int64_t substeps, int malformed_every = 0)
      : malformed_every_(malformed_every),
        pid_(model, period_s),
        bus_(bus),
        log_(log),
        substeps_(substeps),
        sensors_(static_cast<int>(model.params.sensors.size())),
        ambs_(static_cast<int>(model.params.ambs.size())) {}

  void Serve(std::chrono::nanoseconds timeout) noexcept {
    CanFrame in;
    while (bus_->Receive(&in, timeout) == CanStatus::kOk) {
      timeout = std::chrono::nanoseconds(0);
      if (in.id != kSensorsId) continue;
      const std::int64_t t = NowNs();
      const auto data = std::span<const std::uint8_t, kCanFdMaxLen>(in.data);
      SensorReadings r;
      for (int s = 0; s < sensors_; ++s) {
        for (int axis = 0; axis < 2; ++axis) {
          const CanSignalLayout l{kSensorsId, false, 8 * s + 4 * axis, 4, true};
          r.reading_m[s][axis] = static_cast<double>(ReadRaw(l, data)) * kSensorScale_m;
        }
      }
      const CanSignalLayout step_layout{kSensorsId, false, 8 * sensors_, 4, false};
      const std::int64_t sample = ReadRaw(step_layout, data) / substeps_;
      if (sample >= 0 && static_cast<std::size_t>(sample) < log_->recv_ns.size()) {
        log_->recv_ns[static_cast<std::size_t>(sample)] = t;
      }
      pid_.Update(r, &input_);
      CanFrame out;
      out.id = kCurrentsId;
      out.fd = true;
      out.brs = true;
      out.len = kCurrentsLen;
      auto out_data = std::span<std::uint8_t, kCanFdMaxLen>(out.data);
      for (int a = 0; a < ambs_; ++a) {
        for (int axis = 0; axis < 2; ++axis) {
          const CanSignalLayout l{kCurrentsId, false, 4 * a + 2 * axis, 2, true};
          bool saturated = false;
          WriteRaw(l,
                   PhysicalToRaw(l, CanScaling{kCurrentScale_A, 0.0}, input_.amb[a].current_A[axis],
                                 &saturated),
                   out_data);
        }
      }
      WriteRaw(kSequenceLayout, seq_, out_data);
      const std::size_t n = static_cast<std::size_t>(seq_);
      if (n < log_->send_ns.size()) {
        log_->send_ns[n] = NowNs();
        log_->answers_sample[n] = sample;
      }
      if (bus_->Send(out) == CanStatus::kOk) ++seq_;
      if (malformed_every_ > 0 && seq_ % malformed_every_ == 0) {
        CanFrame bad;
        bad.id = kCurrentsId;
        bad.fd = true;
        bad.len = 3;
        if (bus_->Send(bad) == CanStatus::kOk) ++malformed_sent_;
      }
    }
  }
  std::uint64_t malformed_sent() const noexcept { return malformed_sent_; }

 private:
  int malformed_every_ = 0;
  std::uint64_t malformed_sent_ = 0;
  ReferenceController pid_;
  CanBus* bus_;
  ExchangeLog* log_;
  std::int64_t substeps_;
  int sensors_;
  int ambs_;
  ControlInput input_;
  std::int64_t seq_ = 0;
};

// ---------------------------------------------------------------------------------------------
// LCM

/// The emulator's side of LCM (what tools/hil/lcm_controller_link does): the endpoint's rings.
class BenchLcmLink final : public ControllerLink {
 public:
  BenchLcmLink(LcmEndpoint* endpoint, int sensors) : endpoint_(endpoint), sensors_(sensors) {}
  bool PollCurrents(CurrentsMessage* out) noexcept override {
    HilCurrents c;
    bool any = false;
    while (endpoint_->TryPopCurrents(&c)) {
      any = true;
      out->current_A = c.current_A;
      out->sequence = static_cast<std::uint64_t>(c.sequence);
    }
    return any;
  }
  void SendSensors(const SensorReadings& readings, std::int64_t step,
                   double time_s) noexcept override {
    HilSensorReadings r;
    r.step_index = step;
    r.time_s = time_s;
    r.sensor_count = sensors_;
    r.position_m = readings.reading_m;
    (void)endpoint_->TryPushSensors(r);
  }

 private:
  LcmEndpoint* endpoint_;
  int sensors_;
};

/// The controller's side of LCM: a handler on `lcm` (its own instance for udpm; the endpoint's
/// for memq://, which is private to one lcm::LCM) that answers each sample.
class LcmControllerStandIn {
 public:
  /// `malformed_every` > 0: after every that many answers a malformed currents packet (bytes
  /// that are no amb_currents_t: a wrong type hash) follows on the channel.
  LcmControllerStandIn(const Model& model, double period_s, lcm::LCM* lcm, ExchangeLog* log,
                       std::int64_t substeps, int malformed_every = 0)
      : malformed_every_(malformed_every),
        pid_(model, period_s),
        lcm_(lcm),
        log_(log),
        substeps_(substeps),
        ambs_(static_cast<int>(model.params.ambs.size())) {
    lcm_->subscribe("AMBDROP_SENSORS", &LcmControllerStandIn::OnSensors, this);
  }

  void OnSensors(const lcm::ReceiveBuffer*, const std::string&,
                 const ambdrop_lcm::sensor_readings_t* m) {
    const std::int64_t t = NowNs();
    const std::int64_t sample = m->step_index / substeps_;
    if (sample >= 0 && static_cast<std::size_t>(sample) < log_->recv_ns.size()) {
      log_->recv_ns[static_cast<std::size_t>(sample)] = t;
    }
    SensorReadings r;
    for (int s = 0; s < m->sensor_count && s < kMaxSensors; ++s) {
      r.reading_m[s] = {m->x_m[s], m->y_m[s]};
    }
    pid_.Update(r, &input_);
    ambdrop_lcm::amb_currents_t c{};
    c.sequence = seq_;
    c.amb_count = static_cast<std::int8_t>(ambs_);
    for (int a = 0; a < ambs_; ++a) {
      c.current_x_A[a] = input_.amb[a].current_A[0];
      c.current_y_A[a] = input_.amb[a].current_A[1];
    }
    const std::size_t n = static_cast<std::size_t>(seq_);
    if (n < log_->send_ns.size()) {
      log_->send_ns[n] = NowNs();
      log_->answers_sample[n] = sample;
    }
    if (lcm_->publish("AMBDROP_CURRENTS", &c) == 0) ++seq_;
    if (malformed_every_ > 0 && seq_ % malformed_every_ == 0) {
      const std::array<std::uint8_t, 24> garbage{0xde, 0xad, 0xbe, 0xef, 1, 2, 3, 4};
      if (lcm_->publish("AMBDROP_CURRENTS", garbage.data(),
                        static_cast<unsigned int>(garbage.size())) == 0) {
        ++malformed_sent_;
      }
    }
  }
  std::uint64_t malformed_sent() const noexcept { return malformed_sent_; }

 private:
  int malformed_every_ = 0;
  std::uint64_t malformed_sent_ = 0;
  ReferenceController pid_;
  lcm::LCM* lcm_;
  ExchangeLog* log_;
  std::int64_t substeps_;
  int ambs_;
  ControlInput input_;
  std::int64_t seq_ = 0;
};

}  // namespace ambdrop::bench
