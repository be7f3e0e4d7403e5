#include "io/config_readers.hpp"
#include "rt_core/limits.hpp"

namespace ambdrop::config_detail {
namespace {

ContactLawParams ReadContactLaw(const TableReader& tdb) {
  const TableReader table = tdb.Table("contact_law");
  table.AllowOnly({"bearing_stiffness_N_per_m", "bearing_damping_N_s_per_m",
                   "ribbon_stiffness_N_per_m", "ribbon_damping_N_s_per_m", "ribbon_crushing_m"});
  ContactLawParams params;
  params.bearing_stiffness_N_per_m = table.Number("bearing_stiffness_N_per_m", Positive());
  params.bearing_damping_N_s_per_m = table.Number("bearing_damping_N_s_per_m", NonNegative());
  params.ribbon_stiffness_N_per_m = table.Number("ribbon_stiffness_N_per_m", Positive());
  params.ribbon_damping_N_s_per_m = table.Number("ribbon_damping_N_s_per_m", NonNegative());
  params.ribbon_crushing_m = table.Number("ribbon_crushing_m", NonNegative());
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
                    "pitch_diameter_m", "drag_torque_N_m"});
  params.enabled = table->Bool("enabled", params.enabled);
  params.inertia_kg_m2 = table->Number("inertia_kg_m2", Positive(), params.inertia_kg_m2);
  params.rotational_damping_N_m_s =
      table->Number("rotational_damping_N_m_s", NonNegative(), params.rotational_damping_N_m_s);
  params.palmgren_f1 = table->Number("palmgren_f1", NonNegative(), params.palmgren_f1);
  params.pitch_diameter_m =
      table->Number("pitch_diameter_m", NonNegative(), params.pitch_diameter_m);
  params.drag_torque_N_m = table->Number("drag_torque_N_m", NonNegative(), params.drag_torque_N_m);
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

TdbParams ReadTdb(const std::string& name, const TableReader& table, const AxialRange& position) {
  table.AllowOnly({"position_m", "journal_radius_m", "clearance_m", "model", "contact_law",
                   "friction", "spin", "misalignment"});
  TdbParams tdb;
  tdb.name = name;
  tdb.position_m = ReadAxialPosition(table, position);
  tdb.journal_radius_m = table.Number("journal_radius_m", Positive());
  tdb.clearance_m = table.Number("clearance_m", Positive());
  // One model so far; the key exists so that configs stay valid when more are added.
  table.Choice("model", {"contact_law"}, "contact_law");
  tdb.model = TdbModelKind::kContactLaw;
  tdb.contact_law = ReadContactLaw(table);
  tdb.friction = ReadFriction(table);
  tdb.spin = ReadSpin(table);
  tdb.misalignment = ReadMisalignment(table);
  return tdb;
}

}  // namespace

std::vector<TdbParams> ReadTdbs(const TableReader& root, const AxialRange& position) {
  const auto tables = root.NamedTables("tdb");
  root.CheckCount("tdb", tables.size(), kMaxTdbs, "touchdown bearings");
  std::vector<TdbParams> tdbs;
  for (const auto& [name, table] : tables) tdbs.push_back(ReadTdb(name, table, position));
  return tdbs;
}

}  // namespace ambdrop::config_detail
