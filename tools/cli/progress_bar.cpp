#include "tools/cli/progress_bar.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace ambdrop {
namespace {

constexpr int kBarWidth = 40;

std::string FormatSeconds(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0.0) return "--";
  if (seconds < 60.0) return fmt::format("{:.1f} s", seconds);
  const int total = static_cast<int>(seconds);
  return fmt::format("{}:{:02d} min", total / 60, total % 60);
}

}  // namespace

ProgressBar::ProgressBar(bool enabled, std::FILE* stream)
    : enabled_(enabled),
      stream_(stream),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_ - kMinInterval) {}

ProgressBar::~ProgressBar() {
  Finish();
}

bool ProgressBar::IsTerminal(int fd) {
  return ::isatty(fd) == 1;
}

void ProgressBar::Update(double fraction) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_draw_ < kMinInterval) return;
  last_draw_ = now;
  Draw(fraction);
}

void ProgressBar::Draw(double fraction) {
  fraction = std::clamp(std::isfinite(fraction) ? fraction : 0.0, 0.0, 1.0);
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double remaining = fraction > 0.0 ? elapsed * (1.0 - fraction) / fraction : -1.0;
  const int filled = static_cast<int>(fraction * kBarWidth);
  const std::string bar = std::string(filled, '#') + std::string(kBarWidth - filled, '.');
  // \r returns to the start of the line; \033[K clears what a longer previous draw left.
  fmt::print(stream_, "\r[{}] {:5.1f} %  elapsed {}  left {}\033[K", bar, 100.0 * fraction,
             FormatSeconds(elapsed), FormatSeconds(remaining));
  std::fflush(stream_);
  drawn_ = true;
}

void ProgressBar::Finish() {
  if (!enabled_ || !drawn_) return;
  fmt::print(stream_, "\r\033[K");
  std::fflush(stream_);
  drawn_ = false;
}

}  // namespace ambdrop
