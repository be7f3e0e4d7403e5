#pragma once
/// Parameters of the 4-DOF TDB, Jarroux 2019 models #2 and #3 (Sec. 4.1, Fig. 9(b), Table 2).

namespace ambdrop {

/// Hunt-Crossley normal contact, Jarroux 2019 Eq. (10) with Hunt & Crossley's exponent n:
///   fn = kn u^n (1 + 3/2 alpha u')  for u > 0, else 0 (and fn >= 0).
struct HuntCrossleyParams {
  double stiffness_N_per_m_n = 0.0;  ///< kn (N/m^n)
  double exponent = 1.0;             ///< n: 1 as printed in Eq. (10), 3/2 for Hertzian points
  double damping_s_per_m = 0.0;      ///< alpha_nl (s/m)
  friend bool operator==(const HuntCrossleyParams&, const HuntCrossleyParams&) = default;
};

enum class BearingLaw {
  kHertzLinearised,  ///< kbrg, cbrg linearised at an operating load (Jarroux 2019 Sec. 3.1)
  kHertz,            ///< Fr = K ur^(3/2) (Jarroux 2019 Eq. (5), zero internal clearance)
  kQuadratic,        ///< Fr = kq ur^2 (Jarroux 2016 (seed 001), Sec. 2: "a quadratic law")
  kLinear,           ///< kbrg, cbrg given directly (a rig sheet's linear bearing)
};

/// Ball bearing between the races from Hertz theory, Jarroux 2019 Eq. (5)-(8) (Harris).
struct BallBearingParams {
  BearingLaw law = BearingLaw::kHertzLinearised;
  int balls = 0;                                    ///< Z
  double contact_angle_rad = 0.0;                   ///< alpha_c
  double inner_contact_stiffness_N_per_m1_5 = 0.0;  ///< k_ir, ball / inner race, Eq. (7)
  double outer_contact_stiffness_N_per_m1_5 = 0.0;  ///< k_or, ball / outer race, Eq. (7)
  double operating_load_N = 0.0;                    ///< where kbrg is linearised
  double damping_factor = 1.0;                      ///< cbrg / kbrg * 1e5, Eq. (8): [0.25, 2.5]
  /// kq (N/m^2) of the quadratic law; 0: the secant through the Hertz operating point,
  /// kq = F0 / ur0^2, so that both laws deflect alike under the operating load.
  double quadratic_stiffness_N_per_m2 = 0.0;
  double stiffness_N_per_m = 0.0;  ///< kbrg of the linear law (the Hertz data then unused)
  double damping_N_s_per_m = 0.0;  ///< cbrg of the linear law
  friend bool operator==(const BallBearingParams&, const BallBearingParams&) = default;
};

enum class RibbonLaw {
  kKelvinVoigt,   ///< Jarroux 2019 Eq. (4), model #2
  kDahl,          ///< generalized Dahl, Jarroux 2019 Eq. (1)-(3), model #3
  kCrossCoupled,  ///< cross-coupled stiffness against whirl, Jarroux 2016 (seed 001) Eq. (1)
};

/// Kelvin-Voigt ribbon, Jarroux 2019 Eq. (4): frd = crd u' + krd u.
struct KelvinVoigtRibbonParams {
  double stiffness_N_per_m = 0.0;  ///< krd
  double damping_N_s_per_m = 0.0;  ///< crd
  friend bool operator==(const KelvinVoigtRibbonParams&, const KelvinVoigtRibbonParams&) = default;
};

/// Generalized Dahl ribbon, Jarroux 2019 Eq. (1)-(3):
///   frd' = beta |u'| (h - frd),  h = hu while loading (u' > 0), hl while unloading,
///   hu = muFN + kslip u + a exp(b u),  hl = -muFN + kslip u - c exp(-d u).
/// The slipping threshold muFN is slipping_threshold_N * threshold_scale (the paper reduces it
/// 30x at DE and 4x at NDE to match drops, Sec. 6.1).
struct DahlRibbonParams {
  double slipping_threshold_N = 0.0;        ///< muFN from the harmonic tests
  double threshold_scale = 1.0;             ///< factor on muFN
  double slipping_stiffness_N_per_m = 0.0;  ///< kslip
  double beta_per_m = 0.0;                  ///< beta: stick/slip transition
  double upper_hardening_N = 0.0;           ///< a
  double upper_hardening_rate_per_m = 0.0;  ///< b
  double lower_hardening_N = 0.0;           ///< c
  double lower_hardening_rate_per_m = 0.0;  ///< d
  friend bool operator==(const DahlRibbonParams&, const DahlRibbonParams&) = default;
};

/// Corrugated ribbon damper with a cross-coupled stiffness that opposes the outer race's whirl,
/// Jarroux 2016 (seed 001) Eq. (1), on the outer-race position (x, y) and velocity:
///   f = -kcrd [[1, -eta sgn(v)], [eta sgn(v), 1]] (x, y) - ccrd (x', y'),
/// v = (x y' - y x') / |(x, y)| the outer race's whirl speed (> 0 along +spin), and sgn as an
/// arctan law, sgn(v) ~ (2/pi) atan(vref v).
struct CrossCoupledRibbonParams {
  double stiffness_N_per_m = 0.0;              ///< kcrd
  double cross_coupling = 0.0;                 ///< eta
  double damping_N_s_per_m = 0.0;              ///< ccrd
  double sign_regularisation_s_per_m = 100.0;  ///< vref of the arctan sign
  friend bool operator==(const CrossCoupledRibbonParams&,
                         const CrossCoupledRibbonParams&) = default;
};

/// 4-DOF TDB: journal / inner race (Hunt-Crossley), inner race (mass, x, y), ball bearing,
/// outer race (mass, x, y), ribbon and outer race / housing (Hunt-Crossley once the ribbon's
/// radial clearance is used up).
struct FourDofParams {
  double inner_race_mass_kg = 0.0;
  double outer_race_mass_kg = 0.0;
  double ribbon_clearance_m = 0.0;     ///< outer race travel before it meets the housing (urd)
  double gravity_y_m_s2 = 0.0;         ///< on the races, along +y (set from [gravity] at load)
  HuntCrossleyParams inner_contact;    ///< journal / inner race
  HuntCrossleyParams housing_contact;  ///< outer race / housing
  /// false: no housing stop, the outer race travels on the ribbon alone (a rig whose ribbon is
  /// not backed by a housing within reach).
  bool housing_contact_enabled = true;
  BallBearingParams bearing;
  RibbonLaw ribbon = RibbonLaw::kKelvinVoigt;
  KelvinVoigtRibbonParams kelvin_voigt;
  DahlRibbonParams dahl;
  CrossCoupledRibbonParams cross_coupled;
  friend bool operator==(const FourDofParams&, const FourDofParams&) = default;
};

}  // namespace ambdrop
