#pragma once
#include <string>
#include <variant>

#include "rt_core/ball_bearing_tdb_params.hpp"
#include "rt_core/catcher_bearing_params.hpp"
#include "rt_core/four_dof_params.hpp"

namespace ambdrop {

/// The ribbon of the contact-law TDB (see ContactLawTdb).
enum class ContactLawRibbon {
  kBilinear,      ///< inside the bilinear law, Jarroux 2019 Eq. (12) (the default)
  kDahl,          ///< race on a generalized Dahl ribbon, Jarroux 2019 Eq. (1)-(3)
  kCrossCoupled,  ///< race on the cross-coupled ribbon, Jarroux 2016 (seed 001) Eq. (1)
};

/// The normal law where the journal meets the contact-law TDB.
enum class ContactLawNormal {
  kBilinear,      ///< Jarroux 2019 Eq. (12) (the default)
  kHuntCrossley,  ///< Jarroux 2019 Eq. (10) on the journal/race penetration, in place of Eq. (12)
};

/// Contact-law TDB, Jarroux 2019 Eq. (12): ribbon (keq, ceq) until crushed by urd, then the ball
/// bearing (kbrg, cbrg) in series with the crushed ribbon's static force keq*urd. With a Dahl or
/// cross-coupled ribbon the bearing (kbrg, cbrg) is in series with that ribbon instead. With
/// normal_law = kHuntCrossley the journal meets the race by Eq. (10) instead: without a ribbon in
/// series that is the whole law (a rigid race, the common Hertzian TDB of the literature), with
/// one it takes the bearing's (kbrg, cbrg) place.
struct ContactLawParams {
  double bearing_stiffness_N_per_m = 0.0;  ///< kbrg
  double bearing_damping_N_s_per_m = 0.0;  ///< cbrg
  double ribbon_stiffness_N_per_m = 0.0;   ///< keq (ribbon and bearing in series); bilinear only
  /// ceq; with the Dahl ribbon, the viscous part beside the Dahl element (> 0)
  double ribbon_damping_N_s_per_m = 0.0;
  double ribbon_crushing_m = 0.0;  ///< urd, ribbon crushing capacity; bilinear only
  ContactLawRibbon ribbon = ContactLawRibbon::kBilinear;
  DahlRibbonParams dahl;                   ///< ribbon = kDahl
  CrossCoupledRibbonParams cross_coupled;  ///< ribbon = kCrossCoupled
  /// With a ribbon in series: the mass the ribbon carries (the outer race or housing and what
  /// moves with it, Jarroux 2019 model #3's outer race); 0: a massless race (the default).
  double outer_race_mass_kg = 0.0;
  double gravity_y_m_s2 = 0.0;  ///< on that mass, along +y (set from [gravity] at load)
  ContactLawNormal normal_law = ContactLawNormal::kBilinear;
  HuntCrossleyParams hunt_crossley = {};  ///< normal_law = kHuntCrossley
  friend bool operator==(const ContactLawParams&, const ContactLawParams&) = default;
};

enum class FrictionLaw {
  kNone,                ///< frictionless contact
  kRegularisedCoulomb,  ///< Jarroux 2019 Eq. (11)
};

struct FrictionParams {
  FrictionLaw law = FrictionLaw::kRegularisedCoulomb;
  double coefficient = 0.2;               ///< mu_s
  double regularisation_s_per_m = 100.0;  ///< vref in atan(vref * vs)
  /// Viscous tangential force on the journal's whirl speed while in contact (Jarroux 2019,
  /// Sec. 4.2: "a viscous force ... counteracting the rotor whirl motions").
  double whirl_damping_N_s_per_m = 0.0;
  friend bool operator==(const FrictionParams&, const FrictionParams&) = default;
};

/// TDB rotation, Jarroux 2019 Eq. (9): Ieq dOmega/dt + Phi Omega = ft Rir - M1.
struct TdbSpinParams {
  bool enabled = true;                    ///< false: the inner race stays at rest
  double inertia_kg_m2 = 2.2e-3;          ///< Ieq, inner race + balls
  double rotational_damping_N_m_s = 0.0;  ///< Phi
  double palmgren_f1 = 0.0;               ///< M1 = f1 * fn * dm (Palmgren / Harris)
  double pitch_diameter_m = 0.0;          ///< dm
  double drag_torque_N_m = 0.0;           ///< constant drag torque (seals, windage)
  /// k of the drag torque's own smooth sign, k W / sqrt(1 + (k W)^2) on the race speed W;
  /// 0: the friction's, vref Rir (see RaceAcceleration).
  double drag_regularisation_s_per_rad = 0.0;
  friend bool operator==(const TdbSpinParams&, const TdbSpinParams&) = default;
};

/// Offset of the TDB centre from the magnetic centre (Jarroux 2019, Sec. 4).
struct MisalignmentParams {
  bool enabled = false;
  double x_m = 0.0;
  double y_m = 0.0;
  friend bool operator==(const MisalignmentParams&, const MisalignmentParams&) = default;
};

enum class TdbModelKind {
  kContactLaw,      ///< model #1, Eq. (12)
  kFourDof,         ///< models #2 (Kelvin-Voigt ribbon) and #3 (Dahl ribbon), Sec. 4.1
  kBallBearing,     ///< Chen 2019 (seed 002): line contact, discrete balls, optional Ks, Cs
  kCatcherBearing,  ///< seed 003 SDCB/DDCB, seed 004 metal rubber ring (CatcherBearingTdb)
};

/// What one TDB model reads beyond the common geometry, friction, spin and misalignment: one
/// struct per model, and a TdbParams holds exactly one of them (its model), so a model's code
/// cannot reach another's numbers. The alternatives are in TdbModelKind's order.
using TdbModelParams =
    std::variant<ContactLawParams, FourDofParams, BallBearingTdbParams, CatcherBearingParams>;

struct TdbParams {
  std::string name;
  double position_m = 0.0;
  double journal_radius_m = 0.0;  ///< rotor radius at the TDB
  double clearance_m = 0.0;       ///< radial clearance rotor / inner race
  /// Rir, the inner race's rolling radius in the slip, the race torque and the regularisation of
  /// its resisting torques; 0 (a TdbParams built in code): journal_radius_m + clearance_m, which
  /// is also the config's default. Contact geometry (penetration, Hertz radii) keeps clearance_m:
  /// this radius only says which surface speed the race has, a convention simulators differ on.
  double inner_race_radius_m = 0.0;
  TdbModelParams model_params;  ///< the model and its own parameters (contact law by default)
  FrictionParams friction;
  TdbSpinParams spin;
  MisalignmentParams misalignment;

