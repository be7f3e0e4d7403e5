#pragma once
// Whirl classification of a journal orbit after the drop transient (Jarroux 2016, seed 001,
// Sec. 3): rocking motion (RM, the journal swings at the bottom of the race without going
// round), backward whirl (BWM, it rolls round the race against the spin) or forward whirl.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <span>

namespace ambdrop {

enum class WhirlKind {
  kNone,           ///< too few samples, or the journal is not on the race
  kRocking,        ///< oscillates without completing a turn about the TDB centre
  kBackwardWhirl,  ///< goes round against the spin
  kForwardWhirl,   ///< goes round with the spin
};

/// "none", "rocking", "backward_whirl", "forward_whirl" (the summary.json spelling).
inline const char* WhirlName(WhirlKind kind) noexcept {
  switch (kind) {
    case WhirlKind::kRocking:
      return "rocking";
    case WhirlKind::kBackwardWhirl:
      return "backward_whirl";
    case WhirlKind::kForwardWhirl:
      return "forward_whirl";
    case WhirlKind::kNone:
      break;
  }
  return "none";
}

/// One journal position relative to the TDB centre, with the rotor spin at that time.
struct OrbitSample {
  double time_s = 0.0;
  double x_m = 0.0;
  double y_m = 0.0;
  double spin_rad_s = 0.0;
};

struct WhirlClassification {
  WhirlKind kind = WhirlKind::kNone;
  /// Whirl: mean angular speed of the journal-centre vector over the mean spin speed, signed
  /// (> 0 with the spin, < 0 against it). Rocking: swing frequency over spin frequency (> 0).
  /// 0 for none, or when the rotor does not spin.
  double frequency_ratio = 0.0;
  double frequency_Hz = 0.0;  ///< whirl (> 0 along +z) or swing frequency
  double revolutions = 0.0;   ///< net turns of the journal-centre vector about +z
};

/// Thresholds of ClassifyWhirl.
struct WhirlClassifierOptions {
  /// The journal counts as on the race when its mean radius is at least this share of the
  /// clearance (a levitated rotor's small unbalance orbit is "none").
  double min_radius_over_clearance = 0.5;
  /// Net turns about the TDB centre needed to call the motion a whirl.
  double min_revolutions = 1.0;
};

/// Classifies an orbit (samples in time order, relative to the TDB centre):
///  - the angle of the journal-centre vector is unwrapped sample to sample; its net change over
///    the window, in turns, is the orbit's circulation;
///  - at least min_revolutions turns: a whirl, forward when it turns with the spin (about +z
///    when the spin is >= 0), backward against it; its frequency is the mean angular speed;
///  - fewer: rocking, at the frequency of the angle's crossings of its mean (with a hysteresis of
///    a tenth of its RMS swing so that contact chatter does not count).
inline WhirlClassification ClassifyWhirl(std::span<const OrbitSample> orbit, double clearance_m,
                                         const WhirlClassifierOptions& options = {}) noexcept {
  WhirlClassification result;
  const std::size_t n = orbit.size();
  if (n < 3) return result;
  const double duration_s = orbit[n - 1].time_s - orbit[0].time_s;
  if (!(duration_s > 0.0)) return result;
  constexpr double kTwoPi = 2.0 * std::numbers::pi;

  // Mean radius and spin; unwrapped angle, its net change, mean and RMS.
  double radius_sum = 0.0, spin_sum = 0.0;
  double angle = std::atan2(orbit[0].y_m, orbit[0].x_m);
  double previous = angle;
  double angle_sum = 0.0, angle_sq_sum = 0.0;
  const double start = angle;
  for (std::size_t i = 0; i < n; ++i) {
    radius_sum += std::hypot(orbit[i].x_m, orbit[i].y_m);
    spin_sum += orbit[i].spin_rad_s;
    const double wrapped = std::atan2(orbit[i].y_m, orbit[i].x_m);
    double step = wrapped - previous;
    step -= kTwoPi * std::round(step / kTwoPi);
    angle += i == 0 ? 0.0 : step;
    previous = wrapped;
    angle_sum += angle;
    angle_sq_sum += angle * angle;
  }
  const double mean_radius = radius_sum / static_cast<double>(n);
  if (!(mean_radius >= options.min_radius_over_clearance * clearance_m)) return result;
  const double spin = spin_sum / static_cast<double>(n);
  result.revolutions = (angle - start) / kTwoPi;

  // Whirl: net circulation, forward or backward relative to the spin.
  if (std::abs(result.revolutions) >= options.min_revolutions) {
    const double whirl_rad_s = (angle - start) / duration_s;
    const bool forward = spin < 0.0 ? whirl_rad_s < 0.0 : whirl_rad_s > 0.0;
    result.kind = forward ? WhirlKind::kForwardWhirl : WhirlKind::kBackwardWhirl;
    result.frequency_Hz = whirl_rad_s / kTwoPi;
    result.frequency_ratio = spin != 0.0 ? whirl_rad_s / spin : 0.0;
    return result;
  }

  // Rocking: swing frequency from the crossings of the mean angle.
  result.kind = WhirlKind::kRocking;
  const double mean = angle_sum / static_cast<double>(n);
  const double variance = std::max(0.0, angle_sq_sum / static_cast<double>(n) - mean * mean);
  const double band = 0.1 * std::sqrt(variance);
  int crossings = 0;
  int side = 0;  // -1 below mean - band, +1 above mean + band
  angle = std::atan2(orbit[0].y_m, orbit[0].x_m);
  previous = angle;
  for (std::size_t i = 0; i < n; ++i) {
    const double wrapped = std::atan2(orbit[i].y_m, orbit[i].x_m);
    double step = wrapped - previous;
    step -= kTwoPi * std::round(step / kTwoPi);
    angle += i == 0 ? 0.0 : step;
    previous = wrapped;
    const int now = angle > mean + band ? 1 : angle < mean - band ? -1 : 0;
    if (now != 0 && side != 0 && now != side) ++crossings;
    if (now != 0) side = now;
  }
  result.frequency_Hz = 0.5 * crossings / duration_s;
  result.frequency_ratio = spin != 0.0 ? kTwoPi * result.frequency_Hz / std::abs(spin) : 0.0;
  return result;
}

}  // namespace ambdrop
