#include "tools/record/candump_record.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <optional>
#include <stdexcept>

#include "controller_if/loop/hil_session.hpp"
#include "io/can/can_controller_view.hpp"

namespace ambdrop {
namespace {

int HexDigit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

struct LogLine {
  double time_s = 0.0;
  CanFrame frame;
  std::int64_t number = 0;  ///< line number in the file
};

// One line of candump -l; nullopt if malformed.
std::optional<LogLine> ParseLine(const std::string& line) {
  LogLine out;
  if (line.size() < 4 || line[0] != '(') return std::nullopt;
  const std::size_t close = line.find(')');
  if (close == std::string::npos) return std::nullopt;
  try {
    std::size_t used = 0;
    out.time_s = std::stod(line.substr(1, close - 1), &used);
    if (used != close - 1) return std::nullopt;
  } catch (const std::exception&) {
    return std::nullopt;
  }
  const std::size_t iface_start = line.find_first_not_of(' ', close + 1);
  if (iface_start == std::string::npos) return std::nullopt;
  const std::size_t iface_end = line.find(' ', iface_start);
  if (iface_end == std::string::npos) return std::nullopt;
  std::string frame = line.substr(iface_end + 1);
  while (!frame.empty() && (frame.back() == ' ' || frame.back() == '\r')) frame.pop_back();
  const std::size_t hash = frame.find('#');
  if (hash == std::string::npos || (hash != 3 && hash != 8)) return std::nullopt;
  std::uint32_t id = 0;
  for (std::size_t i = 0; i < hash; ++i) {
    const int d = HexDigit(frame[i]);
    if (d < 0) return std::nullopt;
    id = (id << 4) | static_cast<std::uint32_t>(d);
  }
  out.frame.extended = hash == 8;
  out.frame.id = id;
  if (id > (out.frame.extended ? 0x1FFFFFFFU : 0x7FFU)) return std::nullopt;
  std::size_t pos = hash + 1;
  if (pos < frame.size() && frame[pos] == '#') {  // FD: ##<flags><data>
    out.frame.fd = true;
    if (pos + 1 >= frame.size()) return std::nullopt;
    const int flags = HexDigit(frame[pos + 1]);
    if (flags < 0) return std::nullopt;
    out.frame.brs = (flags & 1) != 0;
    out.frame.esi = (flags & 2) != 0;
    pos += 2;
  } else if (pos < frame.size() && (frame[pos] == 'R' || frame[pos] == 'r')) {
    out.frame.rtr = true;
    return out;
  }
  const std::size_t hex = frame.size() - pos;
  const std::size_t max_len = out.frame.fd ? kCanFdMaxLen : 8;
  if (hex % 2 != 0 || hex / 2 > max_len) return std::nullopt;
  for (std::size_t i = 0; i < hex / 2; ++i) {
    const int hi = HexDigit(frame[pos + 2 * i]);
    const int lo = HexDigit(frame[pos + 2 * i + 1]);
    if (hi < 0 || lo < 0) return std::nullopt;
    out.frame.data[i] = static_cast<std::uint8_t>(hi * 16 + lo);
  }
  out.frame.len = static_cast<std::uint8_t>(hex / 2);
  return out;
}

}  // namespace

bool IsCandumpLog(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string line;
  // The whole first line must be a candump -l frame: a binary file (an LCM record, garbage)
  // begins with '(' once in 256.
  return static_cast<bool>(std::getline(in, line)) && ParseLine(line).has_value();
}

CandumpRecord ReadCandumpRecord(const std::filesystem::path& path, const Model& model,
                                const CanConfig& can, CandumpAlign align) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot open");
  std::vector<LogLine> lines;
  CandumpRecord record;
  // The first few lines of each kind of damage, with line numbers; the counts say the rest.
  const auto warn = [&](std::int64_t count, std::int64_t number, const std::string& what) {
    if (count <= 5) {
      record.warnings.push_back(path.string() + ":" + std::to_string(number) + ": " + what);
    }
  };
  std::string text;
  double last_time_s = -std::numeric_limits<double>::infinity();
  for (std::int64_t number = 1; std::getline(in, text); ++number) {
    if (text.empty()) continue;
    std::optional<LogLine> line = ParseLine(text);
    if (!line) {
      warn(++record.malformed_lines, number,
           "not a candump -l line, skipped: " + text.substr(0, 60));
      continue;
    }
    // stod reads "nan" and "inf"; such a time cannot place a frame at a step.
    if (!std::isfinite(line->time_s)) {
      warn(++record.malformed_lines, number,
           "the receive time is not a finite number, skipped: " + text.substr(0, 60));
      continue;
    }
    // candump stamps the frames of one bus in order: an earlier time means an edited or merged
    // log, whose frames would be applied out of order.
    if (line->time_s < last_time_s) {
      warn(++record.out_of_order_lines, number,
           fmt::format("the receive time {:.6f} s is before the previous line's {:.6f} s, "
                       "skipped",
                       line->time_s, last_time_s));
      continue;
    }
    last_time_s = line->time_s;
    line->number = number;
    lines.push_back(*line);
  }
  record.frames = static_cast<std::int64_t>(lines.size());

