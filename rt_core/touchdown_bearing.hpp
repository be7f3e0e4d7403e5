#pragma once
#include <cmath>
#include "rt_core/tdb_params.hpp"

namespace ambdrop {

/// Journal motion at a TDB plane, in the machine frame (x horizontal, y up, z along the axis).
struct JournalMotion {
  double x_m = 0.0;
  double y_m = 0.0;
  double vx_m_s = 0.0;
  double vy_m_s = 0.0;
  double spin_rad_s = 0.0;  ///< rotor spin speed about +z
};

/// What a TDB does to the rotor, and what it reports.
struct TdbForce {
  double fx_N = 0.0;  ///< force on the rotor
  double fy_N = 0.0;
  double torque_on_rotor_N_m = 0.0;  ///< about +z, from contact friction
  double normal_force_N = 0.0;       ///< rotor / inner-race normal force (>= 0)
  double tangential_force_N = 0.0;   ///< friction force on the inner race, along the spin sense
  double penetration_m = 0.0;        ///< journal excursion beyond the clearance (< 0: free)
  double tdb_spin_rad_s = 0.0;       ///< inner-race speed
  /// Force passed to the housing (the rig's load cells), by component. Its magnitude is taken
  /// only when read: the integrator's stages never read it.
  double support_x_N = 0.0;
  double support_y_N = 0.0;
  double support_force_N() const noexcept {
    return std::sqrt(support_x_N * support_x_N + support_y_N * support_y_N);
  }
};

/// A touchdown-bearing model: its own internal states (race speeds, race positions, ribbon
/// forces …) advanced by the rotor's integrator. Implementations are built at setup and
/// are immutable; Evaluate is pure, allocation-free and noexcept.
class TouchdownBearing {
 public:
  virtual ~TouchdownBearing() = default;
  virtual int StateSize() const noexcept = 0;
  virtual void InitialState(double* state) const noexcept = 0;
  /// Forces on the rotor and the rates of the internal states for the given journal motion.
  virtual void Evaluate(const JournalMotion& journal, const double* state, double* state_rate,
                        TdbForce* out) const noexcept = 0;
  /// How far (m) the journal may be from the machine axis with this TDB in state `state` and
  /// touch nothing: there its forces on the rotor are zero and its outputs and state rates do
  /// not read the journal's motion, bit for bit. 0 where no such distance is known. A fit runs
  /// a levitated time once for models that differ in their TDBs only (tools/fit).
  virtual double FreeRadius_m(const double* /*state*/) const noexcept { return 0.0; }
  const TdbParams& params() const noexcept { return params_; }

 protected:
  explicit TouchdownBearing(const TdbParams& params) : params_(params) {}
  TdbParams params_;
};

}  // namespace ambdrop
