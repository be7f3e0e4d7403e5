// The fit's effects are `--set` overrides of the declared config (tools/fit/effect_library.hpp).
// What the report prints must be what was applied, and each line must reach the model: a line
// whose table the TDB's kind does not read, or a value the config refuses, would make a fitted
// effect that changes nothing, or one the user cannot paste back.
#include <gtest/gtest.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "io/config/config_variants.hpp"
#include "test_configs.hpp"
#include "tools/fit/effect_fit.hpp"
#include "tools/fit/effect_library.hpp"

namespace ambdrop::fit_effect_overrides_test {
namespace {

// The value sets an effect is applied at: its probe, its first starts, and each parameter at
// either bound (the fit searches the whole box, so the config must take all of it).
std::vector<std::vector<double>> Corners(const Effect& e) {
  std::vector<double> start;
  for (const EffectParameter& p : e.parameters) start.push_back(p.starts.front());
  std::vector<std::vector<double>> sets = {e.probe, start};
  for (std::size_t i = 0; i < e.parameters.size(); ++i) {
    if (e.parameters[i].periodic) continue;
    for (const double bound : {e.parameters[i].lower, e.parameters[i].upper}) {
      std::vector<double> v = start;
      v[i] = bound;
      sets.push_back(v);
    }
  }
  return sets;
}

// The seed rigs and the independent rigs' translations: a declared power-loss law other than
// the exponential (the magnet-biased flexible rig's ramp) once made the config refuse every
// flux-decay candidate.
std::vector<std::string> RigsAndTruthRigs() {
  std::vector<std::string> rigs = testing::RigConfigFiles();
  for (const std::string& r : testing::TruthRigConfigFiles()) rigs.push_back(r);
  return rigs;
}

TEST(FitEffectOverrides, EveryLineIsReadBackExactlyOnEveryRig) {
  int effects = 0;
  for (const std::string& rig : RigsAndTruthRigs()) {
    SCOPED_TRACE(rig);
    const ConfigVariants variants = testing::LoadTestVariants(rig);
    for (const Effect& e : EffectLibrary(variants)) {
      SCOPED_TRACE(e.name);
      ++effects;
      for (const std::vector<double>& values : Corners(e)) {
        const std::vector<std::string> lines = e.overrides(values);
        ASSERT_FALSE(lines.empty());
        LoadedConfig applied;
        try {
          applied = variants.With(lines);
        } catch (const ConfigError& error) {
          ADD_FAILURE() << "the config refuses the effect inside its fit range: " << error.what();
          continue;
        }
        for (const std::string& line : lines) {
          const std::size_t equals = line.find('=');
          ASSERT_NE(equals, std::string::npos) << line;
          const std::string path = line.substr(0, equals);
          const std::string text = line.substr(equals + 1);
          double number = 0.0;
          const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), number);
          if (error != std::errc() || end != text.data() + text.size()) continue;  // a switch
          const ConfigKey* key = FindKey(applied.keys, path);
          ASSERT_NE(key, nullptr) << line << ": no reader took it";
          EXPECT_EQ(key->value, number) << line << ": read back as " << key->value;
          EXPECT_EQ(key->location.rfind("--set ", 0), 0u) << line << " came from " << key->location;
        }
      }
    }
  }
  EXPECT_GT(effects, 100) << "the library offers too few effects over the rigs";
}

// A flux-decay candidate fits the law it names, whatever law the rig declares: the
// exponential ones switch a declared ramp or hold-then-exponential to the exponential (a
// declared hold of 1 ms once stayed under "exponential" and took its time constant to 2.7 ms
// where the record's was 4.7), the hold candidate switches to the hold.
TEST(FitEffectOverrides, EveryFluxDecayCandidateRunsTheLawItNames) {
  int candidates = 0;
  int parts = 0;  // a declared hold's numbers one at a time (the 4-DOF truth rig declares one)
  for (const std::string& rig : RigsAndTruthRigs()) {
    SCOPED_TRACE(rig);
    const ConfigVariants variants = testing::LoadTestVariants(rig);
    for (const Effect& e : EffectLibrary(variants)) {
      if (e.family != "amb_flux_decay") continue;
      SCOPED_TRACE(e.name);
      ++candidates;
      // amb_flux_decay_hold (both numbers), _hold_time and _hold_tau (one of a declared hold's
      // two, the other as declared).
      const bool hold = e.name.rfind("amb_flux_decay_hold", 0) == 0;
      parts += e.name == "amb_flux_decay_hold_time" || e.name == "amb_flux_decay_hold_tau";
      const ModelParams p = variants.With(e.overrides(e.probe)).params;
      const ModelParams& d = variants.declared().params;
      int touched = 0;
      for (std::size_t i = 0; i < p.ambs.size(); ++i) {
        const AmbParams& a = p.ambs[i];
        const bool named =
            e.name.find(':') == std::string::npos || e.name.substr(e.name.find(':') + 1) == a.name;
        if (!named) continue;
        ++touched;
        EXPECT_TRUE(a.flux_decay.enabled) << a.name;
        EXPECT_EQ(a.flux_decay.current_law, hold ? PowerLossCurrentLaw::kHoldThenExponential
                                                 : PowerLossCurrentLaw::kExponential)
            << a.name;
        if (e.name == "amb_flux_decay_hold_time") {
          EXPECT_EQ(a.flux_decay.time_constant_s, d.ambs[i].flux_decay.time_constant_s);
          EXPECT_NE(a.flux_decay.hold_time_s, d.ambs[i].flux_decay.hold_time_s);
        }
        if (e.name == "amb_flux_decay_hold_tau") {
          EXPECT_EQ(a.flux_decay.hold_time_s, d.ambs[i].flux_decay.hold_time_s);
          EXPECT_NE(a.flux_decay.time_constant_s, d.ambs[i].flux_decay.time_constant_s);
        }
      }
      EXPECT_GT(touched, 0);
    }
  }
  EXPECT_GT(candidates, 12);
  EXPECT_GE(parts, 2);
}

