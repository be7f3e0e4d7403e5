// Friswell et al., Dynamics of Rotating Machines (2010), Example 5.9.1: natural frequencies of
// a two-disc Timoshenko rotor on 1 MN/m bearings at 0 and 4000 rpm, each within 0.1 %.
#include <gtest/gtest.h>

#include <numbers>
#include <vector>

#include "rt_core/modal_analysis.hpp"
#include "test_configs.hpp"

namespace ambdrop::friswell_validation_test {
namespace {

void ExpectFrequencies(const std::vector<double>& got, const std::vector<double>& published) {
  ASSERT_GE(got.size(), published.size());
  for (std::size_t i = 0; i < published.size(); ++i) {
    EXPECT_NEAR(got[i] / published[i], 1.0, 1e-3) << "mode " << i << ": " << got[i] << " rad/s";
  }
}

TEST(FriswellExample591, FrequenciesAtRest) {
  const ModelParams p = testing::LoadTestConfig("friswell_5_9_1.toml");
  const ModalAnalysis m = AnalyseModes(p, 0.0, 6);
  const std::vector<double> published{86.66, 86.66, 274.31, 274.31, 716.78, 716.78};
  ExpectFrequencies(m.supported_rad_s, published);
  ExpectFrequencies(m.reduced_supported_rad_s, published);
}

TEST(FriswellExample591, FrequenciesAt4000Rpm) {
  const ModelParams p = testing::LoadTestConfig("friswell_5_9_1.toml");
  const ModalAnalysis m = AnalyseModes(p, 4000.0 * std::numbers::pi / 30.0, 6);
  const std::vector<double> published{85.39, 87.80, 251.78, 294.71, 600.18, 827.08};
  ExpectFrequencies(m.supported_rad_s, published);
  ExpectFrequencies(m.reduced_supported_rad_s, published);
}

}  // namespace
}  // namespace ambdrop::friswell_validation_test
