#pragma once
// The [realtime] table of a config: what `ambdrop hil` asks of the operating system for its loop
// thread. Host settings, not physics: `ambdrop sim` ignores them, and the command line's
// --rt-priority, --cpu, --spin-us and --enforce-rt override them.
//
//   [realtime]
//   priority = 80     # SCHED_FIFO priority 1..99; 0 (default): normal scheduling (SCHED_OTHER)
//   cpu = 1           # CPU to pin the loop thread to, 0-based; -1 (default): any
//   spin_s = 20e-6    # poll the clock for the last spin_s before each deadline instead of
//                     # sleeping (s, 0..0.01; default 0): removes the wake-up latency at the cost
//                     # of that much CPU per period. With priority > 0 a spin near the period
//                     # trips the kernel's RT throttling (README, "Real-time").
//   enforce = false   # a refused request (priority, CPU, memory lock) is an error, not a warning
#include <optional>

namespace ambdrop {

namespace config_detail {
class TableReader;
}

/// A validated [realtime] table.
struct RealtimeConfig {
  int priority = 0;     ///< SCHED_FIFO priority 1..99; 0: SCHED_OTHER
  int cpu = -1;         ///< CPU to pin the loop thread to; -1: any
  double spin_s = 0.0;  ///< clock polling before each deadline, s
  bool enforce = false;
};

/// Reads the optional [realtime] table of `root`; defaults when it is absent. Unknown keys, wrong
/// types and out-of-range values are ConfigError naming file, line and key.
RealtimeConfig ReadRealtimeConfig(const config_detail::TableReader& root);

}  // namespace ambdrop