  // Time zero: the emulator's first sensor frame.
  const FrameMap& map = can.frame_map;
  const ControllerFrameView view(map);
  FrameMapCounters view_counters;
  std::optional<double> t0;
  for (const LogLine& l : lines) {
    EmulatorOutputs scratch;
    if (view.Decode(l.frame, &scratch, &view_counters) == DecodeResult::kApplied &&
        view.CompletesSensors(l.frame)) {
      t0 = l.time_s;
      break;
    }
  }
  if (!t0) {
    throw std::runtime_error(path.string() +
                             ": no sensor frame of the config's [can] map: cannot tell when the "
                             "run started");
  }

  const std::int64_t substeps = ControllerSubsteps(model);
  const double period_s = static_cast<double>(substeps) * model.params.simulation.step_s;
  const ControlInput initial = StaticLoadInput(model);
  record.run.start.equilibrium_input = initial;
  CanCommand command;
  for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
    record.run.start.loop_current_A[a] = initial.amb[a].current_A;
    command.current_A[a] = initial.amb[a].current_A;
  }
  record.run.sensor_every_steps = substeps;
  FrameMapCounters counters;
  EmulatorOutputs outputs;
  std::int64_t last_step = 0;
  // Frames after the run's end cannot act on it; the bound also keeps the time-to-step
  // conversions below inside int64 for any finite time.
  const std::int64_t last_period = model.total_steps / substeps + 1;
  // Sequence alignment: samples per exchange (the link sends every n-th sample).
  const double exchange_Hz = can.exchange_rate_Hz > 0.0 ? can.exchange_rate_Hz : 1.0 / period_s;
  const std::int64_t per_exchange =
      std::max<std::int64_t>(1, std::llround(1.0 / (exchange_Hz * period_s)));
  std::int64_t exchanges = 0;  // sensor frames completed so far
  for (const LogLine& l : lines) {
    if (l.time_s < *t0) continue;
    // The time this frame stands for: its receive time, or (by sequence) the time of the last
    // exchange completed before it.
    const double since =
        align == CandumpAlign::kTime
            ? l.time_s - *t0
            : static_cast<double>(std::max<std::int64_t>(exchanges - 1, 0) * per_exchange) *
                  period_s;
    if (!(since / period_s < static_cast<double>(last_period))) {
      if (++record.frames_after_end == 1) {
        record.warnings.push_back(fmt::format(
            "{}:{}: the frames from {:.6g} s after the first sensor frame on are beyond the "
            "run's {:.6g} s and are not used",
            path.string(), l.number, since,
            static_cast<double>(model.total_steps) * model.params.simulation.step_s));
      }
      continue;
    }
    const std::uint64_t fails = command.power_fail_frames;
    const std::uint64_t restores = command.power_restore_frames;
    const auto before = command.current_A;
    if (map.Decode(l.frame, &command, &counters) == DecodeResult::kApplied) {
      ++record.controller_frames;
      // The sample of step k S leaves at wall time k T after time zero, at the end of the
      // deadline that computed steps (k-1) S .. k S. A frame arriving between n T and (n+1) T is
      // polled at the next deadline, which computes the period from step n S.
      // By sequence the period is counted, not computed from a time (no rounding).
      const auto n = align == CandumpAlign::kTime
                         ? static_cast<std::int64_t>(std::floor(since / period_s))
                         : std::max<std::int64_t>(exchanges - 1, 0) * per_exchange;
      const std::int64_t step = n * substeps;
      last_step = std::max(last_step, step);
      if (command.power_fail_frames != fails || command.power_restore_frames != restores) {
        RecordedPower p;
        p.step = step;
        p.event.restore = command.power_restore_frames != restores;
        record.run.power.push_back(p);
      }
      if (command.current_A != before) {
        RecordedInput in;
        in.step = step;
        in.receive_ns = std::llround(since * 1e9);
        in.current_A = command.current_A;
        record.run.inputs.push_back(in);
      }
      continue;
    }
    if (view.Decode(l.frame, &outputs, &view_counters) == DecodeResult::kApplied) {
      if (view.CompletesSensors(l.frame)) {
        RecordedSensors s;
        s.step = align == CandumpAlign::kTime ? std::llround(since / period_s) * substeps
                                              : exchanges * per_exchange * substeps;
        ++exchanges;
        s.time_s = static_cast<double>(s.step) * model.params.simulation.step_s;
        for (int i = 0; i < kMaxSensors; ++i) s.readings.reading_m[i] = outputs.sensor_xy_m[i];
        if (record.sensors.empty() || s.step > record.sensors.back().step) {
          record.sensors.push_back(s);
        }
        last_step = std::max(last_step, s.step);
      }
      continue;
    }
    ++record.unknown_frames;
  }
  record.run.end_step = std::min(model.total_steps, last_step);
  return record;
}

}  // namespace ambdrop
