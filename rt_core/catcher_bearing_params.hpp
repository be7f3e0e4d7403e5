#pragma once
/// Parameters of the catcher-bearing TDB: seed 003's single- and double-decker catcher bearings
/// (SDCB, DDCB; Sec. 2.2-2.3, Table 2) and seed 004's auxiliary bearing on a metal rubber ring
/// (Zhu & Zhang, Sec. 2.2, Fig. 4, Table 1).
#include "rt_core/impact_function.hpp"

namespace ambdrop {

/// A race (ring) with lateral DOFs and spin.
struct RaceParams {
  double mass_kg = 0.0;
  double polar_inertia_kg_m2 = 0.0;
  friend bool operator==(const RaceParams&, const RaceParams&) = default;
};

/// A deep-groove ball bearing between two races, each ball a Hertz point contact through the
/// impact function (seed 003 Sec. 2.3: "stiffness-damping contact model is also adopted to define
/// the catcher bearing internal contacts", Eq. (1) with e = 3/2, k_b from Eq. (3), Table 2).
/// The inner and outer ball contacts act in series: kn = (k_i^(-2/3) + k_o^(-2/3))^(-3/2)
/// (Harris; Jarroux 2019 Eq. (6)). Ball j of Z sits at the cage angle + 2 pi j / Z and carries
///   Q_j = rows * F_impact(kn, 3/2, c, d; dx cos phi_j + dy sin phi_j - Pd/2, its rate),
/// with Pd the diametric clearance. The friction moment between the races is viscous (lubricant)
/// plus Palmgren's load term: T = c_v (w_i - w_o) + f1 F dm sgn(w_i - w_o).
struct BallBearingRowParams {
  int balls = 0;                                    ///< Z per row
  int rows = 1;                                     ///< identical bearings side by side
  double ball_diameter_m = 0.0;                     ///< D
  double pitch_diameter_m = 0.0;                    ///< dm
  double inner_contact_stiffness_N_per_m1_5 = 0.0;  ///< ball / inner race (Table 2)
  double outer_contact_stiffness_N_per_m1_5 = 0.0;  ///< ball / outer race (Table 2)
  double contact_damping_N_s_per_m = 0.0;           ///< cm of one ball contact (Table 2)
  double full_damping_deflection_m = 0.0;           ///< dm of Eq. (1) for a ball contact
  double diametric_clearance_m = 0.0;               ///< Pd (Table 2)
  double viscous_drag_N_m_s = 0.0;                  ///< c_v, friction moment per relative speed
  double palmgren_f1 = 0.0;                         ///< f1 of the load moment f1 F dm
  friend bool operator==(const BallBearingRowParams&, const BallBearingRowParams&) = default;
};

enum class CatcherMount {
  kRigid,            ///< outer race fixed in a rigid housing (seed 003; seed 004's reference)
  kMetalRubberRing,  ///< bearing house on a metal rubber ring, Krr and Crr (seed 004, Fig. 4)
};

/// Seed 004, Fig. 4 and Eq. (2): the bearing house (with the outer race, rigidly fitted) on a
/// metal rubber ring modelled as a spring Krr and a damper Crr to the foundation.
struct MetalRubberRingParams {
  double house_mass_kg = 0.0;      ///< m_o (Table 1: 0.35 kg)
  double stiffness_N_per_m = 0.0;  ///< Krr
  double damping_N_s_per_m = 0.0;  ///< Crr
  friend bool operator==(const MetalRubberRingParams&, const MetalRubberRingParams&) = default;
};

/// Catcher bearing: inner race hit by the journal (impact function), one ball bearing to the
/// housing (decks = 1: SDCB, seed 004's AB) or two in series through an intermediate race that
/// spins too (decks = 2: DDCB); housing rigid or on a metal rubber ring.
struct CatcherBearingParams {
  int decks = 1;                       ///< 1: single-decker, 2: double-decker
  ImpactParams impact;                 ///< journal / inner race, seed 003 Eq. (1)-(2)
  RaceParams inner_race;               ///< the race the journal hits
  BallBearingRowParams inner_bearing;  ///< inner race / next body
  RaceParams intermediate_race;        ///< decks = 2 only
  BallBearingRowParams outer_bearing;  ///< decks = 2: intermediate race / housing
  bool ball_passage = true;            ///< the cage turns the ball set (else balls fixed)
  bool race_spin = true;               ///< races spin (else they stay at rest)
  CatcherMount mount = CatcherMount::kRigid;
  MetalRubberRingParams ring;   ///< mount = kMetalRubberRing only
  double gravity_y_m_s2 = 0.0;  ///< on the races and house, along +y (from [gravity])
  friend bool operator==(const CatcherBearingParams&, const CatcherBearingParams&) = default;
};

}  // namespace ambdrop
