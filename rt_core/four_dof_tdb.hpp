#pragma once
#include "rt_core/ball_bearing.hpp"
#include "rt_core/touchdown_bearing.hpp"

namespace ambdrop {

/// TDB models #2 and #3 of Jarroux 2019 (Sec. 4.1, Fig. 9(b), Table 2): the inner and outer
/// races are masses with lateral DOFs.
///   - journal / inner race: Hunt-Crossley normal force, Eq. (10), on the penetration beyond the
///     clearance; regularised Coulomb friction, Eq. (11), on the slip of the journal surface over
///     the inner-race surface (plus the optional viscous force on the relative whirl speed);
///   - inner race / outer race: the ball bearing, Hertz Eq. (5)-(7) linearised to kbrg or
///     nonlinear, or the quadratic law of Jarroux 2016 (seed 001, Sec. 2), with cbrg per Eq. (8);
///   - outer race / housing: the ribbon, Kelvin-Voigt Eq. (4) (model #2) or generalized Dahl
///     Eq. (1)-(3) (model #3), on each lateral axis (the ribbon was identified along one axis,
///     Sec. 2), or the cross-coupled ribbon against the outer race's whirl (Jarroux 2016, seed
///     001, Eq. (1)); and Hunt-Crossley, Eq. (10), once the outer race has used up the ribbon's
///     radial clearance;
///   - race spin, Eq. (9), with the Palmgren torque on the bearing load.
/// The races carry their weight; misalignment moves the housing centre. Race positions are
/// relative to the housing centre.
class FourDofTdb final : public TouchdownBearing {
 public:
  /// Layout of the internal states.
  enum StateIndex : int {
    kRaceSpin = 0,  ///< Omega_tdb (rad/s)
    kInnerX,        ///< inner race x, y (m), vx, vy (m/s)
    kInnerY,
    kInnerVx,
    kInnerVy,
    kOuterX,  ///< outer race x, y (m), vx, vy (m/s)
    kOuterY,
    kOuterVx,
    kOuterVy,
    kRibbonFx,  ///< Dahl ribbon force frd on x, y (N); present with the Dahl ribbon only
    kRibbonFy,
  };
  static constexpr int kStatesKelvinVoigt = kRibbonFx;
  static constexpr int kStatesDahl = kRibbonFy + 1;

  /// Derives the bearing coefficients; throws std::invalid_argument on unusable parameters.
  explicit FourDofTdb(const TdbParams& params);
  int StateSize() const noexcept override { return state_size_; }
  /// Races at rest in their static equilibrium under gravity (Dahl: undeflected, with the ribbon
  /// force that carries the races' weight, kept inside the envelopes); race spin zero.
  void InitialState(double* state) const noexcept override;
  void Evaluate(const JournalMotion& journal, const double* state, double* state_rate,
                TdbForce* out) const noexcept override;
  double FreeRadius_m(const double* state) const noexcept override;
  const BallBearingCoefficients& bearing() const noexcept { return bearing_; }

 private:
  BallBearingCoefficients bearing_;
  int state_size_;
  // Reciprocal race masses (1/kg): the step multiplies instead of dividing four times a call.
  double inverse_inner_mass_;
  double inverse_outer_mass_;
};

}  // namespace ambdrop
