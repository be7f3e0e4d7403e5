#include "io/config/config_ball_bearing_tdb.hpp"

#include <climits>
#include <numbers>

namespace ambdrop::config_detail {
namespace {

LineContactParams ReadLineContact(const TableReader& parent) {
  const TableReader table = parent.Table("line_contact");
  table.AllowOnly({"youngs_modulus_Pa", "length_m"});
  LineContactParams params;
  params.youngs_modulus_Pa = table.Number("youngs_modulus_Pa", Positive());
  params.length_m = table.Number("length_m", Positive());
  return params;
}

SlipFrictionParams ReadSlipFriction(const TableReader& parent) {
  const TableReader table = parent.Table("friction");
  table.AllowOnly(
      {"law", "static_coefficient", "kinetic_coefficient", "stick_speed_m_s", "slip_speeds"});
  SlipFrictionParams params;
  params.law = table.Choice("law", {"static_kinetic", "none"}) == "none"
                   ? SlipFrictionLaw::kNone
                   : SlipFrictionLaw::kStaticKinetic;
  params.static_coefficient = table.Number("static_coefficient", NonNegative());
  params.kinetic_coefficient = table.Number("kinetic_coefficient", NonNegative());
  params.stick_speed_m_s = table.Number("stick_speed_m_s", NonNegative());
  params.slip_speeds =
      table.Choice("slip_speeds", {"contact_point", "spin_only"}, "contact_point") == "spin_only"
          ? SlipSpeeds::kSpinOnly
          : SlipSpeeds::kContactPoint;
  return params;
}

DiscreteBallParams ReadBalls(const TableReader& parent) {
  const TableReader table = parent.Table("bearing");
  table.AllowOnly({"balls", "ball_diameter_m", "pitch_diameter_m", "contact_angle_rad",
                   "inner_groove_conformity", "outer_groove_conformity", "inner_delta_star",
                   "outer_delta_star", "race_youngs_modulus_Pa", "race_poisson_ratio",
                   "ball_youngs_modulus_Pa", "ball_poisson_ratio", "radial_clearance_m",
                   "damping_N_s_per_m", "cage_rotation"});
  DiscreteBallParams params;
  if (!table.Has("balls")) table.FailMissing("balls", "an integer >= 1");
  params.balls = table.Integer("balls", 1, 256, 0);
  params.ball_diameter_m = table.Number("ball_diameter_m", Positive());
  params.pitch_diameter_m = table.Number(
      "pitch_diameter_m",
      AtLeast(params.ball_diameter_m * (1.0 + 1e-12), "a number above ball_diameter_m"));
  params.contact_angle_rad =
      table.Number("contact_angle_rad", InHalfOpenRange(0.0, std::numbers::pi / 2.0));
  const NumberRule conformity = AtLeast(0.5 + 1e-12, "a groove conformity above 0.5");
  params.inner_groove_conformity = table.Number("inner_groove_conformity", conformity);
  params.outer_groove_conformity = table.Number("outer_groove_conformity", conformity);
  params.inner_delta_star = table.Number("inner_delta_star", Positive());
  params.outer_delta_star = table.Number("outer_delta_star", Positive());
  params.race_youngs_modulus_Pa = table.Number("race_youngs_modulus_Pa", Positive());
  params.race_poisson_ratio = table.Number("race_poisson_ratio", InHalfOpenRange(0.0, 0.5));
  params.ball_youngs_modulus_Pa = table.Number("ball_youngs_modulus_Pa", Positive());
  params.ball_poisson_ratio = table.Number("ball_poisson_ratio", InHalfOpenRange(0.0, 0.5));
  params.radial_clearance_m = table.Number("radial_clearance_m", NonNegative());
  params.damping_N_s_per_m = table.Number("damping_N_s_per_m", NonNegative());
  params.cage_rotation = table.Bool("cage_rotation", params.cage_rotation);
  return params;
}

BearingSupportParams ReadSupport(const TableReader& parent) {
  BearingSupportParams params;
  const auto table = parent.OptionalTable("support");
  if (!table) return params;
  table->AllowOnly({"enabled", "stiffness_N_per_m", "damping_N_s_per_m", "outer_race_mass_kg"});
  params.enabled = table->Bool("enabled", params.enabled);
  // A disabled support does not demand its numbers; given, they are still checked.
  const auto number = [&](std::string_view key, const NumberRule& rule) {
    return params.enabled ? table->Number(key, rule) : table->Number(key, rule, 0.0);
  };
  params.stiffness_N_per_m = number("stiffness_N_per_m", Positive());
  params.damping_N_s_per_m = number("damping_N_s_per_m", NonNegative());
  params.outer_race_mass_kg = number("outer_race_mass_kg", Positive());
  return params;
}

}  // namespace

BallBearingTdbParams ReadBallBearingTdb(const TableReader& tdb, const GravityParams& gravity) {
  const TableReader table = tdb.Table("ball_bearing_tdb");
  table.AllowOnly({"inner_race_mass_kg", "line_contact", "friction", "bearing", "support"});
  BallBearingTdbParams params;
  params.inner_race_mass_kg = table.Number("inner_race_mass_kg", Positive());
  params.gravity_y_m_s2 = gravity.enabled ? -gravity.acceleration_m_s2 : 0.0;
  params.line_contact = ReadLineContact(table);
  params.friction = ReadSlipFriction(table);
  params.bearing = ReadBalls(table);
  params.support = ReadSupport(table);
  return params;
}

}  // namespace ambdrop::config_detail
