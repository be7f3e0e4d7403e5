#include "tools/record/run_record_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "ambdrop_lcm/emulator_state_t.hpp"
#include "ambdrop_lcm/record_check_t.hpp"
#include "ambdrop_lcm/record_footer_t.hpp"
#include "ambdrop_lcm/record_header_t.hpp"
#include "ambdrop_lcm/record_start_t.hpp"
#include "ambdrop_lcm/recorded_input_t.hpp"
#include "ambdrop_lcm/recorded_power_t.hpp"
#include "ambdrop_lcm/sensor_readings_t.hpp"
#include "io/files/event_log.hpp"
#include "tools/record/lcm_guarded_decode.hpp"
#include "tools/record/record_channels.hpp"

namespace ambdrop {
namespace {

template <typename Message>
bool Decode(const LogEvent& event, Message* out, int leading_strings = 0) {
  return DecodeLcmGuarded(std::span<const std::uint8_t>(event.data), out, leading_strings);
}

// A header whose numbers could not come from a run: a replay would divide by them or loop on them.
bool HeaderSound(const ambdrop_lcm::record_header_t& h) {
  return std::isfinite(h.step_s) && h.step_s > 0.0 && h.total_steps >= 0 &&
         h.sensor_every_steps >= 0 && h.output_every_steps >= 1;
}

std::string At(const LogEvent& e) {
  return "event " + std::to_string(e.number) + " at byte " + std::to_string(e.offset);
}

class Builder {
 public:
  explicit Builder(RunRecordFile* file) : file_(file) {}

