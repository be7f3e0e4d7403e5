#include "io/config/config_catcher_bearing.hpp"

#include "rt_core/ball_row.hpp"

namespace ambdrop::config_detail {
namespace {

// Seed 003 Eq. (1)-(2): k either from the line-contact length (Eq. (2)) or given.
ImpactParams ReadImpact(const TableReader& catcher) {
  const TableReader table = catcher.Table("impact");
  table.AllowOnly({"exponent", "contact_length_m", "stiffness_N_per_m_e", "max_damping_N_s_per_m",
                   "full_damping_penetration_m"});
  ImpactParams params;
  params.exponent = table.Number("exponent", InRange(1.0, 2.0));
  if (table.Has("contact_length_m")) {
    table.Reject("stiffness_N_per_m_e",
                 "either contact_length_m (k from seed 003 Eq. (2)) or stiffness_N_per_m_e");
    params.stiffness_N_per_m_e = LineContactStiffness(table.Number("contact_length_m", Positive()));
  } else {
    if (!table.Has("stiffness_N_per_m_e")) {
      table.FailMissing("stiffness_N_per_m_e",
                        "a positive number (N/m^e), or contact_length_m for seed 003 Eq. (2)");
    }
    params.stiffness_N_per_m_e = table.Number("stiffness_N_per_m_e", Positive());
  }
  params.max_damping_N_s_per_m = table.Number("max_damping_N_s_per_m", NonNegative());
  params.full_damping_penetration_m = table.Number("full_damping_penetration_m", NonNegative());
  return params;
}

RaceParams ReadRace(const TableReader& table) {
  table.AllowOnly({"mass_kg", "polar_inertia_kg_m2"});
  RaceParams params;
  params.mass_kg = table.Number("mass_kg", Positive());
  params.polar_inertia_kg_m2 = table.Number("polar_inertia_kg_m2", Positive());
  return params;
}

BallBearingRowParams ReadBearingRow(const TableReader& table) {
  table.AllowOnly({"balls", "rows", "ball_diameter_m", "pitch_diameter_m",
                   "inner_contact_stiffness_N_per_m1_5", "outer_contact_stiffness_N_per_m1_5",
                   "contact_damping_N_s_per_m", "full_damping_deflection_m",
                   "diametric_clearance_m", "viscous_drag_N_m_s", "palmgren_f1"});
  BallBearingRowParams params;
  if (!table.Has("balls")) table.FailMissing("balls", "an integer in [1, 64]");
  params.balls = table.Integer("balls", 1, kMaxBallsPerRow, 0);
  params.rows = table.Integer("rows", 1, 8, params.rows);
  params.ball_diameter_m = table.Number("ball_diameter_m", Positive());
  params.pitch_diameter_m = table.Number(
      "pitch_diameter_m", AtLeast(params.ball_diameter_m, "a number above ball_diameter_m"));
  params.inner_contact_stiffness_N_per_m1_5 =
      table.Number("inner_contact_stiffness_N_per_m1_5", Positive());
  params.outer_contact_stiffness_N_per_m1_5 =
      table.Number("outer_contact_stiffness_N_per_m1_5", Positive());
  params.contact_damping_N_s_per_m = table.Number("contact_damping_N_s_per_m", NonNegative());
  params.full_damping_deflection_m = table.Number("full_damping_deflection_m", NonNegative());
  params.diametric_clearance_m = table.Number("diametric_clearance_m", NonNegative());
  params.viscous_drag_N_m_s = table.Number("viscous_drag_N_m_s", NonNegative());
  params.palmgren_f1 = table.Number("palmgren_f1", NonNegative());
  return params;
}

MetalRubberRingParams ReadRing(const TableReader& table) {
  table.AllowOnly({"house_mass_kg", "stiffness_N_per_m", "damping_N_s_per_m"});
  MetalRubberRingParams params;
  params.house_mass_kg = table.Number("house_mass_kg", Positive());
  params.stiffness_N_per_m = table.Number("stiffness_N_per_m", Positive());
  params.damping_N_s_per_m = table.Number("damping_N_s_per_m", NonNegative());
  return params;
}

}  // namespace

// The tables the switches select are required; the others, if given, are checked too, so that
// `--set tdb.X.catcher_bearing.decks=1` or `...mount="rigid"` switch between complete descriptions.
CatcherBearingParams ReadCatcherBearing(const TableReader& tdb, const GravityParams& gravity) {
  const TableReader table = tdb.Table("catcher_bearing");
  table.AllowOnly({"decks", "ball_passage", "race_spin", "mount", "impact", "inner_race",
                   "inner_bearing", "intermediate_race", "outer_bearing", "metal_rubber_ring"});
  CatcherBearingParams params;
  if (!table.Has("decks")) table.FailMissing("decks", "1 (single-decker) or 2 (double-decker)");
  params.decks = table.Integer("decks", 1, 2, 1);
  params.ball_passage = table.Bool("ball_passage", params.ball_passage);
  params.race_spin = table.Bool("race_spin", params.race_spin);
  params.mount = table.Choice("mount", {"rigid", "metal_rubber_ring"}) == "metal_rubber_ring"
                     ? CatcherMount::kMetalRubberRing
                     : CatcherMount::kRigid;
  params.gravity_y_m_s2 = gravity.enabled ? -gravity.acceleration_m_s2 : 0.0;
  params.impact = ReadImpact(table);
  params.inner_race = ReadRace(table.Table("inner_race"));
  params.inner_bearing = ReadBearingRow(table.Table("inner_bearing"));
  const bool two = params.decks == 2;
  if (two || table.Has("intermediate_race")) {
    params.intermediate_race = ReadRace(table.Table("intermediate_race"));
  }
  if (two || table.Has("outer_bearing")) {
    params.outer_bearing = ReadBearingRow(table.Table("outer_bearing"));
  }
  if (params.mount == CatcherMount::kMetalRubberRing || table.Has("metal_rubber_ring")) {
    params.ring = ReadRing(table.Table("metal_rubber_ring"));
  }
  return params;
}

}  // namespace ambdrop::config_detail
