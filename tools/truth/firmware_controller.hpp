#pragma once
// One AMB axis of a firmware-style controller: e = -Gs * reading (V), the sections of
// ControllerRig in cascade, command = Ga * u + feedforward (A), limited. No integral: the
// feedforward carries the static load. Each section H(s) = (b2 s^2 + b1 s + b0) /
// (a2 s^2 + a1 s + a0) is discretised by Tustin's substitution s = c (1 - 1/z) / (1 + 1/z),
// c = 2 / T, or c = w0 / tan(w0 T / 2) prewarped at w0 so that H(exp(j w0 T)) = H(j w0)
// (Franklin, Powell & Workman, "Digital Control of Dynamic Systems", 3rd ed., Sec. 6.3.1),
// and run as y = b0' x + s1, s1 = b1' x - a1' y + s2, s2 = b2' x - a2' y (a direct form II
// transposed biquad: Oppenheim & Schafer, "Discrete-Time Signal Processing", Sec. 6.5).
#include <array>
#include <complex>
#include <vector>

#include "rig.hpp"

namespace ambdrop_truth {

/// A discrete biquad (b0 + b1/z + b2/z^2) / (1 + a1/z + a2/z^2).
struct Biquad {
  std::array<double, 3> b{1.0, 0.0, 0.0};
  std::array<double, 3> a{1.0, 0.0, 0.0};
  std::complex<double> Response(double w_rad_s, double period_s) const;
};

/// The section's continuous coefficients (b2, b1, b0) and (a2, a1, a0).
void SectionPolynomials(const FirmwareSectionRig& s, std::array<double, 3>* num,
                        std::array<double, 3>* den);
/// Its response H(j w).
std::complex<double> SectionResponse(const FirmwareSectionRig& s, double w_rad_s);
/// Tustin (prewarped at s.prewarp_Hz when > 0) at `period_s`.
Biquad Discretise(const FirmwareSectionRig& s, double period_s);

class FirmwareAxis {
 public:
  FirmwareAxis() = default;
  FirmwareAxis(const ControllerRig& c, double limit_A, double feedforward_A);
  /// The limited command for one sensor reading (m).
  double Update(double reading_m);

 private:
  ControllerRig c_{};
  double limit_A_ = 0.0;
  double feedforward_A_ = 0.0;
  std::vector<Biquad> sections_;
  std::vector<std::array<double, 2>> state_;
};

}  // namespace ambdrop_truth
