// The 4-DOF TDB config keys ([tdb.NAME.four_dof], Jarroux 2019 models #2/#3): the shipped
// configs read as written, the switches select the laws, and every rule has a negative test that
// checks the message (file:line, key, expected, found).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "io/config/config_loader.hpp"
#include "test_configs.hpp"

namespace ambdrop::config_four_dof_test {
namespace {

using ::testing::HasSubstr;

std::string ErrorOf(const std::string& file, const std::vector<std::string>& overrides) {
  try {
    LoadConfig(testing::ConfigPath(file), overrides);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ConfigFourDof, Model2ReadsAsWritten) {
  const ModelParams p = testing::LoadTestConfig("jarroux2019_industrial_model2.toml");
  ASSERT_EQ(p.tdbs.size(), 2u);
  for (const TdbParams& t : p.tdbs) {
    EXPECT_EQ(t.model(), TdbModelKind::kFourDof);
    const FourDofParams& f = t.four_dof();
    EXPECT_EQ(f.ribbon, RibbonLaw::kKelvinVoigt);
    EXPECT_EQ(f.bearing.law, BearingLaw::kHertzLinearised);
    EXPECT_DOUBLE_EQ(f.inner_race_mass_kg, 0.4);
    EXPECT_DOUBLE_EQ(f.ribbon_clearance_m, 0.146e-3);
    EXPECT_DOUBLE_EQ(f.gravity_y_m_s2, -9.81);  // from [gravity]
    EXPECT_EQ(f.bearing.balls, 40);
    EXPECT_DOUBLE_EQ(f.inner_contact.exponent, 1.0);
    EXPECT_DOUBLE_EQ(f.kelvin_voigt.stiffness_N_per_m, 5.13e6);
    EXPECT_DOUBLE_EQ(t.friction.coefficient, 0.2);
  }
}

TEST(ConfigFourDof, Model3SelectsTheDahlRibbon) {
  const ModelParams p = testing::LoadTestConfig("jarroux2019_industrial_model3.toml",
                                                {"tdb.de.four_dof.dahl.threshold_scale=0.5"});
  const TdbParams& de = p.tdbs.at(0).name == "de" ? p.tdbs.at(0) : p.tdbs.at(1);
  EXPECT_EQ(de.four_dof().ribbon, RibbonLaw::kDahl);
  EXPECT_DOUBLE_EQ(de.four_dof().dahl.slipping_threshold_N, 1000.0);
  EXPECT_DOUBLE_EQ(de.four_dof().dahl.threshold_scale, 0.5);
  EXPECT_DOUBLE_EQ(de.four_dof().dahl.beta_per_m, 1.0e6);
}

TEST(ConfigFourDof, SwitchesSelectTheLaws) {
  const ModelParams p =
      testing::LoadTestConfig("jarroux2019_industrial_model2.toml",
                              {"tdb.de.four_dof.bearing_law=\"hertz\"", "gravity.enabled=false"});
  const TdbParams& de = p.tdbs.at(0).name == "de" ? p.tdbs.at(0) : p.tdbs.at(1);
  EXPECT_EQ(de.four_dof().bearing.law, BearingLaw::kHertz);
  EXPECT_EQ(de.four_dof().gravity_y_m_s2, 0.0);
  // The base's contact-law TDB keeps its model unless told.
  const ModelParams base = testing::LoadTestConfig("jarroux2019_industrial.toml");
  EXPECT_EQ(base.tdbs.at(0).model(), TdbModelKind::kContactLaw);
}

// A rig sheet's linear bearing (kb, cb) is declared as given: the independent 4-DOF rig's
// translation (tests/truth/rigid_fourdof_c.toml) reads back its numbers, and the races sag by
// the weights over them (the TDB's own static start, tests/four_dof_tdb_test.cpp).
TEST(ConfigFourDof, ALinearBearingTakesTheSheetsNumbers) {
  const ModelParams p = testing::LoadTestConfig("../tests/truth/rigid_fourdof_c.toml",
                                                {"tdb.de.four_dof.bearing.damping_N_s_per_m=0"});
  for (const TdbParams& t : p.tdbs) {
    const BallBearingParams& b = t.four_dof().bearing;
    EXPECT_EQ(b.law, BearingLaw::kLinear);
    EXPECT_EQ(b.stiffness_N_per_m, 1.5e8);
    EXPECT_EQ(b.damping_N_s_per_m, t.name == "de" ? 0.0 : 1500.0);
    EXPECT_FALSE(t.four_dof().housing_contact_enabled);
  }
}

TEST(ConfigFourDof, ErrorsNameFileLineKeyAndExpectation) {
  const std::string model2 = "jarroux2019_industrial_model2.toml";
  EXPECT_THAT(ErrorOf(model2, {"tdb.de.four_dof.ribon=\"dahl\""}),
              HasSubstr("unknown key 'tdb.de.four_dof.ribon' (allowed here: inner_race_mass_kg"));
  EXPECT_THAT(ErrorOf(model2, {"tdb.de.four_dof.ribbon=\"dahl\""}),
              HasSubstr("missing key 'tdb.de.four_dof.dahl': expected a table "
                        "([tdb.de.four_dof.dahl])"));
  EXPECT_THAT(ErrorOf(model2, {"tdb.de.four_dof.bearing_law=\"harris\""}),
              HasSubstr("key 'tdb.de.four_dof.bearing_law': expected one of "
                        "\"hertz_linearised\", \"hertz\", \"quadratic\", \"linear\", found "
                        "\"harris\""));
  // The linear law reads the sheet's kbrg and cbrg, and none of the Hertz data.
  EXPECT_THAT(ErrorOf(model2, {"tdb.de.four_dof.bearing_law=\"linear\""}),
              HasSubstr("unknown key 'tdb.de.four_dof.bearing.balls' (allowed here: "
                        "stiffness_N_per_m, damping_N_s_per_m)"));
  EXPECT_THAT(ErrorOf(model2, {"tdb.de.four_dof.bearing.balls=0"}),
              HasSubstr("key 'tdb.de.four_dof.bearing.balls': expected an integer >= 1"));
  EXPECT_THAT(ErrorOf(model2, {"tdb.de.four_dof.inner_contact.exponent=3.0"}),
              HasSubstr("key 'tdb.de.four_dof.inner_contact.exponent': expected a number in "
                        "[1, 2], found 3"));
  EXPECT_THAT(ErrorOf(model2, {"tdb.de.four_dof.bearing.inner_contact_stiffness_N_per_m1_5=-1"}),
              HasSubstr("expected a positive number (N/m^1.5), found -1"));
  EXPECT_THAT(ErrorOf(model2, {"tdb.de.model=\"four_dofs\""}),
              HasSubstr("key 'tdb.de.model': expected one of \"contact_law\", \"four_dof\""));
  // A file error points at the file and line of the value.
  const std::string model3 = "jarroux2019_industrial_model3.toml";
  EXPECT_THAT(ErrorOf(model3, {"tdb.nde.four_dof.dahl.beta_per_m=0"}),
              HasSubstr("key 'tdb.nde.four_dof.dahl.beta_per_m': expected a positive number "
                        "(1/m), found 0"));
  // The model switch needs the selected model's table.
  EXPECT_THAT(ErrorOf("jarroux2019_industrial.toml", {"tdb.de.model=\"four_dof\""}),
              HasSubstr("missing key 'tdb.de.four_dof': expected a table ([tdb.de.four_dof])"));
}

TEST(ConfigFourDof, ErrorInTheFileNamesItsLine) {
  const std::string text = R"(name = "x"
[rotor]
model = "rigid"
[rotor.rigid]
mass_kg = 10.0
polar_inertia_kg_m2 = 0.1
transverse_inertia_kg_m2 = 0.2
centre_of_mass_m = 0.0
[tdb.a]
position_m = 0.0
journal_radius_m = 0.02
clearance_m = 2e-4
model = "four_dof"
[tdb.a.four_dof]
inner_race_mass_kg = -0.4
)";
  try {
    LoadConfigFromString(text, "t.toml");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_THAT(std::string(e.what()),
                HasSubstr("t.toml:15: key 'tdb.a.four_dof.inner_race_mass_kg': expected a "
                          "positive number (kg), found -0.4"));
  }
}

}  // namespace
}  // namespace ambdrop::config_four_dof_test