// At its probe, an effect moves some number the model reads; the declared config does not
// already hold it (an effect that changes nothing could not be fitted).
TEST(FitEffectOverrides, EveryEffectChangesTheModelAtItsProbe) {
  for (const std::string& rig : RigsAndTruthRigs()) {
    SCOPED_TRACE(rig);
    const ConfigVariants variants = testing::LoadTestVariants(rig);
    const std::vector<ConfigKey>& declared = variants.declared().keys;
    for (const Effect& e : EffectLibrary(variants)) {
      const LoadedConfig applied = variants.With(e.overrides(e.probe));
      bool changed = false;
      for (const ConfigKey& k : applied.keys) {
        const ConfigKey* before = FindKey(declared, k.path);
        changed |= before == nullptr || before->value != k.value;
      }
      EXPECT_TRUE(changed) << e.name << " at its probe leaves every number as declared";
    }
  }
}

// The tree the fit reads variants from is the declared config: with no overrides it gives the
// numbers LoadConfig gives, bit for bit, user overrides included.
TEST(FitEffectOverrides, VariantsWithoutOverridesAreTheDeclaredConfig) {
  const std::vector<std::string> user = {"tdb.de.clearance_m=2.1e-4", "trigger.time_s=0.1"};
  const ConfigVariants variants =
      testing::LoadTestVariants("jarroux2019_industrial_pid.toml", user);
  const LoadedConfig loaded =
      LoadConfig(testing::ConfigPath("jarroux2019_industrial_pid.toml"), user);
  const LoadedConfig again = variants.With({"tdb.de.clearance_m=2.1e-4"});
  ASSERT_EQ(loaded.keys.size(), variants.declared().keys.size());
  ASSERT_EQ(loaded.keys.size(), again.keys.size());
  for (std::size_t i = 0; i < loaded.keys.size(); ++i) {
    EXPECT_EQ(loaded.keys[i].path, again.keys[i].path);
    EXPECT_EQ(loaded.keys[i].value, variants.declared().keys[i].value) << loaded.keys[i].path;
    EXPECT_EQ(loaded.keys[i].value, again.keys[i].value) << loaded.keys[i].path;
  }
  EXPECT_EQ(variants.declared().params.tdbs.front().clearance_m, 2.1e-4);
}

// The user's own --set lines stay theirs in every variant: a power-loss law switched by --set
// leaves the file's numbers of the law it replaced unused in each candidate's config too, and
// a file key keeps its file:line. toml++ copies a node without its source, so a copied tree
// once made the switch look like the file's and every variant refused the file's hold time
// (`ambdrop fit` with the truth's own --set lines exited 2).
TEST(FitEffectOverrides, VariantsKeepTheUsersOverridesAsOverrides) {
  const std::string rig = "../tests/truth/rigid_fourdof_c.toml";  // it declares a hold
  const ConfigVariants variants =
      testing::LoadTestVariants(rig, {"amb.de.flux_decay.current_law=\"exponential\"",
                                      "amb.de.flux_decay.time_constant_s=4.7e-3"});
  LoadedConfig applied;
  ASSERT_NO_THROW(applied = variants.With({"tdb.de.clearance_m=3.2e-4"}));
  EXPECT_EQ(applied.params.ambs.size(), 2u);
  for (const AmbParams& a : applied.params.ambs) {
    EXPECT_EQ(a.flux_decay.current_law, a.name == "de" ? PowerLossCurrentLaw::kExponential
                                                       : PowerLossCurrentLaw::kHoldThenExponential);
  }
  const ConfigKey* clearance = FindKey(applied.keys, "tdb.nde.clearance_m");
  ASSERT_NE(clearance, nullptr);
  EXPECT_NE(clearance->location.find("rigid_fourdof_c.toml:"), std::string::npos)
      << clearance->location;
}

TEST(FitEffectOverrides, NumbersAreWrittenToReadBackExactly) {
  for (const double v : {0.1, 1.0, -0.0, 1e-5, 2.0 / 3.0, 1e20, -123456789.125, 5e-324}) {
    const std::string text = OverrideNumber(v);
    double back = 0.0;
    std::from_chars(text.data(), text.data() + text.size(), back);
    EXPECT_EQ(back, v) << text;
    EXPECT_NE(text.find_first_of(".e"), std::string::npos) << text << " would read as an integer";
  }
  EXPECT_THROW(OverrideNumber(std::nan("")), std::invalid_argument);
}

}  // namespace
}  // namespace ambdrop::fit_effect_overrides_test
