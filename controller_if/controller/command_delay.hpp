#pragma once
// The computation delay: the command computed from sample n is applied at sample n + d.
#include <array>

#include "rt_core/controller_form_params.hpp"

namespace ambdrop {

class CommandDelay {
 public:
  CommandDelay() = default;
  /// Before d commands have been computed, the delay line gives `initial_A`.
  CommandDelay(int samples, double initial_A) : samples_(samples) { line_.fill(initial_A); }

  double Push(double command_A) noexcept {
    if (samples_ == 0) return command_A;
    const double out = line_[next_];
    line_[next_] = command_A;
    next_ = next_ + 1 == samples_ ? 0 : next_ + 1;
    return out;
  }

 private:
  std::array<double, kMaxDelaySamples> line_{};
  int samples_ = 0;
  int next_ = 0;
};

}  // namespace ambdrop
