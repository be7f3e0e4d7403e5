#pragma once
#include <array>
#include <cstdint>

#include "rt_core/limits.hpp"

/// Fixed-size records the real-time loop exchanges with the HIL transport threads. They are
/// plain values (no pointers, no heap), so a SpscRing slot holds one by copy. The LCM message
/// types in io/lcm/lcm_types/ carry the same fields on the wire; io/lcm/lcm_transport.cpp converts.
namespace ambdrop {

/// Bits of HilTrigger::axis_mask and HilEmulatorState::powered_axes (same values as the
/// AXIS_* constants of ambdrop_lcm::trigger_t).
inline constexpr std::uint8_t kAxisX = 1;
inline constexpr std::uint8_t kAxisY = 2;
inline constexpr std::uint8_t kAxisAxial = 4;
inline constexpr std::uint8_t kAllAxes = kAxisX | kAxisY | kAxisAxial;
/// HilTrigger::amb_mask naming every AMB slot (bit i: AMB i).
inline constexpr std::uint8_t kAllAmbs = (1u << kMaxAmbs) - 1u;

/// Coil control currents from the controller for one controller cycle.
struct HilCurrents {
  std::int64_t utime_us = 0;  ///< sender's send time, us since the Unix epoch (informative)
  std::int64_t sequence = 0;  ///< sender's message counter (+1 per message)
  /// When the receive thread decoded it: CLOCK_MONOTONIC (std::chrono::steady_clock), ns, as
  /// the CAN link stamps its frames. Not on the wire; 0 on the sending side.
  std::int64_t receive_ns = 0;
  int amb_count = 0;  ///< AMBs carried, 0..kMaxAmbs; entries beyond are zero
  /// Control current (x, y) per AMB, A. AMB i is the i-th [amb.*] table of the rig config.
  std::array<std::array<double, 2>, kMaxAmbs> current_A{};
  bool axial_valid = false;      ///< axial_current_A holds a value
  double axial_current_A = 0.0;  ///< thrust-bearing control current, A
};

/// A power trigger: shut down (power_on false) or restore (power_on true) the named coils.
/// A full power failure is amb_mask = kAllAmbs, axis_mask = kAllAxes, power_on = false.
struct HilTrigger {
  std::int64_t utime_us = 0;   ///< sender time, us since the Unix epoch (informative)
  std::int64_t sequence = 0;   ///< sender's message counter
  bool power_on = false;       ///< false: the named coils lose power; true: they get it back
  std::uint8_t amb_mask = 0;   ///< bit i: AMB i affected; nonzero, within kAllAmbs
  std::uint8_t axis_mask = 0;  ///< kAxisX | kAxisY | kAxisAxial bits affected; nonzero
};

/// Emulated displacement-sensor readings for one output interval.
struct HilSensorReadings {
  std::int64_t utime_us = 0;    ///< wall-clock time the readings were taken, us since the epoch
  std::int64_t step_index = 0;  ///< physics step that produced them
  double time_s = 0.0;          ///< simulated time (step_index × step), s
  int sensor_count = 0;         ///< sensors carried, 0..kMaxSensors
  /// Rotor displacement (x, y) at each sensor plane, m. Sensor i is the i-th [sensor.*] table.
  std::array<std::array<double, 2>, kMaxSensors> position_m{};
  bool counts_valid = false;  ///< counts holds the readings converted by the rig's scaling
  /// Reading (x, y) as the rig's sensor electronics would output it, ADC counts.
  std::array<std::array<std::int32_t, 2>, kMaxSensors> counts{};
};

/// A power event as the emulator applied it, announced on LCM (ambdrop_lcm::power_event_t).
struct HilPowerEvent {
  std::int64_t utime_us = 0;    ///< wall-clock time of the event, us since the Unix epoch
  std::int64_t sequence = 0;    ///< 0 for a run's first event, +1 per event
  std::int64_t step_index = 0;  ///< physics step the event applies at
  double time_s = 0.0;          ///< simulated time of that step, s
  bool power_on = false;        ///< false: the named coils lost power; true: restored
  std::uint8_t amb_mask = 0;    ///< bit i: AMB i affected
  std::uint8_t axis_mask = 0;   ///< kAxis* bits affected
  bool motor = false;           ///< the drive too: a full failure (restore)
  /// Per AMB after the event: kAxis* bits of the coils that have power.
  std::array<std::uint8_t, kMaxAmbs> powered_axes{};
};

/// What one touchdown bearing reports in HilEmulatorState.
struct HilTdbState {
  double normal_force_N = 0.0;      ///< rotor / inner-race normal force (>= 0), N
  double tangential_force_N = 0.0;  ///< friction force on the inner race along the spin sense, N
  double penetration_m = 0.0;       ///< journal excursion beyond the clearance (< 0: free), m
  double race_speed_rad_s = 0.0;    ///< inner-race spin speed, rad/s
  std::array<double, 2> journal_xy_m{};  ///< journal centre (x, y) at the TDB plane, m
};

/// Full emulator state for monitoring and logging.
struct HilEmulatorState {
  std::int64_t utime_us = 0;    ///< wall-clock time of the state, us since the Unix epoch
  std::int64_t step_index = 0;  ///< physics step
  double time_s = 0.0;          ///< simulated time, s
  bool power_on = true;         ///< the motor drove the rotor in the last step
  /// Per AMB: kAxis* bits of the coils that have power.
  std::array<std::uint8_t, kMaxAmbs> powered_axes{};
  double spin_speed_rad_s = 0.0;  ///< rotor spin speed about +z, rad/s
  double spin_angle_rad = 0.0;    ///< rotor spin angle (not wrapped), rad
  int mode_count = 0;             ///< generalized coordinates in use, 0..kMaxModes
  /// Mass-normalised generalized coordinates [xz plane | yz plane], kg^0.5 m.
  std::array<double, kMaxModes> q{};
  std::array<double, kMaxModes> q_dot{};  ///< their rates, kg^0.5 m/s
  int tdb_count = 0;                      ///< touchdown bearings, 0..kMaxTdbs
  std::array<HilTdbState, kMaxTdbs> tdb{};
  std::int64_t fault_count = 0;  ///< faults the step has counted so far
};

}  // namespace ambdrop