  TdbModelKind model() const noexcept { return static_cast<TdbModelKind>(model_params.index()); }
  /// The model's own parameters; std::bad_variant_access for another model's.
  const ContactLawParams& contact_law() const { return std::get<ContactLawParams>(model_params); }
  ContactLawParams& contact_law() { return std::get<ContactLawParams>(model_params); }
  const FourDofParams& four_dof() const { return std::get<FourDofParams>(model_params); }
  FourDofParams& four_dof() { return std::get<FourDofParams>(model_params); }
  const BallBearingTdbParams& ball_bearing() const {
    return std::get<BallBearingTdbParams>(model_params);
  }
  BallBearingTdbParams& ball_bearing() { return std::get<BallBearingTdbParams>(model_params); }
  const CatcherBearingParams& catcher() const {
    return std::get<CatcherBearingParams>(model_params);
  }
  CatcherBearingParams& catcher() { return std::get<CatcherBearingParams>(model_params); }
  /// Makes this a TDB of that model, its parameters the defaults, and returns them.
  ContactLawParams& UseContactLaw() { return model_params.emplace<ContactLawParams>(); }
  FourDofParams& UseFourDof() { return model_params.emplace<FourDofParams>(); }
  BallBearingTdbParams& UseBallBearing() { return model_params.emplace<BallBearingTdbParams>(); }
  CatcherBearingParams& UseCatcher() { return model_params.emplace<CatcherBearingParams>(); }
  friend bool operator==(const TdbParams&, const TdbParams&) = default;
};

}  // namespace ambdrop
