// The generator's flexible rig (tools/truth/rigs/flexible_pm_b.json) and ambdrop's translation
// of it (tests/truth/flexible_pm_b.toml), number by number: every declared_off entry of that
// rig names an ambdrop key, and its --set line must load on the translation (no unknown key, a
// value in range); a shaft's number moved by its draw must move ambdrop's free-free bending
// frequencies as it moves the generator's (two finite-element codes sharing nothing: within
// 0.3 %, as they agree on the declared shaft).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "declared_off.hpp"
#include "io/config/config_loader.hpp"
#include "rig.hpp"
#include "rotor_modes.hpp"
#include "rt_core/modal_analysis.hpp"

namespace ambdrop::truth_flexible_translation_test {
namespace {

// The first three free-free bending frequencies (rad/s) of each side (ambdrop lists each once
// per plane).
std::vector<double> Generator(const ambdrop_truth::Rig& rig) {
  std::vector<double> w =
      ambdrop_truth::FreeFreeBendingFrequencies(rig.shaft, ambdrop_truth::HardwareStations(rig));
  w.resize(3);
  return w;
}
std::vector<double> Ambdrop(const ModelParams& params) {
  std::vector<double> w;
  for (const double v : AnalyseModes(params, 0.0, 12).free_free_rad_s) {
    if (v > 1.0 && w.size() < 3 && (w.empty() || v > w.back() * (1.0 + 1e-9))) w.push_back(v);
  }
  return w;
}

TEST(TruthFlexibleTranslation, EveryDeclaredNumberLoadsAndTheShaftsMoveAlike) {
  const std::string source = AMBDROP_SOURCE_DIR;
  const ambdrop_truth::Rig declared =
      ambdrop_truth::ReadRig(source + "/tools/truth/rigs/flexible_pm_b.json");
  const std::string config = source + "/tests/truth/flexible_pm_b.toml";
  const std::vector<ambdrop_truth::DeclaredEntry> entries =
      ambdrop_truth::DeclaredOffEntries(declared);
  ASSERT_FALSE(entries.empty());
  const std::vector<double> clean_generator = Generator(declared);
  const std::vector<double> clean_ambdrop = Ambdrop(LoadConfig(config).params);
  ASSERT_EQ(clean_ambdrop.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_NEAR(clean_ambdrop[k] / clean_generator[k], 1.0, 3e-3) << "mode " << k;
  }
  int shaft_entries = 0;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const ambdrop_truth::DeclaredEntry& e = entries[i];
    SCOPED_TRACE(e.name);
    ambdrop_truth::Rig rig = declared;
    const ambdrop_truth::Truth t = ambdrop_truth::ApplyDraw(
        entries, ambdrop_truth::DrawDeclaredOff(declared, entries, static_cast<int>(i), 5, 0), 0,
        &rig);
    std::vector<std::string> sets;
    for (const auto& [key, value] : t.ambdrop_keys) sets.push_back(key + "=" + value);
    ModelParams params;
    try {
      params = LoadConfig(config, sets).params;
    } catch (const std::exception& error) {
      ADD_FAILURE() << sets.front() << ": " << error.what();
      continue;
    }
    if (!e.name.starts_with("rotor.shaft.")) continue;
    ++shaft_entries;
    const std::vector<double> g = Generator(rig);
    const std::vector<double> a = Ambdrop(params);
    ASSERT_EQ(a.size(), 3u);
    for (std::size_t k = 0; k < 3; ++k) {
      // How far the draw moved the mode, and how far apart the two codes are after it.
      const double moved = std::abs(g[k] / clean_generator[k] - 1.0);
      EXPECT_NEAR(a[k] / g[k], 1.0, 3e-3) << "mode " << k << " moved " << moved;
    }
  }
  EXPECT_EQ(shaft_entries, 2 + 5 + 16);
}

}  // namespace
}  // namespace ambdrop::truth_flexible_translation_test
