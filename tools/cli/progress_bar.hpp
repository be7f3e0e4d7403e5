#pragma once
#include <chrono>
#include <cstdio>

namespace ambdrop {

/// A one-line progress bar on a terminal stream (stderr by default), so it never mixes into
/// output that is piped or redirected. Redraws are rate-limited: the simulator may report
/// progress far more often than a terminal can usefully show it.
class ProgressBar {
 public:
  /// `enabled` false makes every call a no-op (not a terminal, or --quiet).
  explicit ProgressBar(bool enabled, std::FILE* stream = stderr);
  ~ProgressBar();

  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  /// True when `fd` is a terminal (isatty).
  static bool IsTerminal(int fd);

  /// `fraction` in [0, 1]; drawn at most every kMinInterval.
  void Update(double fraction);
  /// Clears the line so that what follows starts on a clean one. Idempotent.
  void Finish();

  static constexpr std::chrono::milliseconds kMinInterval{100};

 private:
  void Draw(double fraction);

  bool enabled_;
  bool drawn_ = false;
  std::FILE* stream_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
};

}  // namespace ambdrop
