#pragma once
// The size of a journal orbit as one number: the RMS distance of the journal from its mean
// position, seed 003's "vibration amplitude" (its Sec. 3 compares orbit plots; a mean-centred
// RMS does not reward an orbit for merely sitting lower in the race).
#include <cstdint>

namespace ambdrop {

class OrbitRms {
 public:
  void Add(double x_m, double y_m) noexcept;
  /// 0 before the first sample.
  double rms_m() const noexcept;
  std::int64_t samples() const noexcept { return n_; }

 private:
  double sx_ = 0.0, sy_ = 0.0, sxx_ = 0.0, syy_ = 0.0;
  std::int64_t n_ = 0;
};

}  // namespace ambdrop
