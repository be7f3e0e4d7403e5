#pragma once
// Parameters of the in-process controller's general linear form ([controller.linear]), of the
// computation delay and of the amplifier current loop ([controller.amplifier]). The PID form
// ([controller.pid], PidParams) keeps its own parameters and code path.
#include <array>
#include <limits>
#include <vector>

namespace ambdrop {

/// Which table the in-process controller is built from.
enum class ControllerForm {
  kPid,     ///< [controller.pid]: seed 003's PID (controller.kind = "internal_pid")
  kLinear,  ///< [controller.linear]: a cascade of sections (controller.kind = "internal_linear")
};

/// How a continuous section becomes a z-domain biquad at the controller period.
enum class Discretisation { kTustin, kZeroOrderHold, kBackwardEuler };

enum class SectionKind { kGain, kPid, kLeadLag, kNotch, kLowPass, kSBiquad, kZBiquad };

/// What the integrating sections do while the output current is limited.
enum class AntiWindup {
  kConditional,      ///< hold their states (today's PID rule)
  kBackCalculation,  ///< feed the limited excess back into them over back_calculation_time_s
  kNone,
};

inline constexpr int kMaxControllerSections = 8;
inline constexpr int kMaxDelaySamples = 16;

/// One section of the cascade. Only the fields of its kind are read.
struct ControllerSectionParams {
  SectionKind kind = SectionKind::kGain;
  Discretisation discretisation = Discretisation::kTustin;
  double prewarp_Hz = 0.0;  ///< Tustin only; 0: none
  double gain = 1.0;        ///< gain; lead_lag: its DC gain
  double kp = 0.0;
  double ki_per_s = 0.0;
  double kd_s = 0.0;
  double derivative_filter_s = 0.0;
  double zero_Hz = 0.0;                       ///< lead_lag
  double pole_Hz = 0.0;                       ///< lead_lag
  double frequency_Hz = 0.0;                  ///< notch
  double zero_damping = 0.0;                  ///< notch: 0, an infinitely deep notch
  double pole_damping = 0.0;                  ///< notch: sets its width
  double cutoff_Hz = 0.0;                     ///< low_pass
  int order = 1;                              ///< low_pass: 1 or 2
  double damping_ratio = 0.7071067811865476;  ///< low_pass of order 2
  /// s_biquad: coefficients of s^2, s, 1; z_biquad: of 1, z^-1, z^-2.
  std::array<double, 3> numerator{};
  std::array<double, 3> denominator{};
  friend bool operator==(const ControllerSectionParams&, const ControllerSectionParams&) = default;
};

/// u = sections(e), e = -Gs * reading (V); command i = Ga u + i_ff (A), limited.
struct LinearControllerParams {
  double sensor_gain_V_per_m = 20000.0;
  double amplifier_gain_A_per_V = 0.4;
  bool gravity_feedforward = true;
  AntiWindup anti_windup = AntiWindup::kConditional;
  double back_calculation_time_s = 0.0;
  std::vector<ControllerSectionParams> sections;
  friend bool operator==(const LinearControllerParams&, const LinearControllerParams&) = default;
};

/// The amplifier's current loop between the command and the coil current.
struct AmplifierParams {
  bool enabled = false;
  int order = 1;
  double bandwidth_Hz = 0.0;
  double damping_ratio = 0.7071067811865476;                           ///< order 2
  double slew_rate_A_per_s = std::numeric_limits<double>::infinity();  ///< inf: no limit
  friend bool operator==(const AmplifierParams&, const AmplifierParams&) = default;
};

}  // namespace ambdrop
