#pragma once
/// Parameters of the discrete-ball TDB of Chen, Liu, Yuliane, Kuan (ITRI) 2019 (seed 002):
/// Hertz line contact journal / inner race (Eq. (5)-(8)), static/kinetic friction (Eq. (9)-(12)),
/// a ball bearing of Z discrete balls (Eq. (13)-(19)) and an optional support Ks, Cs (Fig. 16).

namespace ambdrop {

/// Hertz line contact, Chen 2019 (seed 002) Eq. (5):
///   |Fn| = pi/2 delta E L sqrt(delta / (2 ((Ri - Rs) + delta)))  for delta > 0.
struct LineContactParams {
  double youngs_modulus_Pa = 0.0;  ///< E (the paper: the shaft's)
  double length_m = 0.0;           ///< L, contact length along the axis
  friend bool operator==(const LineContactParams&, const LineContactParams&) = default;
};

enum class SlipFrictionLaw {
  kNone,          ///< frictionless contact
  kStaticKinetic  ///< Chen 2019 (seed 002), mu_r by the sign of vs - vi
};

/// Which speeds decide the slip vs - vi.
enum class SlipSpeeds {
  /// The journal's surface at the contact point (its spin plus its whirl) against the race's
  /// surface: the slip the two surfaces really have, so friction only dissipates.
  kContactPoint,
  /// Chen 2019 (seed 002) Eq. (9)-(10) as printed: vs = omega_s Rs, vi = omega_i Ri, the spins
  /// alone. While the race is slower than the journal's surface the friction keeps pushing the
  /// journal backwards along the race, however it whirls: it can feed the whirl from the spin,
  /// which the contact-point slip cannot once the race rolls with the journal.
  kSpinOnly
};

/// Friction between journal and inner race, Chen 2019 (seed 002) Eq. (9)-(12):
/// mu_r = mu_d sgn(vs - vi) while slipping, mu_s while the surfaces roll together. "Together" is
/// the band |vs - vi| <= stick_speed_m_s, inside which the friction holds the surfaces with a
/// force linear in the slip, up to mu_s |Fn| at the band edge (it never adds energy).
struct SlipFrictionParams {
  SlipFrictionLaw law = SlipFrictionLaw::kStaticKinetic;
  double static_coefficient = 0.0;   ///< mu_s
  double kinetic_coefficient = 0.0;  ///< mu_d
  double stick_speed_m_s = 0.0;      ///< half-width of the "vs = vi" band
  SlipSpeeds slip_speeds = SlipSpeeds::kContactPoint;
  friend bool operator==(const SlipFrictionParams&, const SlipFrictionParams&) = default;
};

/// Ball bearing of Z discrete balls, Chen 2019 (seed 002) Eq. (13)-(19) (Harris):
/// per ball Qj = krb deltaj^(3/2), krb from the inner and outer ball/raceway contacts in series
/// (Eq. (14)), each from Hertz (Eq. (15)) with the curvature sums of Eq. (17) and the
/// dimensionless deformation delta* that Harris tabulates against F(rho), Eq. (16).
struct DiscreteBallParams {
  int balls = 0;                         ///< Z
  double ball_diameter_m = 0.0;          ///< Db
  double pitch_diameter_m = 0.0;         ///< dm
  double contact_angle_rad = 0.0;        ///< alpha (gamma = Db cos alpha / dm)
  double inner_groove_conformity = 0.0;  ///< fi = groove radius / Db
  double outer_groove_conformity = 0.0;  ///< fo
  double inner_delta_star = 0.0;         ///< delta*_i, Harris's table at F(rho)_i
  double outer_delta_star = 0.0;         ///< delta*_o, Harris's table at F(rho)_o
  double race_youngs_modulus_Pa = 0.0;   ///< E_{i,o}
  double race_poisson_ratio = 0.0;       ///< nu_{i,o}
  double ball_youngs_modulus_Pa = 0.0;   ///< E_b
  double ball_poisson_ratio = 0.0;       ///< nu_b
  double radial_clearance_m = 0.0;       ///< per-ball radial play before a ball is loaded
  double damping_N_s_per_m = 0.0;        ///< Cb, linear, between the races (Fig. 2)
  bool cage_rotation = true;             ///< balls orbit at the cage speed (false: fixed)
  friend bool operator==(const DiscreteBallParams&, const DiscreteBallParams&) = default;
};

/// Support of the outer race in the housing, Chen 2019 (seed 002) Fig. 16: Ks, Cs (the paper
/// takes Ks = 5e8 N/m, Cs = 27 900 N s/m from Antti). Disabled: the outer race is the housing.
struct BearingSupportParams {
  bool enabled = false;
  double stiffness_N_per_m = 0.0;  ///< Ks
  double damping_N_s_per_m = 0.0;  ///< Cs
  double outer_race_mass_kg = 0.0;
  friend bool operator==(const BearingSupportParams&, const BearingSupportParams&) = default;
};

/// The whole seed-002 TDB: journal / inner race (line contact, friction), inner race (mass, x,
/// y, spin), balls, outer race (fixed, or on Ks, Cs).
struct BallBearingTdbParams {
  double inner_race_mass_kg = 0.0;
  double gravity_y_m_s2 = 0.0;  ///< on the races, along +y (set from [gravity] at load)
  LineContactParams line_contact;
  SlipFrictionParams friction;
  DiscreteBallParams bearing;
  BearingSupportParams support;
  friend bool operator==(const BallBearingTdbParams&, const BallBearingTdbParams&) = default;
};

}  // namespace ambdrop
