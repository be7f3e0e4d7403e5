// The generator's 4-DOF rig (tools/truth/rigs/rigid_fourdof_c.json) and ambdrop's translation
// of it (tests/truth/rigid_fourdof_c.toml): the 4-DOF TDB's static start agrees between the
// two codes (its --set lines load: truth_rig_translations_test): each race sags by
// its load over the stiffness that carries it (the generator's mount, ambdrop's Jarroux 2019
// model #2 with a linear bearing), which places the rotor's contact in the same spot.
#include <gtest/gtest.h>

#include <array>
#include <string>

#include "drop_run.hpp"
#include "io/config/config_loader.hpp"
#include "plant.hpp"
#include "rig.hpp"
#include "rt_core/four_dof_tdb.hpp"

namespace ambdrop::truth_fourdof_translation_test {
namespace {

const std::string kSource = AMBDROP_SOURCE_DIR;
const std::string kRig = kSource + "/tools/truth/rigs/rigid_fourdof_c.json";
const std::string kConfig = kSource + "/tests/truth/rigid_fourdof_c.toml";

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
