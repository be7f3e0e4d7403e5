// The generator's rigid rigs and ambdrop's translations of them (tests/truth/<rig>.toml), as a
// user meets them: every hidden effect's and every declared_off entry's --set lines load on the
// translation (no unknown key, a value in range), and the two codes hold the rotor with the same
// currents: each AMB carries its share of the weight (moments about the centre of mass),
// through the differential electromagnet law at the centre, the generator's own statics against
// ambdrop's. rigid_fourdof_c is the 4-DOF rig (its races' sag: truth_fourdof_translation_test);
// rigid_rotor_e and rigid_fourdof_f were made in session 50, rigid_hc_g (contact-law TDBs with
// Hunt-Crossley's law, 25.6 kHz records) in session 52, after the fit's rules, to try them on
// rigs none was made on.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

#include "declared_off.hpp"
#include "drop_run.hpp"
#include "effects.hpp"
#include "io/config/config_loader.hpp"
#include "rig.hpp"
#include "rt_core/model.hpp"

namespace ambdrop::truth_rig_translations_test {
namespace {

const std::string kSource = AMBDROP_SOURCE_DIR;

struct TranslatedRig {
  std::string name;
  std::size_t declared_entries;  // the sheet's numbers a declared_off draw may move
};

std::ostream& operator<<(std::ostream& out, const TranslatedRig& r) {
  return out << r.name;
}

class TruthRigTranslation : public ::testing::TestWithParam<TranslatedRig> {
 protected:
  std::string Rig() const { return kSource + "/tools/truth/rigs/" + GetParam().name + ".json"; }
  std::string Config() const { return kSource + "/tests/truth/" + GetParam().name + ".toml"; }
};

// The truth's --set lines on the translation: "" when they load, else the config's message.
std::string LoadError(const std::string& config, const ambdrop_truth::Truth& t) {
  std::vector<std::string> sets;
  for (const auto& [key, value] : t.ambdrop_keys) sets.push_back(key + "=" + value);
  try {
    LoadConfig(config, sets);
  } catch (const std::exception& error) {
    return error.what();
  }
  return "";
}

TEST_P(TruthRigTranslation, EveryEffectAndEveryDeclaredNumberLoads) {
  const ambdrop_truth::Rig declared = ambdrop_truth::ReadRig(Rig());
  for (const std::string& kind : ambdrop_truth::EffectKinds()) {
    SCOPED_TRACE(kind);
    ambdrop_truth::Rig rig = declared;
    EXPECT_EQ(LoadError(Config(), ambdrop_truth::ApplyEffect(kind, 3, &rig)), "");
  }
  const std::vector<ambdrop_truth::DeclaredEntry> entries =
      ambdrop_truth::DeclaredOffEntries(declared);
  EXPECT_EQ(entries.size(), GetParam().declared_entries);
  for (std::size_t i = 0; i < entries.size(); ++i) {
    SCOPED_TRACE(entries[i].name);
    ambdrop_truth::Rig rig = declared;
    const ambdrop_truth::Truth t = ambdrop_truth::ApplyDraw(
        entries, ambdrop_truth::DrawDeclaredOff(declared, entries, static_cast<int>(i), 5, 0), 0,
        &rig);
    EXPECT_EQ(LoadError(Config(), t), "");
  }
}

TEST_P(TruthRigTranslation, BothCodesHoldTheRotorWithTheSameCurrents) {
  const ambdrop_truth::Rig rig = ambdrop_truth::ReadRig(Rig());
  std::array<std::array<double, 2>, 2> held{};
  ambdrop_truth::EquilibriumState(rig, &held);
  const Model model = BuildModel(LoadConfig(Config()).params);
  const ControlInput input = StaticLoadInput(model);
  ASSERT_EQ(model.params.ambs.size(), 2u);
  double carried_N = 0.0;
  for (std::size_t a = 0; a < 2; ++a) {
    const std::size_t g = rig.ambs[0].name == model.params.ambs[a].name ? 0 : 1;
    SCOPED_TRACE(model.params.ambs[a].name);
    EXPECT_NEAR(input.amb[a].current_A[0], held[g][0], 1e-9);
    // Lifting: of the order of an ampere, so a relative 1e-9.
    EXPECT_GT(input.amb[a].current_A[1], 0.1);
    EXPECT_NEAR(input.amb[a].current_A[1] / held[g][1], 1.0, 1e-9);
    // The differential law at the centre, 4 k I0 i / g0^2 (seed 003 Eq. (2) linearised).
    const ambdrop_truth::AmbRig& amb = rig.ambs[g];
    carried_N += 4.0 * amb.electromagnet_constant_N_m2_per_A2 * amb.bias_current_A * held[g][1] /
                 (amb.nominal_gap_m * amb.nominal_gap_m);
  }
  // Together they carry the weight: a check of the pair that needs neither code.
  EXPECT_NEAR(carried_N / (rig.rotor.mass_kg * rig.gravity_m_s2), 1.0, 1e-9);
}

// The entries: the rigid rotor's 4, the coast-down's one loss (none on c), the power loss's
// numbers (c and g: its hold and time constant),
// per AMB 4 (constant, bias, gap, station), per sensor 5 (station, gain and offset per axis),
// the PID's 7; per contact-law TDB 9 (the inner-race radius given; on g, 8: the race rolls at
// the journal's radius, and its Hunt-Crossley contact's two numbers stand in place of the
// linear contact's two), per 4-DOF TDB 15 (its
// contact's two numbers, both races' masses, the bearing's and the ribbon's stiffness and
// damping in place of the linear contact's two).
INSTANTIATE_TEST_SUITE_P(
    Rigs, TruthRigTranslation,
    ::testing::Values(TranslatedRig{"rigid_fourdof_c", 4 + 0 + 2 + 8 + 10 + 7 + 30},
                      TranslatedRig{"rigid_rotor_e", 4 + 1 + 1 + 8 + 10 + 7 + 18},
                      TranslatedRig{"rigid_fourdof_f", 4 + 1 + 1 + 8 + 10 + 7 + 30},
                      TranslatedRig{"rigid_hc_g", 4 + 1 + 2 + 8 + 10 + 7 + 16}),
    [](const ::testing::TestParamInfo<TranslatedRig>& info) { return info.param.name; });

}  // namespace
}  // namespace ambdrop::truth_rig_translations_test