  /// Applies one event; false (with a warning) if it cannot be decoded.
  bool Apply(const LogEvent& e) {
    const std::string& ch = e.channel;
    if (ch == kRecHeaderChannel) {
      ambdrop_lcm::record_header_t h{};
      if (!Decode(e, &h, kRecordHeaderStrings)) return Bad(e, "header");
      if (!HeaderSound(h)) {
        return Bad(
            e, "header",
            fmt::format("step_s {}, total_steps {}, sensor_every_steps {}, "
                        "output_every_steps {} cannot come from a run",
                        h.step_s, h.total_steps, h.sensor_every_steps, h.output_every_steps));
      }
      RecordHeader& r = file_->header;
      r.ambdrop_version = h.ambdrop_version;
      r.source = h.source;
      r.controller = h.controller;
      r.config_toml = h.config_toml;
      r.config_hash = h.config_hash;
      r.step_s = h.step_s;
      r.sensor_every_steps = h.sensor_every_steps;
      r.output_every_steps = h.output_every_steps;
      r.total_steps = h.total_steps;
      file_->run.sensor_every_steps = h.sensor_every_steps;
      has_header_ = true;
    } else if (ch == kRecStartChannel) {
      ambdrop_lcm::record_start_t m{};
      if (!Decode(e, &m)) return Bad(e, "start");
      RecordedStart& s = file_->run.start;
      s.equilibrium_input.motor_on = m.equilibrium_motor_on;
      for (int a = 0; a < kMaxAmbs; ++a) {
        s.equilibrium_input.amb[a].current_A = {m.equilibrium_current_x_A[a],
                                                m.equilibrium_current_y_A[a]};
        s.equilibrium_input.amb[a].force_scale = {m.equilibrium_force_scale_x[a],
                                                  m.equilibrium_force_scale_y[a]};
        s.loop_current_A[a] = {m.loop_current_x_A[a], m.loop_current_y_A[a]};
      }
      has_start_ = true;
    } else if (ch == kRecInputChannel) {
      ambdrop_lcm::recorded_input_t m{};
      if (!Decode(e, &m) || m.kind < 0 || m.kind > 2) return Bad(e, "input");
      RecordedInput in;
      in.step = m.step_index;
      in.receive_ns = m.receive_ns;
      in.sequence = static_cast<std::uint64_t>(m.sequence);
      in.kind = static_cast<RecordedInputKind>(m.kind);
      for (int a = 0; a < kMaxAmbs; ++a) in.current_A[a] = {m.current_x_A[a], m.current_y_A[a]};
      if (!InOrder(e, in.step)) return false;
      file_->run.inputs.push_back(in);
    } else if (ch == kRecPowerChannel) {
      ambdrop_lcm::recorded_power_t m{};
      if (!Decode(e, &m)) return Bad(e, "power");
      RecordedPower p;
      p.step = m.step_index;
      p.event.restore = m.power_on;
      p.event.amb_mask = static_cast<std::uint32_t>(m.amb_mask);
      p.event.axis_x = m.axis_x;
      p.event.axis_y = m.axis_y;
      p.event.motor = m.motor;
      if (!InOrder(e, p.step)) return false;
      file_->run.power.push_back(p);
    } else if (ch == kRecSensorsChannel) {
      ambdrop_lcm::sensor_readings_t m{};
      if (!Decode(e, &m)) return Bad(e, "sensors");
      RecordedSensors s;
      s.step = m.step_index;
      s.time_s = m.time_s;
      for (int i = 0; i < kMaxSensors; ++i) s.readings.reading_m[i] = {m.x_m[i], m.y_m[i]};
      if (!InOrder(e, s.step)) return false;
      file_->sensors.push_back(s);
    } else if (ch == kRecStateChannel) {
      // A replay recomputes the state (its step bounds the replay); a measurement reads it.
      ambdrop_lcm::emulator_state_t m{};
      if (!Decode(e, &m)) return Bad(e, "state");
      if (!InOrder(e, m.step_index)) return false;
      RecordedStateSample s;
      s.step = m.step_index;
      s.time_s = m.time_s;
      s.power_on = m.power_on;
      s.spin_speed_rad_s = m.spin_speed_rad_s;
      s.spin_angle_rad = m.spin_angle_rad;
      s.tdb_count = m.tdb_count;
      for (int t = 0; t < kMaxTdbs; ++t) {
        s.tdb_normal_force_N[t] = m.tdb_normal_force_N[t];
        s.tdb_tangential_force_N[t] = m.tdb_tangential_force_N[t];
        s.tdb_penetration_m[t] = m.tdb_penetration_m[t];
        s.tdb_race_speed_rad_s[t] = m.tdb_race_speed_rad_s[t];
        s.tdb_journal_xy_m[t] = {m.tdb_journal_x_m[t], m.tdb_journal_y_m[t]};
      }
      s.fault_count = m.fault_count;
      file_->states.push_back(s);
    } else if (ch == kRecFooterChannel) {
      ambdrop_lcm::record_footer_t m{};
      if (!Decode(e, &m, kRecordFooterStrings)) return Bad(e, "footer");
      RecordFooter f;
      f.status = m.status;
      f.final_step = m.final_step;
      f.produced = {m.inputs_produced, m.power_produced, m.sensors_produced, m.states_produced};
      f.written = {m.inputs_written, m.power_written, m.sensors_written, m.states_written};
      file_->footer = f;
    } else {
      file_->warnings.push_back(At(e) + ": unknown channel '" + ch + "' ignored");
    }
    ++file_->events_read;
    return true;
  }

  bool has_header() const { return has_header_; }
  bool has_start() const { return has_start_; }
  std::int64_t last_step() const { return last_step_; }

 private:
  bool Bad(const LogEvent& e, const char* what, const std::string& why = "does not decode") {
    file_->damaged = true;
    file_->warnings.push_back(At(e) + ": the " + std::string(what) + " message " + why +
                              "; the record is used up to it");
    return false;
  }
  bool InOrder(const LogEvent& e, std::int64_t step) {
    if (step < 0 || step < last_step_) {
      file_->warnings.push_back(At(e) + ": step " + std::to_string(step) +
                                " goes back in time; the record is used up to it");
      return false;
    }
    // An event past the configured end cannot come from the run; a replay would run to it.
    if (step > file_->header.total_steps) {
      file_->damaged = true;
      file_->warnings.push_back(
          At(e) + ": step " + std::to_string(step) + " is beyond the run's configured " +
          std::to_string(file_->header.total_steps) + " steps; the record is used up to it");
      return false;
    }
    last_step_ = step;
    return true;
  }

