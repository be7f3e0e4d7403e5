#include "controller_if/controller/discrete_controller.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "controller_if/controller/controller_discretisation.hpp"

namespace ambdrop {

LinearAxis::LinearAxis(const LinearControllerParams& p, double period_s, double feedforward_A,
                       double limit_A)
    : count_(static_cast<int>(p.sections.size())),
      sensor_gain_V_per_m_(p.sensor_gain_V_per_m),
      amplifier_gain_A_per_V_(p.amplifier_gain_A_per_V),
      feedforward_A_(feedforward_A),
      limit_A_(limit_A),
      anti_windup_(p.anti_windup) {
  if (count_ > kMaxControllerSections) {
    throw std::invalid_argument("more controller sections than kMaxControllerSections");
  }
  for (int i = 0; i < count_; ++i) sections_[i] = Biquad(SectionBiquad(p.sections[i], period_s));
  if (anti_windup_ != AntiWindup::kBackCalculation) return;
  // The integrating section nearest the output: the sections after it pass DC at a finite gain,
  // which turns the excess at the output into a correction of its own output.
  for (int i = count_ - 1; i >= 0 && back_calculation_section_ < 0; --i) {
    if (sections_[i].coefficients().Integrates()) back_calculation_section_ = i;
  }
  double gain = 1.0;
  for (int i = back_calculation_section_ + 1; i < count_; ++i) {
    const BiquadCoefficients& c = sections_[i].coefficients();
    gain *= (c.b0 + c.b1 + c.b2) / (1.0 + c.a1 + c.a2);
  }
  if (back_calculation_section_ < 0 || !std::isfinite(gain) || std::abs(gain) < 1e-12) {
    throw std::invalid_argument(
        "anti_windup = \"back_calculation\" needs an integrating section (a pid with ki_per_s > 0) "
        "whose later sections pass DC");
  }
  downstream_dc_gain_ = gain;
  back_calculation_gain_ = period_s / p.back_calculation_time_s;
}

void LinearAxis::HoldAtRest(double reading_m, double current_A) noexcept {
  int last = -1;
  for (int i = count_ - 1; i >= 0 && last < 0; --i) {
    if (sections_[i].coefficients().Integrates()) last = i;
  }
  const auto dc_gain = [this](int i) {
    const BiquadCoefficients& c = sections_[i].coefficients();
    return (c.b0 + c.b1 + c.b2) / (1.0 + c.a1 + c.a2);
  };
  // What the sections after the integrator make of the integral it holds.
  double downstream = 1.0;
  for (int i = last + 1; i < count_; ++i) downstream *= dc_gain(i);
  const double held_V = (current_A - feedforward_A_) / amplifier_gain_A_per_V_;
  double x = -sensor_gain_V_per_m_ * reading_m;
  for (int i = 0; i < count_; ++i) {
    double y = 0.0;  // an earlier integrator rests empty (its input is zero)
    if (i == last) {
      y = held_V / downstream;
    } else if (!sections_[i].coefficients().Integrates()) {
      y = dc_gain(i) * x;
    }
    sections_[i].HoldAt(x, y);
    x = y;
  }
  unlimited_A_ = current_A;
}

double LinearAxis::Update(double reading_m) noexcept {
  std::array<double, kMaxControllerSections> held_s1{};
  std::array<double, kMaxControllerSections> held_s2{};
  for (int i = 0; i < count_; ++i) {
    held_s1[i] = sections_[i].s1();
    held_s2[i] = sections_[i].s2();
  }
  double u = -sensor_gain_V_per_m_ * reading_m;
  for (int i = 0; i < count_; ++i) u = sections_[i].Update(u);
  unlimited_A_ = amplifier_gain_A_per_V_ * u + feedforward_A_;
  const double limited = std::clamp(unlimited_A_, -limit_A_, limit_A_);
  if (limited == unlimited_A_) return limited;
  switch (anti_windup_) {
    case AntiWindup::kConditional:
      // The integrators do not take this sample in while the output is limited (today's PID
      // rule, Åström & Hägglund, "Advanced PID Control", 2006, Sec. 3.5 "conditional
      // integration").
      for (int i = 0; i < count_; ++i) {
        if (sections_[i].coefficients().Integrates()) sections_[i].SetState(held_s1[i], held_s2[i]);
      }
      break;
    case AntiWindup::kBackCalculation: {
      // I += (T / Tt) (limited - unlimited) (Åström & Hägglund 2006, Sec. 3.5, Fig. 3.12), in
      // volts at the section's output.
      const double excess_V = (limited - unlimited_A_) / amplifier_gain_A_per_V_;
      sections_[back_calculation_section_].AddToIntegral(back_calculation_gain_ * excess_V /
                                                         downstream_dc_gain_);
      break;
    }
    case AntiWindup::kNone:
      break;
  }
  return limited;
}

}  // namespace ambdrop
