// The generator's 4-DOF rig (tools/truth/rigs/rigid_fourdof_c.json) and ambdrop's translation
// of it (tests/truth/rigid_fourdof_c.toml), as a user meets them: every hidden effect's and
// every declared_off entry's --set lines load on the translation (no unknown key, a value in
// range), and the 4-DOF TDB's static start agrees between the two codes: each race sags by
// its load over the stiffness that carries it (the generator's mount, ambdrop's Jarroux 2019
// model #2 with a linear bearing), which places the rotor's contact in the same spot.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "declared_off.hpp"
#include "drop_run.hpp"
#include "effects.hpp"
#include "io/config/config_loader.hpp"
#include "plant.hpp"
#include "rig.hpp"
#include "rt_core/four_dof_tdb.hpp"

namespace ambdrop::truth_fourdof_translation_test {
namespace {

const std::string kSource = AMBDROP_SOURCE_DIR;
const std::string kRig = kSource + "/tools/truth/rigs/rigid_fourdof_c.json";
const std::string kConfig = kSource + "/tests/truth/rigid_fourdof_c.toml";

// The truth's --set lines on the translation: "" when they load, else the config's message.
std::string LoadError(const ambdrop_truth::Truth& t) {
  std::vector<std::string> sets;
  for (const auto& [key, value] : t.ambdrop_keys) sets.push_back(key + "=" + value);
  try {
    LoadConfig(kConfig, sets);
  } catch (const std::exception& error) {
    return error.what();
  }
  return "";
}

TEST(TruthFourDofTranslation, EveryEffectAndEveryDeclaredNumberLoads) {
  const ambdrop_truth::Rig declared = ambdrop_truth::ReadRig(kRig);
  int loaded = 0;
  for (const std::string& kind : ambdrop_truth::EffectKinds()) {
    SCOPED_TRACE(kind);
    ambdrop_truth::Rig rig = declared;
    const ambdrop_truth::Truth t = ambdrop_truth::ApplyEffect(kind, 3, &rig);
    EXPECT_EQ(LoadError(t), "");
    ++loaded;
  }
  const std::vector<ambdrop_truth::DeclaredEntry> entries =
      ambdrop_truth::DeclaredOffEntries(declared);
  for (std::size_t i = 0; i < entries.size(); ++i) {
    SCOPED_TRACE(entries[i].name);
    ambdrop_truth::Rig rig = declared;
    const ambdrop_truth::Truth t = ambdrop_truth::ApplyDraw(
        entries, ambdrop_truth::DrawDeclaredOff(declared, entries, static_cast<int>(i), 5, 0), 0,
        &rig);
    EXPECT_EQ(LoadError(t), "");
    ++loaded;
  }
  // 15 kinds and clean; per TDB the 4-DOF numbers in place of the linear contact's.
  EXPECT_EQ(loaded, 16 + 61);
}

TEST(TruthFourDofTranslation, TheRacesSagAlikeInBothCodes) {
  const ambdrop_truth::Rig rig = ambdrop_truth::ReadRig(kRig);
  std::array<std::array<double, 2>, 2> held{};
  const ambdrop_truth::PlantState y = ambdrop_truth::EquilibriumState(rig, &held);
  const ambdrop_truth::Plant plant(rig);
  const ModelParams params = LoadConfig(kConfig).params;
  ASSERT_EQ(params.tdbs.size(), 2u);
  for (int t = 0; t < 2; ++t) {
    SCOPED_TRACE(rig.tdbs[t].name);
    const TdbParams& p =
        params.tdbs[t].name == rig.tdbs[t].name ? params.tdbs[t] : params.tdbs[1 - t];
    const FourDofTdb tdb(p);
    std::array<double, FourDofTdb::kStatesDahl> s{};
    tdb.InitialState(s.data());
    // Both codes: y up, the race centres below the TDB's centre by sub-micrometre sags.
    const double generator_outer = y(plant.layout().outer_race(t) + 1);
    const double generator_inner = y(plant.layout().housing(t) + 1);
    EXPECT_LT(generator_inner, generator_outer);
    EXPECT_LT(generator_outer, 0.0);
    EXPECT_NEAR(s[FourDofTdb::kOuterY], generator_outer, 1e-12);
    EXPECT_NEAR(s[FourDofTdb::kInnerY], generator_inner, 1e-12);
  }
}

}  // namespace
}  // namespace ambdrop::truth_fourdof_translation_test
