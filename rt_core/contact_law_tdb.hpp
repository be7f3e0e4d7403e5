#pragma once
#include "rt_core/touchdown_bearing.hpp"

namespace ambdrop {

/// TDB model #1 of Jarroux 2019 (Sec. 4.2): no race dynamics; the normal force follows the
/// bilinear contact law Eq. (12) on the rotor/TDB penetration urs,
///   fn = kbrg (urs - urd) + cbrg urs' + keq urd   for urs >= urd,
///   fn = keq urs + ceq urs'                        for urd > urs >= 0,   0 otherwise;
/// the tangential force is regularised Coulomb friction Eq. (11) on the slip speed plus a viscous
/// force on the whirl speed; the inner race spins up by Eq. (9),
///   Ieq Omega_tdb' + Phi Omega_tdb = ft Rir - M1,  M1 = f1 fn dm (Palmgren).
/// One internal state: the inner-race speed Omega_tdb (rad/s).
class ContactLawTdb final : public TouchdownBearing {
 public:
  explicit ContactLawTdb(const TdbParams& params);
  int StateSize() const noexcept override { return 1; }
  void InitialState(double* state) const noexcept override { state[0] = 0.0; }
  void Evaluate(const JournalMotion& journal, const double* state, double* state_rate,
                TdbForce* out) const noexcept override;
};

}  // namespace ambdrop
