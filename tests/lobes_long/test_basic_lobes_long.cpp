// Long statistical tests of the basic lobes (label "long"): the chi-square grid at >= 1e6
// samples per case with ARCHWAVE_FULL_BUDGET=1 (a tenth by default, see
// tests/lobes/lobe_harness.h), and white furnaces at the same budget. The fast versions of
// these checks run in tests/lobes on every CI run.
#include <gtest/gtest.h>

#include "kernels/lobes/diffuse.h"
#include "kernels/lobes/translucency.h"
#include "tests/lobes/lobe_harness.h"

namespace aw {
namespace lobe_test {
namespace {

const float kRoughness[] = {0.0f, 0.25f, 0.5f, 1.0f};
const double kDiffuseTheta[] = {0.0, 30.0, 60.0, 80.0, 89.0};  // 89: grazing
const double kTranslucencyTheta[] = {0.0, 30.0, 60.0, 80.0, 89.0, 135.0};

LobeFns diffuse_fns(float3 albedo, float roughness) {
  return LobeFns{[=](float3 wo, float3 wi) { return lobe_diffuse_eval(albedo, roughness, wo, wi); },
                 [=](float3 wo, float3 wi) { return lobe_diffuse_pdf(roughness, wo, wi); },
                 [=](float3 wo, float2 u) { return lobe_diffuse_sample(albedo, roughness, wo, u); }};
}

LobeFns translucency_fns(float3 color) {
  return LobeFns{[=](float3 wo, float3 wi) { return lobe_translucency_eval(color, wo, wi); },
                 [=](float3 wo, float3 wi) { return lobe_translucency_pdf(wo, wi); },
                 [=](float3 wo, float2 u) { return lobe_translucency_sample(color, wo, u); }};
}

// 4 roughness values x 5 incident angles = 20 cases, Sidak-corrected together; the bins are
// uniform in theta here (finer near the normal than the fast test's cos-theta bins).
TEST(BasicLobesLong, DiffuseChiSquareGrid) {
  ChiSquareConfig cfg;
  cfg.samples = lobe_test_samples(2000000);
  cfg.theta_bins = 40;
  cfg.phi_bins = 80;
  cfg.bin_in_theta = true;
  cfg.n_cases = int(sizeof(kRoughness) / sizeof(kRoughness[0]) * sizeof(kDiffuseTheta) / sizeof(kDiffuseTheta[0]));
  cfg.seed = 1000;
  for (float r : kRoughness) {
    for (double th : kDiffuseTheta) {
      ++cfg.seed;
      EXPECT_TRUE(chi_square_passes(diffuse_fns(make_float3(0.8f, 0.5f, 0.2f), r), direction_from_theta_deg(th), cfg))
          << "roughness " << r << " theta " << th;
    }
  }
}

TEST(BasicLobesLong, TranslucencyChiSquareGrid) {
  ChiSquareConfig cfg;
  cfg.samples = lobe_test_samples(2000000);
  cfg.theta_bins = 40;
  cfg.phi_bins = 80;
  cfg.bin_in_theta = true;
  cfg.n_cases = int(sizeof(kTranslucencyTheta) / sizeof(kTranslucencyTheta[0]));
  cfg.seed = 2000;
  for (double th : kTranslucencyTheta) {
    ++cfg.seed;
    EXPECT_TRUE(chi_square_passes(translucency_fns(make_float3(0.7f, 0.6f, 0.5f)), direction_from_theta_deg(th), cfg))
        << "theta " << th;
  }
}

TEST(BasicLobesLong, WhiteFurnaces) {
  const size_t n = lobe_test_samples(4000000);
  uint32_t seed = 3000;
  for (float r : {0.0f, 0.1f, 0.25f, 0.5f, 0.75f, 1.0f}) {
    for (double th : kDiffuseTheta) {
      EXPECT_TRUE(white_furnace(diffuse_fns(make_float3(1.0f, 1.0f, 1.0f), r), direction_from_theta_deg(th), n,
                                seed += 2, /*lossless*/ true))
          << "roughness " << r << " theta " << th;
    }
  }
  for (double th : kTranslucencyTheta) {
    EXPECT_TRUE(white_furnace(translucency_fns(make_float3(1.0f, 1.0f, 1.0f)), direction_from_theta_deg(th), n,
                              seed += 2, /*lossless*/ true))
        << "theta " << th;
  }
}

}  // namespace
}  // namespace lobe_test
}  // namespace aw
