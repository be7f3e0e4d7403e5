#include <climits>
#include <numbers>

#include "io/config/config_ball_bearing_tdb.hpp"
#include "io/config/config_catcher_bearing.hpp"
#include "io/config/config_readers.hpp"
#include "rt_core/limits.hpp"

namespace ambdrop::config_detail {
namespace {

HuntCrossleyParams ReadHuntCrossley(const TableReader& four_dof, std::string_view key) {
  const TableReader table = four_dof.Table(key);
  table.AllowOnly({"stiffness_N_per_m_n", "exponent", "damping_s_per_m"});
  HuntCrossleyParams params;
  params.stiffness_N_per_m_n = table.Number("stiffness_N_per_m_n", Positive());
  params.exponent = table.Number("exponent", InRange(1.0, 2.0));
  params.damping_s_per_m = table.Number("damping_s_per_m", NonNegative());
  return params;
}

// The outer race / housing contact, switchable off (enabled = false: no housing stop). A disabled
// table does not demand its numbers; given, they are still checked.
HuntCrossleyParams ReadHousingContact(const TableReader& four_dof, bool* enabled) {
  const TableReader table = four_dof.Table("housing_contact");
  table.AllowOnly({"enabled", "stiffness_N_per_m_n", "exponent", "damping_s_per_m"});
  *enabled = table.Bool("enabled", true);
  HuntCrossleyParams params;
  if (*enabled) {
    params.stiffness_N_per_m_n = table.Number("stiffness_N_per_m_n", Positive());
    params.exponent = table.Number("exponent", InRange(1.0, 2.0));
    params.damping_s_per_m = table.Number("damping_s_per_m", NonNegative());
  } else {
    params.stiffness_N_per_m_n = table.Number("stiffness_N_per_m_n", Positive(), 0.0);
    params.exponent = table.Number("exponent", InRange(1.0, 2.0), params.exponent);
    params.damping_s_per_m = table.Number("damping_s_per_m", NonNegative(), 0.0);
  }
  return params;
}

// The linear law takes kbrg and cbrg from the sheet; the Hertz laws derive them from the balls
// (Jarroux 2019 Eq. (5)-(8)), so each reads only its own keys.
BallBearingParams ReadBallBearing(const TableReader& four_dof, BearingLaw law) {
  const TableReader table = four_dof.Table("bearing");
  BallBearingParams params;
  params.law = law;
  if (law == BearingLaw::kLinear) {
    table.AllowOnly({"stiffness_N_per_m", "damping_N_s_per_m"});
    params.stiffness_N_per_m = table.Number("stiffness_N_per_m", Positive());
    params.damping_N_s_per_m = table.Number("damping_N_s_per_m", NonNegative());
    return params;
  }
  table.AllowOnly({"balls", "contact_angle_rad", "inner_contact_stiffness_N_per_m1_5",
                   "outer_contact_stiffness_N_per_m1_5", "operating_load_N", "damping_factor",
                   "quadratic_stiffness_N_per_m2"});
  if (!table.Has("balls")) table.FailMissing("balls", "an integer >= 1");
  params.balls = table.Integer("balls", 1, INT_MAX, 0);
  params.contact_angle_rad =
      table.Number("contact_angle_rad", InHalfOpenRange(0.0, std::numbers::pi / 2.0));
  params.inner_contact_stiffness_N_per_m1_5 =
      table.Number("inner_contact_stiffness_N_per_m1_5", Positive());
  params.outer_contact_stiffness_N_per_m1_5 =
      table.Number("outer_contact_stiffness_N_per_m1_5", Positive());
  params.operating_load_N = table.Number("operating_load_N", Positive());
  params.damping_factor = table.Number("damping_factor", NonNegative());
  // Jarroux 2016 (seed 001), Sec. 2: kq of the quadratic law; absent, the secant through the
  // Hertz operating point.
  params.quadratic_stiffness_N_per_m2 =
      table.Number("quadratic_stiffness_N_per_m2", Positive(), 0.0);
  return params;
}

KelvinVoigtRibbonParams ReadKelvinVoigt(const TableReader& table) {
  table.AllowOnly({"stiffness_N_per_m", "damping_N_s_per_m"});
  KelvinVoigtRibbonParams params;
  params.stiffness_N_per_m = table.Number("stiffness_N_per_m", Positive());
  params.damping_N_s_per_m = table.Number("damping_N_s_per_m", NonNegative());
  return params;
}

DahlRibbonParams ReadDahl(const TableReader& table) {
  table.AllowOnly({"slipping_threshold_N", "threshold_scale", "slipping_stiffness_N_per_m",
                   "beta_per_m", "upper_hardening_N", "upper_hardening_rate_per_m",
                   "lower_hardening_N", "lower_hardening_rate_per_m"});
  DahlRibbonParams params;
  params.slipping_threshold_N = table.Number("slipping_threshold_N", NonNegative());
  params.threshold_scale = table.Number("threshold_scale", NonNegative(), params.threshold_scale);
  params.slipping_stiffness_N_per_m = table.Number("slipping_stiffness_N_per_m", NonNegative());
  params.beta_per_m = table.Number("beta_per_m", Positive());
  params.upper_hardening_N = table.Number("upper_hardening_N", NonNegative());
  params.upper_hardening_rate_per_m = table.Number("upper_hardening_rate_per_m", NonNegative());
  params.lower_hardening_N = table.Number("lower_hardening_N", NonNegative());
  params.lower_hardening_rate_per_m = table.Number("lower_hardening_rate_per_m", NonNegative());
  return params;
}

// Cross-coupled ribbon, Jarroux 2016 (seed 001) Eq. (1).
CrossCoupledRibbonParams ReadCrossCoupled(const TableReader& table) {
  table.AllowOnly(
      {"stiffness_N_per_m", "cross_coupling", "damping_N_s_per_m", "sign_regularisation_s_per_m"});
  CrossCoupledRibbonParams params;
  params.stiffness_N_per_m = table.Number("stiffness_N_per_m", Positive());
  params.cross_coupling = table.Number("cross_coupling", NonNegative());
  params.damping_N_s_per_m = table.Number("damping_N_s_per_m", NonNegative());
  params.sign_regularisation_s_per_m =
      table.Number("sign_regularisation_s_per_m", Positive(), params.sign_regularisation_s_per_m);
  return params;
}

// Jarroux 2019 Eq. (12); with `ribbon` = "dahl" or "cross_coupled" a ribbon law in series with
// the bearing (ContactLawTdb), read by the 4-DOF TDB's ribbon readers from the table of that
// name. As there, the selected ribbon's table is required and the other one checked if given.
ContactLawParams ReadContactLaw(const TableReader& tdb, const GravityParams& gravity) {
  const TableReader table = tdb.Table("contact_law");
  table.AllowOnly({"normal_law", "hunt_crossley", "bearing_stiffness_N_per_m",
                   "bearing_damping_N_s_per_m", "ribbon_stiffness_N_per_m",
                   "ribbon_damping_N_s_per_m", "ribbon_crushing_m", "ribbon", "dahl",
                   "cross_coupled", "outer_race_mass_kg"});
  ContactLawParams params;
  const std::string ribbon =
      table.Choice("ribbon", {"bilinear", "dahl", "cross_coupled"}, "bilinear");
  params.ribbon = ribbon == "dahl"            ? ContactLawRibbon::kDahl
                  : ribbon == "cross_coupled" ? ContactLawRibbon::kCrossCoupled
                                              : ContactLawRibbon::kBilinear;
  const bool bilinear = params.ribbon == ContactLawRibbon::kBilinear;
  // Jarroux 2019 Eq. (10) in place of Eq. (12): its table is required; given with the bilinear
  // law it is checked, as the unselected ribbon's table is, so that `--set` can switch.
  const std::string normal = table.Choice("normal_law", {"bilinear", "hunt_crossley"}, "bilinear");
  if (normal == "hunt_crossley") params.normal_law = ContactLawNormal::kHuntCrossley;
  const bool hunt_crossley = params.normal_law == ContactLawNormal::kHuntCrossley;
  if (hunt_crossley || table.Has("hunt_crossley")) {
    params.hunt_crossley = ReadHuntCrossley(table, "hunt_crossley");
  }
  params.gravity_y_m_s2 = gravity.enabled ? -gravity.acceleration_m_s2 : 0.0;
  // The bilinear law has no race in series: there a given mass is checked and kept for a switch
  // of `ribbon` (as the other ribbon's table is), and an absent one is not logged as a key a fit
  // could move.
  params.outer_race_mass_kg =
      bilinear ? table.OptionalNumber("outer_race_mass_kg", NonNegative()).value_or(0.0)
               : table.Number("outer_race_mass_kg", NonNegative(), 0.0);
  const bool massless_race = bilinear || !(params.outer_race_mass_kg > 0.0);
  if (hunt_crossley) {
    // Eq. (10) replaces the bearing where the journal meets the race and, with no ribbon in
    // series, the whole of Eq. (12): given, those numbers are checked, absent, not logged.
    params.bearing_stiffness_N_per_m =
        table.OptionalNumber("bearing_stiffness_N_per_m", Positive()).value_or(0.0);
    params.bearing_damping_N_s_per_m =
        table.OptionalNumber("bearing_damping_N_s_per_m", NonNegative()).value_or(0.0);
  } else {
    params.bearing_stiffness_N_per_m = table.Number("bearing_stiffness_N_per_m", Positive());
    params.bearing_damping_N_s_per_m = table.Number("bearing_damping_N_s_per_m", NonNegative());
  }
  if (bilinear && hunt_crossley) {
    params.ribbon_stiffness_N_per_m =
        table.OptionalNumber("ribbon_stiffness_N_per_m", Positive()).value_or(0.0);
    params.ribbon_damping_N_s_per_m =
        table.OptionalNumber("ribbon_damping_N_s_per_m", NonNegative()).value_or(0.0);
    params.ribbon_crushing_m =
        table.OptionalNumber("ribbon_crushing_m", NonNegative()).value_or(0.0);
  } else if (bilinear) {
    params.ribbon_stiffness_N_per_m = table.Number("ribbon_stiffness_N_per_m", Positive());
    params.ribbon_damping_N_s_per_m = table.Number("ribbon_damping_N_s_per_m", NonNegative());
    params.ribbon_crushing_m = table.Number("ribbon_crushing_m", NonNegative());
  } else {
    // The ribbon law replaces keq and urd (and, cross-coupled, ceq): given, they are checked,
    // absent, they are not logged as keys a fit could move.
    params.ribbon_stiffness_N_per_m =
        table.OptionalNumber("ribbon_stiffness_N_per_m", Positive()).value_or(0.0);
    params.ribbon_crushing_m =
        table.OptionalNumber("ribbon_crushing_m", NonNegative()).value_or(0.0);
    if (params.ribbon == ContactLawRibbon::kDahl && massless_race) {
      const NumberRule positive_damping{
          .lower = 0.0,
          .lower_inclusive = false,
          .what =
              "a positive number (the Dahl ribbon's race is massless, no outer_race_mass_kg: "
              "this damping beside the Dahl element sets its deflection rate)"};
      params.ribbon_damping_N_s_per_m = table.Number("ribbon_damping_N_s_per_m", positive_damping);
    } else {
      params.ribbon_damping_N_s_per_m =
          table.OptionalNumber("ribbon_damping_N_s_per_m", NonNegative()).value_or(0.0);
    }
  }
  const auto ribbon_table = [&](std::string_view key) {
    return ribbon == key ? std::optional<TableReader>(table.Table(key)) : table.OptionalTable(key);
  };
  if (const auto dahl = ribbon_table("dahl")) params.dahl = ReadDahl(*dahl);
  if (const auto cc = ribbon_table("cross_coupled")) {
    params.cross_coupled = ReadCrossCoupled(*cc);
    if (params.ribbon == ContactLawRibbon::kCrossCoupled && massless_race &&
        !(params.cross_coupled.damping_N_s_per_m > 0.0)) {
      cc->Fail("damping_N_s_per_m",
               "a positive number (N s/m) (in series with the contact the ribbon's race is "
               "massless, no outer_race_mass_kg: its damping sets the deflection rate)");
    }
  }
  return params;
}

// The ribbon the switch selects must be there; the other one, if given, is checked too, so
// that `--set tdb.X.four_dof.ribbon=...` can switch between two complete descriptions.
FourDofParams ReadFourDof(const TableReader& tdb, const GravityParams& gravity) {
  const TableReader table = tdb.Table("four_dof");
  table.AllowOnly({"inner_race_mass_kg", "outer_race_mass_kg", "ribbon_clearance_m", "bearing_law",
                   "ribbon", "inner_contact", "housing_contact", "bearing", "kelvin_voigt", "dahl",
                   "cross_coupled"});
  FourDofParams params;
  params.inner_race_mass_kg = table.Number("inner_race_mass_kg", Positive());
  params.outer_race_mass_kg = table.Number("outer_race_mass_kg", Positive());
  params.ribbon_clearance_m = table.Number("ribbon_clearance_m", NonNegative());
  params.gravity_y_m_s2 = gravity.enabled ? -gravity.acceleration_m_s2 : 0.0;
  params.inner_contact = ReadHuntCrossley(table, "inner_contact");
  params.housing_contact = ReadHousingContact(table, &params.housing_contact_enabled);
  const std::string bearing_law =
      table.Choice("bearing_law", {"hertz_linearised", "hertz", "quadratic", "linear"});
  params.bearing = ReadBallBearing(table, bearing_law == "hertz"       ? BearingLaw::kHertz
                                          : bearing_law == "quadratic" ? BearingLaw::kQuadratic
                                          : bearing_law == "linear"    ? BearingLaw::kLinear
                                                                    : BearingLaw::kHertzLinearised);
  const std::string ribbon = table.Choice("ribbon", {"kelvin_voigt", "dahl", "cross_coupled"});
  params.ribbon = ribbon == "dahl"            ? RibbonLaw::kDahl
                  : ribbon == "cross_coupled" ? RibbonLaw::kCrossCoupled
                                              : RibbonLaw::kKelvinVoigt;
  const auto ribbon_table = [&](std::string_view key) {
    return ribbon == key ? std::optional<TableReader>(table.Table(key)) : table.OptionalTable(key);
  };
  if (const auto kv = ribbon_table("kelvin_voigt")) params.kelvin_voigt = ReadKelvinVoigt(*kv);
  if (const auto dahl = ribbon_table("dahl")) params.dahl = ReadDahl(*dahl);
  if (const auto cc = ribbon_table("cross_coupled")) params.cross_coupled = ReadCrossCoupled(*cc);
  return params;
}

FrictionParams ReadFriction(const TableReader& tdb) {
  FrictionParams params;
  const auto table = tdb.OptionalTable("friction");
  if (!table) return params;
  table->AllowOnly({"law", "coefficient", "regularisation_s_per_m", "whirl_damping_N_s_per_m"});
  const std::string_view default_law =
      params.law == FrictionLaw::kNone ? "none" : "regularised_coulomb";
  params.law = table->Choice("law", {"regularised_coulomb", "none"}, default_law) == "none"
                   ? FrictionLaw::kNone
                   : FrictionLaw::kRegularisedCoulomb;
  params.coefficient = table->Number("coefficient", NonNegative(), params.coefficient);
  params.regularisation_s_per_m =
      table->Number("regularisation_s_per_m", Positive(), params.regularisation_s_per_m);
  params.whirl_damping_N_s_per_m =
      table->Number("whirl_damping_N_s_per_m", NonNegative(), params.whirl_damping_N_s_per_m);
  return params;
}

TdbSpinParams ReadSpin(const TableReader& tdb) {
  TdbSpinParams params;
  const auto table = tdb.OptionalTable("spin");
  if (!table) return params;
  table->AllowOnly({"enabled", "inertia_kg_m2", "rotational_damping_N_m_s", "palmgren_f1",
                    "pitch_diameter_m", "drag_torque_N_m", "drag_regularisation_s_per_rad"});
  params.enabled = table->Bool("enabled", params.enabled);
  params.inertia_kg_m2 = table->Number("inertia_kg_m2", Positive(), params.inertia_kg_m2);
  params.rotational_damping_N_m_s =
      table->Number("rotational_damping_N_m_s", NonNegative(), params.rotational_damping_N_m_s);
  params.palmgren_f1 = table->Number("palmgren_f1", NonNegative(), params.palmgren_f1);
  params.pitch_diameter_m =
      table->Number("pitch_diameter_m", NonNegative(), params.pitch_diameter_m);
  params.drag_torque_N_m = table->Number("drag_torque_N_m", NonNegative(), params.drag_torque_N_m);
  // Absent: the drag shares the friction's regularisation, as before the key existed.
  params.drag_regularisation_s_per_rad = table->Number("drag_regularisation_s_per_rad", Positive(),
                                                       params.drag_regularisation_s_per_rad);
  return params;
}

MisalignmentParams ReadMisalignment(const TableReader& tdb) {
  MisalignmentParams params;
  const auto table = tdb.OptionalTable("misalignment");
  if (!table) return params;
  table->AllowOnly({"enabled", "x_m", "y_m"});
  params.enabled = table->Bool("enabled", params.enabled);
  params.x_m = table->Number("x_m", AnyNumber(), params.x_m);
  params.y_m = table->Number("y_m", AnyNumber(), params.y_m);
  return params;
}

TdbParams ReadTdb(const std::string& name, const TableReader& table, const AxialRange& position,
                  const GravityParams& gravity) {
  table.AllowOnly({"position_m", "journal_radius_m", "clearance_m", "inner_race_radius_m", "model",
                   "contact_law", "friction", "spin", "misalignment", "four_dof",
                   "ball_bearing_tdb", "catcher_bearing"});
  TdbParams tdb;
  tdb.name = name;
  tdb.position_m = ReadAxialPosition(table, position);
  tdb.journal_radius_m = table.Number("journal_radius_m", Positive());
  tdb.clearance_m = table.Number("clearance_m", Positive());
  // Rir of the slip and race torque. The race bore surrounds the journal, so it cannot be smaller
  // than the journal radius. Absent: 0 in the parameters, derived where it is used (journal radius
  // + clearance, InnerRaceRadius), so that it follows a clearance changed later, as it did before
  // the key; the registry lists the value derived now as a default (declared = false), which a
  // reading with another clearance derives again.
  const NumberRule race_radius =
      AtLeast(tdb.journal_radius_m,
              "a radius at least journal_radius_m (the race bore surrounds the journal)");
  tdb.inner_race_radius_m =
      table.Number("inner_race_radius_m", race_radius, tdb.journal_radius_m + tdb.clearance_m);
  if (!table.Has("inner_race_radius_m")) tdb.inner_race_radius_m = 0.0;
  // The selected model's table is required; the other, if given, is checked too, so that
  // `--set tdb.X.model=...` can switch between two complete descriptions.
  const std::string model = table.Choice(
      "model", {"contact_law", "four_dof", "ball_bearing_tdb", "catcher_bearing"}, "contact_law");
  // The selected model's parameters are kept; another model's table is read for its checks
  // only.
  if (model == "contact_law" || table.Has("contact_law")) {
    ContactLawParams read = ReadContactLaw(table, gravity);
    if (model == "contact_law") tdb.model_params = std::move(read);
  }
  if (model == "four_dof" || table.Has("four_dof")) {
    FourDofParams read = ReadFourDof(table, gravity);
    if (model == "four_dof") tdb.model_params = std::move(read);
  }
  if (model == "ball_bearing_tdb" || table.Has("ball_bearing_tdb")) {
    BallBearingTdbParams read = ReadBallBearingTdb(table, gravity);
    if (model == "ball_bearing_tdb") tdb.model_params = std::move(read);
  }
  if (model == "catcher_bearing" || table.Has("catcher_bearing")) {
    CatcherBearingParams read = ReadCatcherBearing(table, gravity);
    if (model == "catcher_bearing") tdb.model_params = std::move(read);
  }
  if (tdb.model() == TdbModelKind::kCatcherBearing) {
    table.Reject("spin",
                 "no [spin] table with model = \"catcher_bearing\" (its races' inertias "
                 "and friction moments are in [catcher_bearing])");
  }
  if (tdb.model() == TdbModelKind::kBallBearing) {
    // Its journal/race friction is [ball_bearing_tdb.friction]; of [friction] it reads only the
    // regularisation its races' load torque shares (RaceAcceleration), so the rest would be
    // accepted and ignored.
    if (const auto friction = table.OptionalTable("friction")) {
      for (const std::string_view key : {"law", "coefficient", "whirl_damping_N_s_per_m"}) {
        friction->Reject(key,
                         "no key here: model = \"ball_bearing_tdb\" takes its friction from "
                         "[ball_bearing_tdb.friction], and of [friction] only "
                         "regularisation_s_per_m, the races' load torque regularisation");
      }
    }
  }
  tdb.friction = ReadFriction(table);
  tdb.spin = ReadSpin(table);
  tdb.misalignment = ReadMisalignment(table);
  return tdb;
}

}  // namespace

std::vector<TdbParams> ReadTdbs(const TableReader& root, const AxialRange& position) {
  const auto tables = root.NamedTables("tdb");
  root.CheckCount("tdb", tables.size(), kMaxTdbs, "touchdown bearings");
  // The races of 4-DOF TDBs carry their weight.
  const GravityParams gravity = ReadGravity(root);
  std::vector<TdbParams> tdbs;
  for (const auto& [name, table] : tables) tdbs.push_back(ReadTdb(name, table, position, gravity));
  return tdbs;
}

}  // namespace ambdrop::config_detail