  RunRecordFile* file_;
  bool has_header_ = false;
  bool has_start_ = false;
  std::int64_t last_step_ = 0;
};

}  // namespace

RunRecordFile ReadRunRecord(const std::filesystem::path& path) {
  RunRecordFile file;
  EventLogReader reader(path);
  Builder builder(&file);
  std::vector<LogEvent> block;  // events since the last check, not yet trusted
  std::uint64_t hash = kFnv1a64Basis;
  LogEvent event;
  bool stopped = false;
  for (;;) {
    const LogReadStatus status = reader.Next(&event);
    if (status == LogReadStatus::kEnd) {
      if (!block.empty()) {
        file.warnings.push_back(std::to_string(block.size()) +
                                " events at the end have no integrity check (the recorder "
                                "stopped early); they are used");
      }
      break;
    }
    if (status == LogReadStatus::kTruncated) {
      file.damaged = true;
      file.warnings.push_back(path.string() + ": truncated: " + reader.problem() +
                              (block.empty() ? std::string()
                                             : "; the " + std::to_string(block.size()) +
                                                   " whole events after the last integrity "
                                                   "check are used unchecked"));
      break;
    }
    if (status == LogReadStatus::kCorrupt) {
      file.damaged = true;
      file.warnings.push_back(path.string() + ": corrupt: " + reader.problem() +
                              (block.empty()
                                   ? std::string()
                                   : "; the " + std::to_string(block.size()) +
                                         " events since the last integrity check "
                                         "(from byte " +
                                         std::to_string(block.front().offset) + ") are not used"));
      block.clear();
      break;
    }
    if (event.channel == kRecCheckChannel) {
      ambdrop_lcm::record_check_t c{};
      const bool decoded = Decode(event, &c);
      if (!decoded || c.event_count != static_cast<std::int64_t>(block.size()) ||
          static_cast<std::uint64_t>(c.fnv1a64) != hash) {
        file.damaged = true;
        file.warnings.push_back(
            path.string() + ": corrupt: the integrity check " + At(event) + " does not match " +
            (block.empty() ? std::string("its events")
                           : "events " + std::to_string(block.front().number) + ".." +
                                 std::to_string(block.back().number) + " (from byte " +
                                 std::to_string(block.front().offset) + ")") +
            "; they and what follows are not used");
        block.clear();
        break;
      }
      for (const LogEvent& e : block) {
        if (!builder.Apply(e)) {
          stopped = true;
          break;
        }
      }
      block.clear();
      hash = kFnv1a64Basis;
      if (stopped) break;
      continue;
    }
    hash = Fnv1a64(event.channel, hash);
    hash = Fnv1a64(std::span<const std::uint8_t>(event.data), hash);
    block.push_back(std::move(event));
    event = LogEvent{};
  }
  // Whole events that no check covers (truncated file, recorder killed): used, with the
  // warning above.
  if (!stopped) {
    for (const LogEvent& e : block) {
      if (!builder.Apply(e)) break;
    }
  }
  if (!builder.has_header()) {
    throw std::runtime_error(path.string() + ": not an ambdrop run record (no valid header)" +
                             (file.warnings.empty() ? std::string() : ": " + file.warnings[0]));
  }
  if (!builder.has_start()) {
    throw std::runtime_error(path.string() + ": the record holds no start event");
  }
  const bool footer_in_range = file.footer && file.footer->final_step >= builder.last_step() &&
                               file.footer->final_step <= file.header.total_steps;
  if (file.footer && !file.damaged && !footer_in_range) {
    file.damaged = true;
    file.warnings.push_back(fmt::format(
        "the footer's final step {} is outside the recorded steps {}..{}: it is not used",
        file.footer->final_step, builder.last_step(), file.header.total_steps));
  }
  if (file.footer && !file.damaged) {
    file.run.end_step = file.footer->final_step;
    if (!(file.footer->produced == file.footer->written)) {
      file.warnings.push_back(
          "the recorder fell behind during the run: the footer counts fewer events written "
          "than produced; the replay misses those events");
    }
  } else {
    file.run.end_step = builder.last_step();
    file.warnings.push_back("no footer: the replay ends at the last recorded step, " +
                            std::to_string(file.run.end_step));
  }
  return file;
}

}  // namespace ambdrop
