#include "tools/record/run_record_writer.hpp"

#include <fmt/format.h>

#include <chrono>
#include <stdexcept>

#include "ambdrop_lcm/emulator_state_t.hpp"
#include "ambdrop_lcm/record_check_t.hpp"
#include "ambdrop_lcm/record_footer_t.hpp"
#include "ambdrop_lcm/record_header_t.hpp"
#include "ambdrop_lcm/record_start_t.hpp"
#include "ambdrop_lcm/recorded_input_t.hpp"
#include "ambdrop_lcm/recorded_power_t.hpp"
#include "ambdrop_lcm/sensor_readings_t.hpp"
#include "tools/record/record_channels.hpp"

#ifndef AMBDROP_VERSION
#define AMBDROP_VERSION "unknown"
#endif

namespace ambdrop {
namespace {

template <typename Message>
std::vector<std::uint8_t> Encode(const Message& message) {
  std::vector<std::uint8_t> data(static_cast<std::size_t>(message.getEncodedSize()));
  if (message.encode(data.data(), 0, static_cast<int>(data.size())) < 0) {
    throw std::runtime_error("record: cannot encode an LCM message");
  }
  return data;
}

std::int64_t WallClockUs() noexcept {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace

std::string RunRecordWriter::ConfigHash(const std::string& config_toml) {
  return fmt::format("{:016x}", Fnv1a64(config_toml));
}

RunRecordWriter::RunRecordWriter(const std::filesystem::path& path, const Model& model,
                                 const RecordHeaderInfo& header, const RecordWriterOptions& options)
    : model_(model), options_(options), log_(path), ring_(std::make_unique<Ring>()) {
  ambdrop_lcm::record_header_t h;
  h.ambdrop_version = AMBDROP_VERSION;
  h.source = header.source;
  h.controller = header.controller;
  h.config_toml = header.config_toml;
  h.config_hash = ConfigHash(header.config_toml);
  h.step_s = model.params.simulation.step_s;
  h.sensor_every_steps = header.sensor_every_steps;
  h.output_every_steps = header.output_every_steps;
  h.total_steps = header.total_steps;
  h.check_every_events = options.check_every_events;
  // The header is its own check block, so a reader can trust it before anything else.
  WriteEvent(kRecHeaderChannel, options.wall_clock ? WallClockUs() : 0, Encode(h));
  WriteCheck();
  thread_ = std::thread([this] { WriterLoop(); });
}

RunRecordWriter::~RunRecordWriter() {
  if (!finished_) {
    try {
      Finish("interrupted", -1);
    } catch (...) {  // a destructor must not throw; Finish's caller sees errors
    }
  }
}

std::int64_t RunRecordWriter::Stamp(double time_s) const noexcept {
  return options_.wall_clock ? WallClockUs() : std::llround(time_s * 1e6);
}

void RunRecordWriter::Push(const Slot& slot, std::int64_t* produced) noexcept {
  ++*produced;
  while (!ring_->TryPush(slot)) {
    if (!options_.wait_when_full) {
      dropped_.fetch_add(1);
      return;
    }
    std::this_thread::yield();
  }
}

void RunRecordWriter::OnStart(const RecordedStart& start) noexcept {
  std::int64_t unused = 0;
  Push(Slot{Stamp(0.0), start}, &unused);
}

void RunRecordWriter::OnInput(const RecordedInput& input) noexcept {
  Push(Slot{Stamp(static_cast<double>(input.step) * model_.params.simulation.step_s), input},
       &produced_.inputs);
}

void RunRecordWriter::OnPower(const RecordedPower& power) noexcept {
  Push(Slot{Stamp(static_cast<double>(power.step) * model_.params.simulation.step_s), power},
       &produced_.power);
}

void RunRecordWriter::OnSensors(const RecordedSensors& sensors) noexcept {
  Push(Slot{Stamp(sensors.time_s), sensors}, &produced_.sensors);
}

void RunRecordWriter::OnState(const State& state, const Observation& observation) noexcept {
  StateSample s;
  s.step = state.step_index;
  s.time_s = observation.time_s;
  s.power_on = state.power_on;
  s.modes = model_.modes();
  for (int i = 0; i < s.modes && i < kMaxModes; ++i) {
    s.q[i] = state.y[i];
    s.q_dot[i] = state.y[s.modes + i];
  }
  s.observation = observation;
  s.faults = state.faults.non_finite_state + state.faults.excursion_beyond_bound;
  Push(Slot{Stamp(observation.time_s), s}, &produced_.states);
}

void RunRecordWriter::WriteEvent(const char* channel, std::int64_t utime_us,
                                 const std::vector<std::uint8_t>& data) {
  // lcm-logplayer paces by timestamp: keep them non-decreasing.
  last_utime_us_ = std::max(last_utime_us_, utime_us);
  const std::string name(channel);
  log_.Write(name, last_utime_us_, data);
  if (check_events_ == 0) check_first_event_ = log_.events() - 1;
  ++check_events_;
  check_hash_ = Fnv1a64(name, check_hash_);
  check_hash_ = Fnv1a64(std::span<const std::uint8_t>(data), check_hash_);
  events_written_.store(log_.events());
}

void RunRecordWriter::WriteCheck() {
  if (check_events_ == 0) return;
  ambdrop_lcm::record_check_t c;
  c.first_event = check_first_event_;
  c.event_count = check_events_;
  c.fnv1a64 = static_cast<std::int64_t>(check_hash_);
  const std::vector<std::uint8_t> data = Encode(c);
  log_.Write(kRecCheckChannel, last_utime_us_, data);
  events_written_.store(log_.events());
  check_events_ = 0;
  check_hash_ = kFnv1a64Basis;
}

void RunRecordWriter::WriteSlot(const Slot& slot) {
  const int ambs = static_cast<int>(model_.params.ambs.size());
  if (const auto* start = std::get_if<RecordedStart>(&slot.payload)) {
    ambdrop_lcm::record_start_t m{};
    m.equilibrium_motor_on = start->equilibrium_input.motor_on;
    for (int a = 0; a < kMaxAmbs; ++a) {
      const AmbDrive& d = start->equilibrium_input.amb[a];
      m.equilibrium_current_x_A[a] = d.current_A[0];
      m.equilibrium_current_y_A[a] = d.current_A[1];
      m.equilibrium_force_scale_x[a] = d.force_scale[0];
      m.equilibrium_force_scale_y[a] = d.force_scale[1];
      m.loop_current_x_A[a] = start->loop_current_A[a][0];
      m.loop_current_y_A[a] = start->loop_current_A[a][1];
    }
    WriteEvent(kRecStartChannel, slot.utime_us, Encode(m));
  } else if (const auto* in = std::get_if<RecordedInput>(&slot.payload)) {
    ambdrop_lcm::recorded_input_t m{};
    m.utime = slot.utime_us;
    m.step_index = in->step;
    m.receive_ns = in->receive_ns;
    m.sequence = static_cast<std::int64_t>(in->sequence);
    m.kind = static_cast<std::int8_t>(in->kind);
    m.amb_count = static_cast<std::int8_t>(ambs);
    for (int a = 0; a < kMaxAmbs; ++a) {
      m.current_x_A[a] = in->current_A[a][0];
      m.current_y_A[a] = in->current_A[a][1];
    }
    WriteEvent(kRecInputChannel, slot.utime_us, Encode(m));
    ++written_.inputs;
  } else if (const auto* p = std::get_if<RecordedPower>(&slot.payload)) {
    ambdrop_lcm::recorded_power_t m{};
    m.utime = slot.utime_us;
    m.step_index = p->step;
    m.power_on = p->event.restore;
    m.amb_mask = static_cast<std::int32_t>(p->event.amb_mask);
    m.axis_x = p->event.axis_x;
    m.axis_y = p->event.axis_y;
    m.motor = p->event.motor;
    WriteEvent(kRecPowerChannel, slot.utime_us, Encode(m));
    ++written_.power;
  } else if (const auto* s = std::get_if<RecordedSensors>(&slot.payload)) {
    ambdrop_lcm::sensor_readings_t m{};
    m.utime = slot.utime_us;
    m.step_index = s->step;
    m.time_s = s->time_s;
    m.sensor_count = static_cast<std::int8_t>(model_.params.sensors.size());
    m.counts_valid = false;
    for (int i = 0; i < kMaxSensors; ++i) {
      m.x_m[i] = s->readings.reading_m[i][0];
      m.y_m[i] = s->readings.reading_m[i][1];
    }
    WriteEvent(kRecSensorsChannel, slot.utime_us, Encode(m));
    ++written_.sensors;
  } else if (const auto* st = std::get_if<StateSample>(&slot.payload)) {
    ambdrop_lcm::emulator_state_t m{};
    m.utime = slot.utime_us;
    m.step_index = st->step;
    m.time_s = st->time_s;
    m.power_on = st->power_on;
    m.spin_speed_rad_s = st->observation.spin_speed_rad_s;
    m.spin_angle_rad = st->observation.spin_angle_rad;
    m.mode_count = static_cast<std::int8_t>(st->modes);
    for (int i = 0; i < st->modes && i < kMaxModes; ++i) {
      m.q[i] = st->q[i];
      m.q_dot[i] = st->q_dot[i];
    }
    const int tdbs = static_cast<int>(model_.params.tdbs.size());
    m.tdb_count = static_cast<std::int8_t>(tdbs);
    for (int t = 0; t < tdbs && t < kMaxTdbs; ++t) {
      const TdbForce& f = st->observation.tdb[t];
      m.tdb_normal_force_N[t] = f.normal_force_N;
      m.tdb_tangential_force_N[t] = f.tangential_force_N;
      m.tdb_penetration_m[t] = f.penetration_m;
      m.tdb_race_speed_rad_s[t] = f.tdb_spin_rad_s;
      m.tdb_journal_x_m[t] = st->observation.tdb_journal_xy_m[t][0];
      m.tdb_journal_y_m[t] = st->observation.tdb_journal_xy_m[t][1];
    }
    m.fault_count = st->faults;
    WriteEvent(kRecStateChannel, slot.utime_us, Encode(m));
    ++written_.states;
  }
  if (check_events_ >= options_.check_every_events) WriteCheck();
}

void RunRecordWriter::WriterLoop() {
  Slot slot;
  try {
    for (;;) {
      bool any = false;
      while (ring_->TryPop(&slot)) {
        WriteSlot(slot);
        any = true;
      }
      if (!any) {
        if (done_.load()) {
          while (ring_->TryPop(&slot)) WriteSlot(slot);
          return;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
    }
  } catch (const std::exception& e) {
    error_ = e.what();
    // Keep draining so a waiting producer never blocks forever.
    while (!done_.load()) {
      while (ring_->TryPop(&slot)) dropped_.fetch_add(1);
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }
}

RecordCounts RunRecordWriter::written() const {
  return written_;
}

void RunRecordWriter::Finish(const std::string& status, std::int64_t final_step) {
  if (finished_) return;
  finished_ = true;
  done_.store(true);
  thread_.join();
  if (!error_.empty()) throw std::runtime_error("record: " + error_);
  WriteCheck();
  ambdrop_lcm::record_footer_t f;
  f.status = status;
  f.final_step = final_step;
  f.inputs_produced = produced_.inputs;
  f.inputs_written = written_.inputs;
  f.power_produced = produced_.power;
  f.power_written = written_.power;
  f.sensors_produced = produced_.sensors;
  f.sensors_written = written_.sensors;
  f.states_produced = produced_.states;
  f.states_written = written_.states;
  WriteEvent(kRecFooterChannel, last_utime_us_, Encode(f));
  WriteCheck();
  log_.Close();
}

}  // namespace ambdrop
