#pragma once
/// Compile-time capacities. The step works on fixed-capacity Eigen objects so it never touches
/// the heap; a config that needs more is rejected when the model is built.
namespace ambdrop {
inline constexpr int kMaxModes = 40;                ///< generalized rotor coordinates
inline constexpr int kMaxTdbs = 4;                  ///< touchdown bearings
inline constexpr int kMaxTdbStates = 16;            ///< internal states of one touchdown bearing
inline constexpr int kMaxAmbs = 4;                  ///< radial magnetic bearings
inline constexpr int kMaxSensors = 8;               ///< displacement sensor planes
inline constexpr int kMaxUnbalances = 8;            ///< unbalance masses
inline constexpr int kMaxLinearBearings = 4;        ///< linear spring/damper supports
inline constexpr int kMaxProfilePoints = 1024;      ///< points of one coil-current profile
inline constexpr int kMaxSensorDelaySamples = 256;  ///< a sensor lag's ring of samples
inline constexpr int kMaxStateSize = 2 * kMaxModes + 2 + kMaxTdbs * kMaxTdbStates;
}  // namespace ambdrop
