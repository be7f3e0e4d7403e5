#pragma once
#include "rt_core/discrete_ball_bearing.hpp"
#include "rt_core/touchdown_bearing.hpp"

namespace ambdrop {

/// TDB of Chen, Liu, Yuliane, Kuan (ITRI) 2019 (seed 002), Fig. 2, 3, 4 and 16:
///   - journal / inner race: Hertz line contact, Eq. (5)-(8), on the deflection
///     delta = |journal - inner race| - (Ri - Rs) (Eq. (6)); no contact damping (the paper's
///     contact is un-lubricated Hertz);
///   - friction mu_r |Fn| along the slip, static/kinetic by the sign of vs - vi, Eq. (9)-(12);
///     the slip vs - vi also counts the journal's whirl relative to the race, which Eq. (9)-(10)
///     leave out (they hold for a journal resting in the race);
///   - inner race: a mass with x, y and its spin (Jarroux 2019 Eq. (9), shared with the other
///     TDB models, with the friction torque Ft Ri);
///   - inner race / outer race: Z discrete balls, Qj = krb deltaj^(3/2), Eq. (13)-(19), the ball
///     set turning with the cage, and a linear damper Cb;
///   - outer race: the housing itself, or (support enabled, Fig. 16) a mass on Ks, Cs.
/// A new model rather than options of FourDofTdb: the structure differs in each link (line
/// contact with no damping instead of Hunt-Crossley, switched friction instead of the arctan law,
/// discrete balls with a cage angle state instead of the radial integral, no ribbon or housing
/// contact), so sharing the class would mean a switch on every line.
class BallBearingTdb final : public TouchdownBearing {
 public:
  /// Layout of the internal states.
  enum StateIndex : int {
    kRaceSpin = 0,  ///< inner-race speed omega_i (rad/s)
    kCageAngle,     ///< angle of ball 0 from +x (rad)
    kInnerX,        ///< inner race x, y (m) from the housing centre, vx, vy (m/s)
    kInnerY,
    kInnerVx,
    kInnerVy,
    kOuterX,  ///< outer race x, y (m), vx, vy (m/s); with the support only
    kOuterY,
    kOuterVx,
    kOuterVy,
  };
  static constexpr int kStatesRigidSupport = kOuterX;
  static constexpr int kStatesElasticSupport = kOuterVy + 1;

  /// Derives krb; throws std::invalid_argument on unusable parameters.
  explicit BallBearingTdb(const TdbParams& params);
  int StateSize() const noexcept override { return state_size_; }
  /// Races at rest in their static equilibrium under gravity, cage angle and spin zero.
  void InitialState(double* state) const noexcept override;
  void Evaluate(const JournalMotion& journal, const double* state, double* state_rate,
                TdbForce* out) const noexcept override;
  const DiscreteBallBearing& bearing() const noexcept { return bearing_; }

 private:
  DiscreteBallBearing bearing_;
  int state_size_;
};

}  // namespace ambdrop
