#pragma once
// One record: the rotor levitated by its PIDs from its static equilibrium, the power fails at
// the trigger, the rotor drops onto its TDBs. The plant steps at the rig's fine step; the
// controller samples its sensors at its rate and applies each command after its computation
// delay; the acquisition samples at its own rate with its own noise.
#include <array>
#include <cstdint>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include "plant.hpp"
#include "rig.hpp"

namespace ambdrop_truth {

/// A speed in rpm per the same in rad/s (the record's speed columns are in rpm unless --si).
inline constexpr double kRpmPerRadPerS = 60.0 / (2.0 * std::numbers::pi);

/// One acquisition sample, SI.
struct RecordRow {
  double t_s = 0.0;
  std::array<std::array<double, 2>, 2> displacement_m{};  ///< [sensor][axis], as read
  std::array<std::array<double, 2>, 2> current_A{};       ///< [amb][axis] coil control current
  std::array<std::array<double, 2>, 2> command_A{};       ///< [amb][axis] controller command
  std::array<double, 2> race_speed_rad_s{};
  double rotor_speed_rad_s = 0.0;
  std::array<double, 2> normal_force_N{};
  std::array<std::array<double, 2>, 2> support_force_N{};  ///< [tdb][axis] load cell, tared
};

struct RunOptions {
  /// Start at the static equilibrium with the integrals holding the static load (a machine
  /// levitated for long); false: centred, integrals empty.
  bool start_at_equilibrium = true;
  bool add_noise = true;
  /// The record's channels exact (no acquisition noise, no quantisation) while the controller
  /// still reads noisy sensors: the rotor's noise-driven motion is kept and seen as it is
  /// (diagnosis of a fit's start estimate). Without add_noise it changes nothing.
  bool exact_record = false;
  /// Called after every fine step with the time and state (tests); may be empty.
  std::function<void(double, const PlantState&)> on_step;
};

struct RunResult {
  std::vector<RecordRow> rows;
  bool finite = true;
  /// Empty, or where the rotor left the physics the generator models: it reached an AMB's
  /// poles (the magnet law holds inside the air gap; nothing models a pole strike), so the
  /// record is no drop onto the TDBs.
  std::string left_physics;
};

RunResult RunDrop(const Rig& rig, std::uint64_t seed, const RunOptions& options = {});

/// The control current limit of an AMB axis: both coils inside [0, coil limit]; with a
/// magnet's bias the amplifier's control current within the limit and the bias.
double ControlCurrentLimit(const AmbRig& a);

/// The forces [amb][axis] (N) the AMBs exert when they carry the static load (weight, side
/// pull) alone: sums of forces and moments about the centre of mass zero.
std::array<std::array<double, 2>, 2> StaticAmbForces(const Rig& rig);

/// The initial state at the static equilibrium (readings zero, static load carried) and the
/// control current each AMB axis then holds.
PlantState EquilibriumState(const Rig& rig, std::array<std::array<double, 2>, 2>* held_A);

}  // namespace ambdrop_truth
