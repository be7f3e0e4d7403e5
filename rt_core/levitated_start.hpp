#pragma once
// Where a rotor under the in-process controller starts: the static equilibrium the controller
// itself holds. A controller holds its sensors' readings, not the rotor: with a sensor offset the
// rotor sits where the reading is the set point, reading = gain (x + runout) + offset
// (docs/equations.md, "Sensors"; controller_if/boundary/sensor_emulator.cpp), and the controller's
// integrators carry whatever current holds it there.
#include <array>
#include <vector>

#include "rt_core/eigen_types.hpp"
#include "rt_core/model_params.hpp"

namespace ambdrop {

struct Model;

/// What the in-process controller does at rest, when its input is a constant reading r (m) and
/// nothing moves: derived from the DC gain of its form (the PID, or the cascade of sections; the
/// computation delay and the amplifier loop pass DC unchanged).
struct ControllerStaticLaw {
  enum class Kind {
    kHoldsReading,  ///< integral action: at rest the reading is held where it is set
    kProportional,  ///< no integral action: i = i_ff - gain_A_per_m * r
    kUnknown,       ///< an integrator and a DC-blocking section together: not derived
  };
  Kind kind = Kind::kUnknown;
  double gain_A_per_m = 0.0;  ///< kProportional: Ga * H(0) * Gs
};

/// The static law of `controller` (only meaningful with ControllerKind::kInternalPid). Tustin,
/// zero-order hold and backward Euler all map s = 0 to z = 1, so the DC gain of each section's
/// continuous form (controller_if/controller/controller_discretisation.cpp) is its discrete one's.
ControllerStaticLaw StaticLawOf(const ControllerParams& controller);

/// The levitated start of a run under the in-process controller (initial_position =
/// "equilibrium", powered at step 0).
///
/// The reference start (`moved` false) is the one every such run had before: the powered
/// equilibrium of the feedforward currents that carry the static load with zero deflection at
/// the AMB planes (PoweredEquilibrium of the static-load currents), the controller's integrators
/// empty. It is kept, bit for bit, whenever it is the controller's equilibrium: no controlling
/// sensor reads an offset and the feedforward carries the static load.
///
/// Otherwise (`moved`) the start is the controller's own static equilibrium, found by Newton's
/// method on the exact AMB force laws (seed 003 Eq. (2) for the electromagnet law) with the
/// currents as unknowns:
///   K q = f_gravity + sum_a S_a^T f_a(i_a, S_a q)          (force balance, every mode)
///   holds-reading axis:  r_a(q) = r_a(q_ref)                (the integrators hold the reading)
///   proportional axis:   i_a = i_ff,a - G (r_a(q) - r_a(q_ref))
/// with r_a(q) = gain (S_sensor q) + offset the reading of the AMB's sensor axis and q_ref the
/// reference start read without the offset. On a rigid rotor r(q_ref) is zero, so an
/// integrating controller's sensors read exactly the set point; on a flexible rotor whose
/// sensors are not at its AMBs, r(q_ref) is the static sag the reference start already had
/// there, so the start moves continuously with the offset (from zero) and the sag settles as it
/// always did. With two sensor planes and two AMBs this is the rotor's rigid displacement
/// (translation and tilt) that puts both readings at the set point, plus the bending the
/// changed AMB forces cause. A solve that does not converge, or that puts a journal outside its
/// TDB clearance, keeps the reference start.
struct LevitatedStart {
  bool moved = false;
  ModalVector q;  ///< modal coordinates of the start
  /// Per AMB (x, y): the control currents that hold it (what the controller commands at rest).
  std::vector<std::array<double, 2>> current_A;
  /// Per AMB (x, y): the reading of the AMB's sensor axis at the start less its reading at the
  /// reference start without the offset (0 for an integrating controller).
  std::vector<std::array<double, 2>> reading_shift_m;
};

/// Computes the levitated start of a built model (BuildModel calls it last; it reads the
/// model's shapes, stiffness and static-load forces).
LevitatedStart ComputeLevitatedStart(const Model& model);

}  // namespace ambdrop
