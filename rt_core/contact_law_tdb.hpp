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
///
/// Hunt-Crossley normal law (contact_law.normal_law = "hunt_crossley"): Jarroux 2019 Eq. (10),
/// fn = kn urs^n (1 + 3/2 alpha urs'), in place of Eq. (12): a rigid race met by a Hertzian
/// contact (n = 3/2 for a point, about 10/9 for a line). With a ribbon in series it takes the
/// bearing's (kbrg, cbrg) place; the massless race's balance stays linear in u'_n (below), with
/// cbrg -> 3/2 alpha kn delta^n.
///
/// Ribbon in series (contact_law.ribbon = "dahl" or "cross_coupled"): the bilinear law's ribbon
/// (keq, ceq, urd) becomes a ribbon law of its own between a massless outer race and the housing,
/// in series with the bearing (kbrg, cbrg) that meets the journal. The race centre is carried by
/// the ribbon's deflection u = (ux, uy) from the TDB centre (internal states); the journal meets
/// the race at delta = |r_j - u| - clearance, along n from the race centre, t = (-ny, nx):
///   fn = max(0, kbrg delta + cbrg (v_j - u')·n)                             (Eq. (12), crushed)
///   F  = fn n + (ft + cw v_whirl) t      what the journal puts on the race, ft by Eq. (11)
///   c u' + R(u) = F                      the race is massless: the ribbon carries F exactly
/// with, per ribbon law,
///   Dahl (Jarroux 2019 Eq. (1)-(3)): R = frd per axis (two more states, frd' = beta |u'|
///     (h(u) - frd)), c = ceq (ribbon_damping_N_s_per_m), the viscous part beside the Dahl
///     element; without it a massless race has no rate to follow;
///   cross-coupled (Jarroux 2016 (seed 001) Eq. (1)): R = kcrd [[1, -eta s], [eta s, 1]] u,
///     c = ccrd, s = (2/pi) atan(vref v_or) on the race's whirl speed v_or.
/// Along n the balance is linear in u' and solved exactly, (c + cbrg) u'_n = kbrg delta +
/// cbrg v_j·n - R·n (u'_n = -R·n / c once the contact would pull); along t, u'_t = (F·t - R·t)
/// / c. Assumed: the race's own lateral speed u' is left out of the slip and whirl speeds of
/// Eq. (11) (it is the ribbon's creep, small beside the journal's whirl and surface speeds), and
/// the cross-coupled ribbon's sign s is taken on the race whirl of a first solve without the
/// cross-coupling (one fixed-point pass: the sign only picks the direction of a bounded force).
/// States: Omega_tdb, ux, uy (m) and, with the Dahl ribbon, frd_x, frd_y (N); the race starts
/// centred, the ribbon unloaded (a massless race carries no weight).
///
/// A race with mass (contact_law.outer_race_mass_kg = m > 0; Jarroux 2019 model #3's outer race
/// between bearing and ribbon, here without its inner race; Lahriri's bearing house on its
/// ring): Newton on the race instead of the balance above,
///   m u'' = -F_rotor - R(u) - c u' + m g          (Jarroux 2019 Sec. 4.1, outer race)
/// with the journal's contact on the moving race, fn = max(0, kbrg delta + cbrg (v_j - u')·n)
/// (Eq. (12), crushed), the slip and whirl speeds of Eq. (11) relative to the race, and the
/// ribbon's damping c allowed 0. Two more states, the race's velocity (vx, vy) (m/s), after the
/// others; the race starts at rest with its weight on the ribbon (Dahl: frd_y = m g within the
/// envelopes; cross-coupled: uy = m g / kcrd).
class ContactLawTdb final : public TouchdownBearing {
 public:
  enum StateIndex : int {
    kRaceSpin = 0,  ///< Omega_tdb (rad/s)
    kRibbonX,       ///< ribbon deflection ux, uy (m); with a ribbon in series only
    kRibbonY,
    kRibbonFx,  ///< Dahl ribbon force frd on x, y (N); with the Dahl ribbon only
    kRibbonFy,
  };
  static constexpr int kStatesBilinear = 1;
  static constexpr int kStatesCrossCoupled = kRibbonY + 1;
  static constexpr int kStatesDahl = kRibbonFy + 1;

  /// Index of the race's velocity x (y follows) when it has mass: after the ribbon's states.
  int RaceVelocityIndex() const noexcept { return race_velocity_index_; }

  /// Throws std::invalid_argument when a massless race's ribbon in series has no damping.
  explicit ContactLawTdb(const TdbParams& params);
  int StateSize() const noexcept override { return state_size_; }
  void InitialState(double* state) const noexcept override;
  void Evaluate(const JournalMotion& journal, const double* state, double* state_rate,
                TdbForce* out) const noexcept override;
  double FreeRadius_m(const double* state) const noexcept override;

 private:
  void EvaluateInSeries(const JournalMotion& journal, const double* state, double* state_rate,
                        TdbForce* out) const noexcept;
  void EvaluateRaceWithMass(const JournalMotion& journal, const double* state, double* state_rate,
                            TdbForce* out) const noexcept;
  int race_velocity_index_;
  int state_size_;
};

}  // namespace ambdrop
