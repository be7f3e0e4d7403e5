#pragma once
// A `candump -l` log (can-utils) as the input record of a replay: lines
//   (1700000000.123456) vcan0 100#0102030405060708     classic frame
//   (1700000000.123456) vcan0 123##1<payload>          CAN FD (## then the flags nibble)
//   (1700000000.123456) vcan0 123#R                    remote request
// The config's [can] frame map says what the frames mean. The controller's frames (currents,
// power fail/restore) become recorded inputs; the emulator's sensor frames become the record to
// compare with. Time zero is the emulator's first sensor frame (its step-0 sample, sent at the
// start of the run); the sample of step k S (S steps per period of T) leaves at k T. A controller
// frame that arrives between n T and (n+1) T is applied from step n S, as the live loop polls it
// at the next deadline, where it computes the period from step n S. Receive times on a bus are not
// the live loop's exact poll times, so a replay of a candump log agrees with the live run up to
// that timing (about a period), not bit for bit: the comparison reports the differences and does
// not fail on them.
#include <filesystem>
#include <string>
#include <vector>

#include "controller_if/loop/run_record.hpp"
#include "io/config/config_can.hpp"
#include "rt_core/model.hpp"

namespace ambdrop {

struct CandumpRecord {
  RecordedRun run;
  std::vector<RecordedSensors> sensors;  ///< the emulator's sensor frames, as decoded
  std::int64_t frames = 0;               ///< frames read
  std::int64_t controller_frames = 0;    ///< currents and trigger frames applied
  std::int64_t unknown_frames = 0;       ///< ids the frame map does not know (or malformed)
  std::vector<std::string> warnings;     ///< rejected lines (first few, with line numbers)
  std::int64_t malformed_lines = 0;      ///< not candump -l, or a receive time not finite
  std::int64_t out_of_order_lines = 0;   ///< a receive time before the previous line's
  std::int64_t frames_after_end = 0;     ///< received after the run's configured end
  /// Lines were rejected: the replay misses some of what the bus carried.
  bool damaged() const { return malformed_lines > 0 || out_of_order_lines > 0; }
};

/// How the log's frames are placed at steps.
enum class CandumpAlign {
  /// By receive time from the first sensor frame (a live, wall-clock run).
  kTime,
  /// By sequence: the k-th completed sensor frame is the k-th exchange (step k n S, n samples per
  /// exchange), and a controller frame after it applies from that step. A lock-step run on the
  /// virtual clock: its wall times say nothing of its steps.
  kSequence,
};

/// True if the file looks like a candump -l log (its first line starts with "(").
bool IsCandumpLog(const std::filesystem::path& path);

/// Reads the log. Throws std::runtime_error if the file cannot be read or holds no sensor frame
/// of the map (no time zero); malformed lines (a receive time that is not finite included),
/// lines whose time goes back, and frames after the run's end are counted and skipped.
CandumpRecord ReadCandumpRecord(const std::filesystem::path& path, const Model& model,
                                const CanConfig& can, CandumpAlign align = CandumpAlign::kTime);

}  // namespace ambdrop
