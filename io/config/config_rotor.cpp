#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <map>
#include <numbers>
#include <optional>
#include <string>

#include "io/config/config_readers.hpp"
#include "rt_core/limits.hpp"

namespace ambdrop::config_detail {
namespace {

using MaterialMap = std::map<std::string, Material>;

// Section lengths that add up to e.g. 0.7999999999999999 must still admit a component at 0.8.
constexpr double kShaftEndTolerance = 1e-9;

// The finite-element model is dense, 4 DOF per node: 500 elements already take a 2004 x 2004
// eigenproblem; 100000 ran out of memory (a bare std::bad_alloc).
constexpr int kMaxShaftElements = 500;

const std::vector<std::string_view> kDiscMassKeys = {"mass_kg", "polar_inertia_kg_m2",
                                                     "transverse_inertia_kg_m2"};
const std::vector<std::string_view> kDiscGeometryKeys = {"outer_diameter_m", "inner_diameter_m",
                                                         "thickness_m", "material"};

MaterialMap ReadMaterials(const TableReader& rotor) {
  MaterialMap materials;
  for (const auto& [name, table] : rotor.NamedTables("materials")) {
    table.AllowOnly({"youngs_modulus_Pa", "shear_modulus_Pa", "density_kg_m3"});
    Material material;
    material.youngs_modulus_Pa = table.Number("youngs_modulus_Pa", Positive());
    material.shear_modulus_Pa = table.Number("shear_modulus_Pa", Positive());
    material.density_kg_m3 = table.Number("density_kg_m3", Positive());
    materials.emplace(name, material);
  }
  return materials;
}

const Material& LookUpMaterial(const TableReader& table, const MaterialMap& materials) {
  std::string expected = "the name of a [rotor.materials.NAME] table (none is defined)";
  if (!materials.empty()) {
    std::vector<std::string> names;
    for (const auto& entry : materials) names.push_back(fmt::format("{:?}", entry.first));
    expected =
        fmt::format("one of the materials {} (from [rotor.materials])", fmt::join(names, ", "));
  }
  if (!table.Has("material")) table.FailMissing("material", expected);
  if (!table.Find("material")->is_string()) table.Fail("material", expected);
  const auto found = materials.find(table.String("material"));
  if (found == materials.end()) table.Fail("material", expected);
  return found->second;
}

NumberRule InnerDiameterRule(double outer_diameter_m) {
  return NonNegativeBelow(
      outer_diameter_m,
      fmt::format("a non-negative number less than outer_diameter_m = {}", outer_diameter_m));
}

std::vector<ShaftSection> ReadSections(const TableReader& rotor, const MaterialMap& materials) {
  const std::vector<TableReader> tables = rotor.TableArray("sections");
  if (tables.empty()) {
    const std::string_view expected =
        "at least one shaft section ([[rotor.sections]]) for model = \"flexible\"";
    if (rotor.Has("sections")) rotor.Fail("sections", expected);
    rotor.FailMissing("sections", expected);
  }
  std::vector<ShaftSection> sections;
  int elements = 0;
  for (const TableReader& table : tables) {
    table.AllowOnly({"length_m", "outer_diameter_m", "inner_diameter_m", "material", "elements"});
    ShaftSection section;
    section.length_m = table.Number("length_m", Positive());
    section.outer_diameter_m = table.Number("outer_diameter_m", Positive());
    section.inner_diameter_m =
        table.Number("inner_diameter_m", InnerDiameterRule(section.outer_diameter_m), 0.0);
    section.material = LookUpMaterial(table, materials);
    section.elements = table.Integer("elements", 1, kMaxShaftElements, section.elements);
    elements += section.elements;
    if (elements > kMaxShaftElements) {
      table.Fail(
          "elements",
          fmt::format("at most {} elements over all sections of the shaft", kMaxShaftElements),
          fmt::format("{} (the shaft's {} so far)", section.elements, elements));
    }
    sections.push_back(section);
  }
  return sections;
}

void ReadGeometricDisc(const TableReader& table, const MaterialMap& materials, Disc& disc) {
  const double outer = table.Number("outer_diameter_m", Positive());
  const double inner = table.Number("inner_diameter_m", InnerDiameterRule(outer), 0.0);
  const double thickness = table.Number("thickness_m", Positive());
  const double density = LookUpMaterial(table, materials).density_kg_m3;
  const double diameters_squared = outer * outer + inner * inner;
  disc.mass_kg = density * std::numbers::pi / 4.0 * (outer * outer - inner * inner) * thickness;
  disc.polar_inertia_kg_m2 = disc.mass_kg / 8.0 * diameters_squared;
  disc.transverse_inertia_kg_m2 =
      disc.mass_kg / 16.0 * diameters_squared + disc.mass_kg * thickness * thickness / 12.0;
}

Disc ReadDisc(const TableReader& table, std::size_t index, const MaterialMap& materials,
              const AxialRange& position) {
  std::vector<std::string_view> allowed = {"name", "position_m"};
  allowed.insert(allowed.end(), kDiscMassKeys.begin(), kDiscMassKeys.end());
  allowed.insert(allowed.end(), kDiscGeometryKeys.begin(), kDiscGeometryKeys.end());
  table.AllowOnly(allowed);

  Disc disc;
  disc.name = table.String("name", fmt::format("disc{}", index));
  disc.position_m = ReadAxialPosition(table, position);
  const auto has_any = [&table](const std::vector<std::string_view>& keys) {
    return std::any_of(keys.begin(), keys.end(), [&table](auto key) { return table.Has(key); });
  };
  if (has_any(kDiscMassKeys)) {
    for (const std::string_view key : kDiscGeometryKeys) {
      table.Reject(key,
                   "no geometry key next to mass_kg / polar_inertia_kg_m2 / "
                   "transverse_inertia_kg_m2 (a disc is given by its mass and inertias or by its "
                   "geometry, not both)");
    }
    disc.mass_kg = table.Number("mass_kg", NonNegative());
    disc.polar_inertia_kg_m2 = table.Number("polar_inertia_kg_m2", NonNegative());
    disc.transverse_inertia_kg_m2 = table.Number("transverse_inertia_kg_m2", NonNegative());
  } else if (has_any(kDiscGeometryKeys)) {
    ReadGeometricDisc(table, materials, disc);
  } else {
    table.FailMissing("mass_kg",
                      "a non-negative number (kg) with polar_inertia_kg_m2 and "
                      "transverse_inertia_kg_m2, or a geometric disc (outer_diameter_m, "
                      "thickness_m, material)");
  }
  return disc;
}

RigidRotorParams ReadRigid(const TableReader& rotor) {
  const TableReader table = rotor.Table("rigid");
  table.AllowOnly(
      {"mass_kg", "polar_inertia_kg_m2", "transverse_inertia_kg_m2", "centre_of_mass_m"});
  RigidRotorParams rigid;
  rigid.mass_kg = table.Number("mass_kg", Positive());
  rigid.polar_inertia_kg_m2 = table.Number("polar_inertia_kg_m2", Positive());
  rigid.transverse_inertia_kg_m2 = table.Number("transverse_inertia_kg_m2", Positive());
  rigid.centre_of_mass_m = table.Number("centre_of_mass_m", AnyNumber());
  return rigid;
}

ShaftElementTheory ReadElementTheory(const TableReader& rotor) {
  const std::string theory =
      rotor.Choice("element_theory", {"timoshenko", "rayleigh", "euler_bernoulli"}, "timoshenko");
  if (theory == "rayleigh") return ShaftElementTheory::kRayleigh;
  if (theory == "euler_bernoulli") return ShaftElementTheory::kEulerBernoulli;
  return ShaftElementTheory::kTimoshenko;
}

// A disabled table need not give its numbers; any it gives are still checked.
CoastDownParams ReadCoastDown(const TableReader& rotor) {
  CoastDownParams c;
  const std::optional<TableReader> table = rotor.OptionalTable("coast_down");
  if (!table) return c;
  table->AllowOnly({"enabled", "constant_torque_N_m", "viscous_N_m_s", "windage_N_m_s2",
                    "sign_regularisation_s_per_rad"});
  c.enabled = table->Bool("enabled", c.enabled);
  c.constant_torque_N_m =
      table->Number("constant_torque_N_m", NonNegative(), c.constant_torque_N_m);
  c.viscous_N_m_s = table->Number("viscous_N_m_s", NonNegative(), c.viscous_N_m_s);
  c.windage_N_m_s2 = table->Number("windage_N_m_s2", NonNegative(), c.windage_N_m_s2);
  c.sign_regularisation_s_per_rad =
      table->Number("sign_regularisation_s_per_rad", Positive(), c.sign_regularisation_s_per_rad);
  return c;
}

}  // namespace

AxialRange ShaftRange(const RotorParams& rotor) {
  if (rotor.kind == RotorKind::kRigid) return AxialRange{.rule = AnyNumber()};
  double length = 0.0;
  for (const ShaftSection& section : rotor.sections) length += section.length_m;
  NumberRule rule = InRange(0.0, length * (1.0 + kShaftEndTolerance));
  rule.what = fmt::format("a position on the shaft, in [0, {}]", length);
  return AxialRange{.rule = std::move(rule), .end_m = length};
}

double ReadAxialPosition(const TableReader& table, const AxialRange& range) {
  return std::min(table.Number("position_m", range.rule), range.end_m);
}

RotorParams ReadRotor(const TableReader& root) {
  const TableReader rotor = root.Table("rotor");
  RotorParams params;
  const bool rigid = rotor.Choice("model", {"flexible", "rigid"}) == "rigid";
  if (rigid) {
    params.kind = RotorKind::kRigid;
    for (const std::string_view key : {"materials", "sections", "discs"}) {
      rotor.Reject(key, fmt::format("no {} with model = \"rigid\" (a rigid rotor is described by "
                                    "[rotor.rigid] alone)",
                                    key));
    }
    rotor.Reject("element_theory",
                 "no element_theory with model = \"rigid\" (it selects the flexible shaft's "
                 "beam elements)");
    rotor.AllowOnly({"model", "modes", "modal_damping_ratio", "rigid", "coast_down"});
  } else {
    rotor.Reject("rigid",
                 "no [rotor.rigid] table with model = \"flexible\" (set model = \"rigid\" to use "
                 "it)");
    rotor.AllowOnly({"model", "modes", "modal_damping_ratio", "materials", "sections", "discs",
                     "element_theory", "coast_down"});
  }
  params.modes = rotor.Integer("modes", 1, kMaxModes, params.modes);
  params.modal_damping_ratio =
      rotor.Number("modal_damping_ratio", InHalfOpenRange(0.0, 1.0), params.modal_damping_ratio);
  params.coast_down = ReadCoastDown(rotor);
  if (rigid) {
    params.rigid = ReadRigid(rotor);
    return params;
  }
  params.element_theory = ReadElementTheory(rotor);
  const MaterialMap materials = ReadMaterials(rotor);
  params.sections = ReadSections(rotor, materials);
  const AxialRange position = ShaftRange(params);
  const std::vector<TableReader> discs = rotor.TableArray("discs");
  for (std::size_t i = 0; i < discs.size(); ++i) {
    params.discs.push_back(ReadDisc(discs[i], i, materials, position));
  }
  return params;
}

}  // namespace ambdrop::config_detail
