// Transmission lobes: rough and smooth refraction (kernels/lobes/refraction.h), thin walls
// (kernels/lobes/thin_walled.h) and fog (kernels/lobes/fog.h).
//
// Conventions under test (stated in the headers):
// - eta = n(far side) / n(side of wo); the frame has wo.z > 0, a transmitted wi has wi.z < 0.
// - The refraction lobe is the transmitted part only (no Fresnel factor) and transports
//   radiance: a smooth interface has the delta weight 1/eta^2, a rough one the albedo
//   <= 1/eta^2. Measured as importance (times eta^2) the smooth albedo is exactly 1 and the
//   rough one <= 1; smooth glass F + (1 - F) (importance albedo) = 1.
// - A path into a slab and back out through the parallel face has the factor 1 and leaves
//   in its original direction; the rough BTDF obeys f(wo -> wi; eta) eta^2 = f(wi -> wo; 1/eta).
//
// The full chi-square grid at >= 1e6 samples per case is in tests/lobes_long.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "kernels/lobes/fog.h"
#include "kernels/lobes/fresnel.h"
#include "kernels/lobes/refraction.h"
#include "kernels/lobes/thin_walled.h"
#include "tests/lobes/lobe_harness.h"
#include "tests/lobes/transmission_cases.h"

namespace aw {
namespace {

using namespace lobe_test;

RefractionParams rough(uint dist, float glossiness, float eta) { return refraction_params(glossiness, dist, eta); }

std::string describe_case(uint dist, float g, float eta, double theta) {
  char b[128];
  std::snprintf(b, sizeof b, "%s glossiness %.2f eta %.4f theta_o %.0f deg", dist_name(dist), double(g), double(eta),
                theta);
  return b;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Chi-square of a lobe through its zoom (zoomed_chi_square_config, tests/lobes/transmission_cases.h).
::testing::AssertionResult zoomed_chi_square(const LobeFns& lobe, float3 wo, size_t samples,
                                             int n_cases, uint32_t seed) {
  return chi_square_passes(lobe_zoomed(lobe, wo), wo, zoomed_chi_square_config(samples, n_cases, seed));
}

// Rough refraction: samples fail at TIR on a microfacet and where refraction about h leaves
// wi above the surface.
::testing::AssertionResult refraction_chi_square(uint dist, float g, float eta, double theta, size_t samples,
                                                 int n_cases, uint32_t seed) {
  RefractionParams p = refraction_params(g, dist, eta);
  return zoomed_chi_square(refraction_fns(p), direction_from_theta_deg(theta), samples, n_cases, seed);
}

// Frosted thin wall: samples fail where the reflection about h goes below the horizon.
::testing::AssertionResult thin_chi_square(float g, double theta, size_t samples, int n_cases, uint32_t seed) {
  return zoomed_chi_square(thin_fns(g), direction_from_theta_deg(theta), samples, n_cases, seed);
}

// ------------------------------------------------------------------------------------------
// Chi-square: a representative subset of the grid (every distribution, roughness, eta and
// incidence appears at least once). The whole grid is in tests/lobes_long.
// ------------------------------------------------------------------------------------------
struct RoughCase {
  uint dist;
  float glossiness;
  float eta;
  double theta;
};

const RoughCase kChiSquareSubset[] = {
    {AW_MF_GGX, 0.3f, kEtaIn, 0.0},       {AW_MF_GGX, 0.6f, kEtaIn, 45.0},     {AW_MF_GGX, 0.9f, kEtaIn, 80.0},
    {AW_MF_GGX, 0.3f, kEtaOut, 45.0},     {AW_MF_GGX, 0.6f, kEtaOut, 80.0},    {AW_MF_GGX, 0.9f, kEtaOut, 0.0},
    {AW_MF_BECKMANN, 0.3f, kEtaIn, 80.0}, {AW_MF_BECKMANN, 0.6f, kEtaIn, 0.0}, {AW_MF_BECKMANN, 0.9f, kEtaIn, 45.0},
    {AW_MF_BECKMANN, 0.3f, kEtaOut, 0.0}, {AW_MF_BECKMANN, 0.6f, kEtaOut, 45.0},
    {AW_MF_BECKMANN, 0.9f, kEtaOut, 80.0},
};

TEST(RefractionRough, ChiSquareSubset) {
  const int n_cases = int(sizeof(kChiSquareSubset) / sizeof(kChiSquareSubset[0]));
  auto t0 = std::chrono::steady_clock::now();
  for (const RoughCase& c : kChiSquareSubset) {
    ::testing::AssertionResult r = refraction_chi_square(c.dist, c.glossiness, c.eta, c.theta,
                                                         lobe_test_samples(1000000), n_cases,
                                                         11u + uint32_t(&c - kChiSquareSubset));
    EXPECT_TRUE(r) << describe_case(c.dist, c.glossiness, c.eta, c.theta);
    if (r) std::printf("[ info     ] %s: %s\n", describe_case(c.dist, c.glossiness, c.eta, c.theta).c_str(), r.message());
  }
  std::printf("[ info     ] %d rough refraction chi-square cases at %zu samples: %.1f s\n", n_cases,
              lobe_test_samples(1000000), seconds_since(t0));
}

// The chi-square test must be able to fail: a sampler that forgets the Jacobian's effect
// (refracting about the normal-sampled h with a pdf that omits |dh/dwi|) is rejected.
TEST(RefractionRough, ChiSquareRejectsAPdfWithoutTheJacobian) {
  RefractionParams p = rough(AW_MF_GGX, 0.4f, kEtaIn);
  LobeFns broken = refraction_fns(p);
  broken.pdf = [=](float3 wo, float3 wi) {
    float3 h;
    if (!(wo.z > 0.0f) || !(wi.z < 0.0f) || !refraction_half_vector(wo, wi, p.eta, &h)) return 0.0f;
    return mf_pdf_visible(p.mf, wo, h);  // density of h, not of wi
  };
  ChiSquareConfig cfg;
  cfg.samples = 20000;
  cfg.expect_unit_mass = false;
  ChiSquareResult r = run_chi_square(broken, direction_from_theta_deg(30.0), cfg);
  EXPECT_FALSE(r.passed) << r.message;
}

// ------------------------------------------------------------------------------------------
// eval / pdf / sample consistency, finiteness at the extremes.
// ------------------------------------------------------------------------------------------
TEST(RefractionRough, SampleWeightAndPdfMatchEvalAndPdf) {
  const uint dists[] = {AW_MF_GGX, AW_MF_BECKMANN};
  const float glossinesses[] = {0.0f, 0.3f, 0.6f, 0.9f, 0.968f};  // alpha 1 ... ~1e-3
  const float etas[] = {kEtaIn, kEtaOut, 1.0011f, 2.4f};
  const double thetas[] = {0.0, 45.0, 80.0, 89.5};
  for (uint d : dists)
    for (float g : glossinesses)
      for (float eta : etas)
        for (double th : thetas) {
          EXPECT_TRUE(sample_matches_eval_pdf(refraction_fns(rough(d, g, eta)), direction_from_theta_deg(th), 2000,
                                              17u, 1e-4, 1e-6))
              << describe_case(d, g, eta, th);
        }
}

TEST(RefractionRough, AnisotropicSampleMatchesEvalAndPdf) {
  RefractionParams p;
  p.mf.ax = 0.05f;
  p.mf.ay = 0.6f;
  p.eta = kEtaIn;
  for (uint d : {AW_MF_GGX, AW_MF_BECKMANN}) {
    p.mf.dist = d;
    EXPECT_TRUE(sample_matches_eval_pdf(refraction_fns(p), direction_from_theta_deg(50.0, 20.0), 5000, 5u));
    ChiSquareConfig cfg;
    cfg.samples = lobe_test_samples(1000000);
    cfg.n_cases = 2;
    cfg.expect_unit_mass = false;
    EXPECT_TRUE(chi_square_passes(refraction_fns(p), direction_from_theta_deg(50.0, 20.0), cfg)) << dist_name(d);
  }
}

TEST(Refraction, FiniteAtExtremes) {
  std::vector<RefractionParams> ps;
  for (uint d : {AW_MF_GGX, AW_MF_BECKMANN}) {
    for (float eta : {1.0f, 1.0005f, 0.9995f, 1.0011f, kEtaIn, kEtaOut, 3.0f, 1.0f / 3.0f}) {
      for (float a : {1e-4f, AW_MF_MIRROR_ALPHA, 0.01f, 0.3f, 1.0f}) {
        RefractionParams p;
        p.mf.ax = a;
        p.mf.ay = a;
        p.mf.dist = d;
        p.eta = eta;
        ps.push_back(p);
      }
      RefractionParams p;  // the widest anisotropic stretch of alpha = 1
      p.mf.ax = 3.16f;
      p.mf.ay = 1e-4f;
      p.mf.dist = d;
      p.eta = eta;
      ps.push_back(p);
      ps.push_back(refraction_params(0.0f, d, eta));
      ps.push_back(refraction_params(1.0f, d, eta));
    }
  }
  for (const RefractionParams& p : ps) {
    EXPECT_TRUE(eval_pdf_sample_finite(refraction_fns(p), 2000, 21u))
        << dist_name(p.mf.dist) << " ax " << p.mf.ax << " ay " << p.mf.ay << " eta " << p.eta;
  }
}

TEST(Refraction, DeltaAndPassThroughHaveNoDensity) {
  // Glossiness 1 (alpha 1e-4 < AW_MF_MIRROR_ALPHA) is a delta lobe: eval and pdf are 0.
  RefractionParams p = refraction_params(1.0f, AW_MF_GGX, kEtaIn);
  EXPECT_TRUE(refraction_is_delta(p));
  float3 wo = direction_from_theta_deg(30.0);
  LobeSample s = lobe_refraction_sample(p, wo, make_float2(0.3f, 0.7f));
  ASSERT_NE(s.flags, 0u);
  EXPECT_EQ(s.flags, AW_LOBE_SPECULAR | AW_LOBE_TRANSMISSION);
  EXPECT_EQ(lobe_refraction_eval(p, wo, s.wi).x, 0.0f);
  EXPECT_EQ(lobe_refraction_pdf(p, wo, s.wi), 0.0f);
  EXPECT_FALSE(refraction_is_delta(refraction_params(0.968f, AW_MF_GGX, kEtaIn)));  // alpha 1.02e-3
}

// ------------------------------------------------------------------------------------------
// Energy.
// ------------------------------------------------------------------------------------------

// Rough refraction measured as importance loses energy (single scattering, TIR at facets)
// but never creates it: both estimators (sampling, and uniform-sphere integration of eval
// that does not use sample() or pdf()) <= 1, and they agree with each other.
TEST(RefractionRough, WhiteFurnaceImportanceAtMostOne) {
  auto t0 = std::chrono::steady_clock::now();
  for (uint d : {AW_MF_GGX, AW_MF_BECKMANN})
    for (float g : {0.0f, 0.3f, 0.6f})
      for (float eta : {kEtaIn, kEtaOut})
        for (double th : {0.0, 45.0, 80.0}) {
          RefractionParams p = rough(d, g, eta);
          float3 wo = direction_from_theta_deg(th);
          LobeFns imp = refraction_importance_fns(p);
          EXPECT_TRUE(white_furnace(imp, wo, 100000, 31u, /*lossless*/ false)) << describe_case(d, g, eta, th);
          // Radiance: <= 1/eta^2 (the radiance scale of the smooth interface).
          AlbedoEstimate rad = albedo_by_sampling(refraction_fns(p), wo, 100000, 33u);
          EXPECT_TRUE(albedo_at_most(rad, 1.0 / (double(eta) * double(eta)))) << describe_case(d, g, eta, th);
          // The two estimators of the importance albedo agree (sampling vs eval alone).
          AlbedoEstimate by_s = albedo_by_sampling(imp, wo, 100000, 35u);
          AlbedoEstimate by_u = albedo_by_uniform_sphere(imp, wo, 400000, 37u);
          double tol = 4.0 * std::sqrt(by_s.stderr_[0] * by_s.stderr_[0] + by_u.stderr_[0] * by_u.stderr_[0]) + 1e-4;
          EXPECT_NEAR(by_s.mean[0], by_u.mean[0], tol)
              << describe_case(d, g, eta, th) << ": " << describe(by_s) << " vs " << describe(by_u);
        }
  std::printf("[ info     ] rough furnace: %.1f s\n", seconds_since(t0));
}

// Near-smooth rough glass entering at normal incidence is nearly lossless in importance: the
// rough model converges to the smooth one.
TEST(RefractionRough, NearlySmoothIsNearlyLossless) {
  for (uint d : {AW_MF_GGX, AW_MF_BECKMANN}) {
    RefractionParams p = rough(d, 0.95f, kEtaIn);  // alpha 2.5e-3
    AlbedoEstimate a = albedo_by_sampling(refraction_importance_fns(p), direction_from_theta_deg(0.0), 20000, 41u);
    EXPECT_GT(a.mean[0], 0.999) << dist_name(d) << ": " << describe(a);
    EXPECT_LE(a.mean[0], 1.0 + 1e-6) << dist_name(d) << ": " << describe(a);
  }
}

// Smooth: the delta weight is exactly the radiance scale 1/eta^2; as importance it is 1; and
// smooth glass is lossless: F + (1 - F) * (importance albedo) = 1 at every angle.
TEST(RefractionSmooth, WeightIsRadianceScaleAndGlassIsLossless) {
  int checked = 0;
  for (float eta : {kEtaIn, kEtaOut, 1.33f, 1.0f / 1.33f, 2.4f, 1.0011f}) {
    RefractionParams p = refraction_params(1.0f, AW_MF_GGX, eta);
    for (int i = 1; i <= 2000; ++i) {
      float c = float(i) / 2000.0f;
      float3 wo = direction_from_cos_phi(c, 0.3 + i);
      LobeSample s = lobe_refraction_sample(p, wo, make_float2(0.5f, 0.5f));
      float F = fresnel_dielectric(wo.z, eta);
      float importance = s.flags ? s.weight.x * eta * eta : 0.0f;
      if (s.flags) {
        EXPECT_EQ(s.weight.x, refraction_radiance_scale(eta));
        EXPECT_EQ(s.flags, AW_LOBE_SPECULAR | AW_LOBE_TRANSMISSION);
        EXPECT_NEAR(importance, 1.0f, 2e-7f);
        // Snell: sin_t = sin_i / eta, same azimuth, opposite side.
        float sin_i = std::sqrt(wo.x * wo.x + wo.y * wo.y);
        float sin_t = std::sqrt(s.wi.x * s.wi.x + s.wi.y * s.wi.y);
        EXPECT_NEAR(sin_t, sin_i / eta, 2e-6f) << "cos_i " << c << " eta " << eta;
        EXPECT_LT(s.wi.z, 0.0f);
        if (sin_i > 1e-3f) {
          EXPECT_GT(-(s.wi.x * wo.x + s.wi.y * wo.y), 0.0f);  // continues forward
        }
        ++checked;
      }
      // The sample fails exactly where Fresnel reports total internal reflection.
      EXPECT_EQ(s.flags == 0u, F == 1.0f) << "cos_i " << c << " eta " << eta << " F " << F;
      EXPECT_NEAR(F + (1.0f - F) * importance, 1.0f, 1e-6f) << "cos_i " << c << " eta " << eta;
    }
  }
  EXPECT_GT(checked, 8000);
}

// The TIR boundary is where refraction_cos_t and fresnel_dielectric must agree bit for bit:
// sweep every float cos_i around the critical angle of glass -> air.
TEST(RefractionSmooth, TotalInternalReflectionAgreesWithFresnel) {
  const float eta = kEtaOut;
  const float c_crit = std::sqrt(1.0f - eta * eta);  // ~0.745
  float c = c_crit;
  for (int k = 0; k < 200; ++k) c = std::nextafter(c, 0.0f);
  int fails = 0, passes = 0;
  for (int k = 0; k < 400; ++k, c = std::nextafter(c, 1.0f)) {
    float F = fresnel_dielectric(c, eta);
    bool tir = refraction_cos_t(c, eta) < 0.0f;
    EXPECT_EQ(tir, F == 1.0f) << "cos_i " << c;
    (tir ? fails : passes)++;
  }
  EXPECT_GT(fails, 0);
  EXPECT_GT(passes, 0);
  // Well beyond the critical angle (60 deg > 41.8 deg): the smooth sample fails, F = 1.
  RefractionParams p = refraction_params(1.0f, AW_MF_GGX, eta);
  float3 wo = direction_from_theta_deg(60.0);
  LobeSample s = lobe_refraction_sample(p, wo, make_float2(0.5f, 0.5f));
  EXPECT_EQ(s.flags, 0u);
  EXPECT_EQ(s.pdf, 0.0f);
  EXPECT_EQ(s.weight.x, 0.0f);
  EXPECT_EQ(fresnel_dielectric(wo.z, eta), 1.0f);
  float3 wt;
  EXPECT_EQ(refract_dir(wo, make_float3(0.0f, 0.0f, 1.0f), eta, &wt), 0);
  EXPECT_LT(refraction_cos_t(wo.z, eta), 0.0f);
  // Rough glass -> air beyond the critical angle loses most samples but stays <= 1.
  AlbedoEstimate a = albedo_by_sampling(refraction_importance_fns(rough(AW_MF_GGX, 0.6f, eta)), wo, 50000, 43u);
  EXPECT_TRUE(albedo_at_most(a));
}

// Radiance scaling, path form: camera ray into a glass slab through the top face, out through
// the parallel bottom face. At the bottom the caller's frame has +z pointing back inside (the
// side of wo' = -wi) and eta' = 1/eta. The ray must leave parallel to how it came (-wo) and
// the two weights must multiply to 1.
TEST(RefractionSmooth, PathInAndBackOutHasFactorOne) {
  for (float eta : {kEtaIn, 1.33f, 2.4f, 1.0011f, 1.0f}) {
    RefractionParams in = refraction_params(1.0f, AW_MF_GGX, eta);
    RefractionParams out = refraction_params(1.0f, AW_MF_GGX, 1.0f / eta);
    for (double th : {0.0, 10.0, 30.0, 60.0, 80.0, 89.0}) {
      float3 wo = direction_from_theta_deg(th, 57.0);
      LobeSample a = lobe_refraction_sample(in, wo, make_float2(0.1f, 0.2f));
      ASSERT_NE(a.flags, 0u);
      LobeSample b = lobe_refraction_sample(out, -a.wi, make_float2(0.3f, 0.4f));
      ASSERT_NE(b.flags, 0u) << "eta " << eta << " theta " << th;
      EXPECT_NEAR(a.weight.x * b.weight.x, 1.0f, 3e-7f) << "eta " << eta << " theta " << th;
      // Leaving at grazing angles, eta'^2 cos_t^2 = eta'^2 - 1 + cos^2 cancels (both terms
      // ~0.55 for glass at 89 deg), so the direction carries ~1e-6 absolute error there.
      EXPECT_NEAR(b.wi.x, -wo.x, 1e-5f);
      EXPECT_NEAR(b.wi.y, -wo.y, 1e-5f);
      EXPECT_NEAR(b.wi.z, -wo.z, 1e-5f);
    }
  }
}

// Radiance scaling, rough form (generalised reciprocity, Veach 1997 Sec. 5.2): swapping the
// roles of wo and wi across the same interface (frame flipped to keep wo.z > 0, eta -> 1/eta)
// multiplies the BTDF by eta^2: f(wo -> wi; eta) eta^2 = f(wi -> wo; 1/eta).
TEST(RefractionRough, GeneralisedReciprocity) {
  Uniform uni(47u);
  int nonzero = 0;
  double worst = 0.0;
  for (uint d : {AW_MF_GGX, AW_MF_BECKMANN}) {
    for (float eta : {kEtaIn, kEtaOut, 2.4f}) {
      RefractionParams p = rough(d, 0.4f, eta);
      p.mf.ay = 0.5f * p.mf.ax;  // anisotropic too
      RefractionParams q = p;
      q.eta = 1.0f / eta;
      for (int i = 0; i < 5000; ++i) {
        float2 a = uni.next2(), b = uni.next2();
        float3 wo = direction_from_cos_phi(0.02 + 0.98 * a.x, 6.283185307179586 * a.y);
        float3 wi = direction_from_cos_phi(-(0.02 + 0.98 * b.x), 6.283185307179586 * b.y);
        float3 wo2 = make_float3(wi.x, wi.y, -wi.z);  // the old wi, frame flipped
        float3 wi2 = make_float3(wo.x, wo.y, -wo.z);
        // Skip ill-conditioned pairs where wi or wo is nearly tangent to the microfacet h:
        // the factors |wi.h|, |wo.h| then cancel to a few significant digits in float.
        float3 hv = make_float3(-(wo.x + eta * wi.x), -(wo.y + eta * wi.y), -(wo.z + eta * wi.z));
        hv = hv / length(hv);
        if (std::min(std::fabs(dot(wo, hv)), std::fabs(dot(wi, hv))) < 0.02f) continue;
        double f1 = double(lobe_refraction_eval(p, wo, wi).x) / std::fabs(wi.z);
        double f2 = double(lobe_refraction_eval(q, wo2, wi2).x) / std::fabs(wi2.z);
        double lhs = f1 * double(eta) * double(eta);
        if (lhs > 0.0 || f2 > 0.0) ++nonzero;
        double rel = relative_difference(lhs, f2, 1e-6);
        worst = std::max(worst, rel);
        EXPECT_LT(rel, 2e-4) << dist_name(d) << " eta " << eta << " wo " << fmt3(wo) << " wi " << fmt3(wi) << ": "
                             << lhs << " vs " << f2;
      }
    }
  }
  EXPECT_GT(nonzero, 5000);
  std::printf("[ info     ] generalised reciprocity: worst relative difference %.3g\n", worst);
}

// ------------------------------------------------------------------------------------------
// IOR 1: pass-through, whatever the glossiness.
// ------------------------------------------------------------------------------------------
TEST(Refraction, IorOneIsExactPassThrough) {
  for (float eta : {1.0f, 1.0009f, 0.9991f, std::nextafter(1.0f, 2.0f), std::nextafter(1.0f, 0.0f)}) {
    for (uint d : {AW_MF_GGX, AW_MF_BECKMANN}) {
      for (float g : {0.0f, 0.3f, 0.7f, 1.0f}) {
        RefractionParams p = refraction_params(g, d, eta);
        EXPECT_TRUE(refraction_is_delta(p));
        for (double th : {0.0, 33.0, 80.0, 89.99}) {
          float3 wo = direction_from_theta_deg(th, 123.0);
          LobeSample s = lobe_refraction_sample(p, wo, make_float2(0.77f, 0.12f));
          ASSERT_EQ(s.flags, AW_LOBE_SPECULAR | AW_LOBE_TRANSMISSION) << "eta " << eta << " g " << g;
          EXPECT_EQ(s.wi.x, -wo.x);
          EXPECT_EQ(s.wi.y, -wo.y);
          EXPECT_EQ(s.wi.z, -wo.z);
          EXPECT_EQ(s.weight.x, 1.0f);
          EXPECT_EQ(s.weight.y, 1.0f);
          EXPECT_EQ(s.weight.z, 1.0f);
          EXPECT_EQ(lobe_refraction_eval(p, wo, -wo).x, 0.0f);
          EXPECT_EQ(lobe_refraction_pdf(p, wo, -wo), 0.0f);
        }
      }
    }
  }
  // Just outside the band the interface refracts (and a rough one is glossy).
  EXPECT_FALSE(refraction_is_pass_through(1.0011f));
  EXPECT_FALSE(refraction_is_delta(refraction_params(0.5f, AW_MF_GGX, 1.0011f)));
  // refract_dir with eta exactly 1 returns -wo bit for bit.
  float3 wo = direction_from_theta_deg(71.0, 5.0), wt;
  ASSERT_EQ(refract_dir(wo, make_float3(0.0f, 0.0f, 1.0f), 1.0f, &wt), 1);
  EXPECT_EQ(wt.x, -wo.x);
  EXPECT_EQ(wt.y, -wo.y);
  EXPECT_EQ(wt.z, -wo.z);
}

TEST(Refraction, RefractDirIsRobustAtGrazing) {
  for (float eta : {kEtaIn, 1.0011f, 3.0f}) {
    for (float z : {0.0f, 1e-30f, 1e-12f, 1e-7f, 1e-3f}) {
      float3 wo = make_float3(std::sqrt(1.0f - z * z), 0.0f, z);
      float3 wt;
      ASSERT_EQ(refract_dir(wo, make_float3(0.0f, 0.0f, 1.0f), eta, &wt), 1) << "eta " << eta << " z " << z;
      EXPECT_TRUE(finite3(wt));
      EXPECT_NEAR(length(wt), 1.0f, 1e-6f);
      EXPECT_LT(wt.z, 0.0f);
      // sin_t = 1/eta at grazing incidence: cos_t = sqrt(1 - 1/eta^2).
      EXPECT_NEAR(-wt.z, std::sqrt(1.0f - 1.0f / (eta * eta)), 2e-3f);
    }
  }
  EXPECT_EQ(refraction_cos_t(1.0f, kEtaIn), 1.0f);
  EXPECT_EQ(refraction_cos_t(0.0f, kEtaOut), -1.0f);
  EXPECT_EQ(refraction_cos_t(0.5f, 0.0f), -1.0f);
  EXPECT_EQ(refraction_cos_t(0.5f, std::nanf("")), -1.0f);
}

// ------------------------------------------------------------------------------------------
// Thin walls.
// ------------------------------------------------------------------------------------------
TEST(ThinWalled, ReflectanceAndTransmittanceConserveEnergy) {
  for (int i = 0; i <= 10000; ++i) {
    float R = float(i) / 10000.0f;
    float Rp = thin_wall_reflectance(R);
    float Tp = thin_wall_transmittance(R);
    EXPECT_NEAR(Rp + Tp, 1.0f, 2e-7f) << "R " << R;
    EXPECT_GE(Rp, R) << "R " << R;
    EXPECT_GE(Tp, 0.0f);
    EXPECT_LE(Rp, 1.0f);
    if (R < 0.999f) {
      // The series forms of docs/material.md §3.6 (computed in double), no absorption.
      double T = 1.0 - double(R);
      double rs = double(R) + T * T * double(R) / (1.0 - double(R) * double(R));
      double ts = T * T / (1.0 - double(R) * double(R));
      EXPECT_NEAR(double(Rp), rs, 1e-6 * std::max(1.0, rs)) << "R " << R;
      EXPECT_NEAR(double(Tp), ts, 1e-6) << "R " << R;
    }
  }
  EXPECT_EQ(thin_wall_reflectance(0.0f), 0.0f);
  EXPECT_EQ(thin_wall_transmittance(0.0f), 1.0f);
  EXPECT_EQ(thin_wall_reflectance(1.0f), 1.0f);
  EXPECT_EQ(thin_wall_transmittance(1.0f), 0.0f);
  // A glass pane at normal incidence: R = 0.04 -> R' = 0.0769..., T' = 0.923...
  float R = fresnel_dielectric(1.0f, kEtaIn);
  EXPECT_NEAR(thin_wall_reflectance(R), 2.0 * 0.04 / 1.04, 1e-6);
}

TEST(ThinWalled, ClearIsStraightThrough) {
  for (float g : {1.0f, 0.99f, 0.9685f}) {  // alpha 1e-4, 1e-4, 9.9e-4: all delta
    ASSERT_TRUE(thin_wall_is_delta(g)) << g;
    for (double th : {0.0, 45.0, 89.9}) {
      float3 wo = direction_from_theta_deg(th, 200.0);
      LobeSample s = lobe_thin_transmission_sample(g, wo, make_float2(0.4f, 0.9f));
      ASSERT_EQ(s.flags, AW_LOBE_SPECULAR | AW_LOBE_TRANSMISSION);
      EXPECT_EQ(s.wi.x, -wo.x);
      EXPECT_EQ(s.wi.y, -wo.y);
      EXPECT_EQ(s.wi.z, -wo.z);
      EXPECT_EQ(s.weight.x, 1.0f);
      EXPECT_EQ(lobe_thin_transmission_eval(g, wo, -wo).x, 0.0f);
      EXPECT_EQ(lobe_thin_transmission_pdf(g, wo, -wo), 0.0f);
    }
  }
  EXPECT_FALSE(thin_wall_is_delta(0.968f));
}

TEST(ThinWalled, FrostedChiSquareConsistencyFurnace) {
  const float gs[] = {0.3f, 0.6f, 0.9f};
  const double ths[] = {0.0, 45.0, 80.0};
  // Representative subset for chi-square (the full 3 x 3 grid is in tests/lobes_long).
  const std::pair<float, double> chi[] = {{0.3f, 80.0}, {0.6f, 0.0}, {0.9f, 45.0}};
  for (const auto& c : chi) {
    ::testing::AssertionResult r = thin_chi_square(c.first, c.second, lobe_test_samples(1000000), 3, 81u);
    EXPECT_TRUE(r) << "glossiness " << c.first << " theta " << c.second;
    if (r) std::printf("[ info     ] thin wall glossiness %.1f theta_o %.0f: %s\n", double(c.first), c.second, r.message());
  }
  for (float g : gs) {
    for (double th : ths) {
      float3 wo = direction_from_theta_deg(th);
      EXPECT_TRUE(sample_matches_eval_pdf(thin_fns(g), wo, 5000, 51u)) << g << " " << th;
      EXPECT_TRUE(white_furnace(thin_fns(g), wo, 100000, 53u, false)) << g << " " << th;
    }
    EXPECT_TRUE(eval_pdf_sample_finite(thin_fns(g), 2000, 55u)) << g;
  }
  for (float g : {0.0f, 1.0f, 0.968f}) EXPECT_TRUE(eval_pdf_sample_finite(thin_fns(g), 2000, 57u)) << g;
}

// The frosted blur is centred on the straight-through direction: its mean direction is close
// to -wo, tighter for higher glossiness; and f is symmetric under wo <-> flip(wi)
// (a reflection lobe mirrored through the plane is reciprocal).
TEST(ThinWalled, FrostedIsCentredOnStraightThroughAndReciprocal) {
  float3 wo = direction_from_theta_deg(30.0, 40.0);
  double prev_spread = 1e9;
  for (float g : {0.3f, 0.6f, 0.9f}) {
    Uniform uni(61u);
    double sum_dot = 0.0;
    int n = 0;
    for (int i = 0; i < 20000; ++i) {
      LobeSample s = lobe_thin_transmission_sample(g, wo, uni.next2());
      if (!s.flags) continue;
      sum_dot += double(dot(s.wi, -wo));
      ++n;
    }
    double spread = 1.0 - sum_dot / n;
    EXPECT_LT(spread, prev_spread) << g;
    prev_spread = spread;
  }
  EXPECT_LT(prev_spread, 5e-3);  // GGX's long tail dominates this mean, even at alpha 0.01
  Uniform uni(63u);
  for (int i = 0; i < 5000; ++i) {
    float2 a = uni.next2(), b = uni.next2();
    float3 o = direction_from_cos_phi(0.05 + 0.95 * a.x, 6.283185307179586 * a.y);
    float3 w = direction_from_cos_phi(-(0.05 + 0.95 * b.x), 6.283185307179586 * b.y);
    double f1 = lobe_thin_transmission_eval(0.5f, o, w).x / std::fabs(w.z);
    double f2 = lobe_thin_transmission_eval(0.5f, thin_wall_flip(w), thin_wall_flip(o)).x / std::fabs(o.z);
    EXPECT_LT(relative_difference(f1, f2, 1e-6), 1e-4) << fmt3(o) << " " << fmt3(w);
  }
}

// ------------------------------------------------------------------------------------------
// Fog.
// ------------------------------------------------------------------------------------------
TEST(Fog, EndColorClosedForm) {
  // "Fog with end colour C at distance D transmits C^(d/D)" (docs/material.md §3.7).
  const float3 C = make_float3(0.8f, 0.3f, 0.05f);
  const float D = 2.5f;
  for (float d : {0.0f, 0.1f, 1.0f, 2.5f, 5.0f, 12.5f, 100.0f}) {
    float3 t = fog_transmittance(C, D, 1, d);
    const float c[3] = {C.x, C.y, C.z};
    const float tv[3] = {t.x, t.y, t.z};
    for (int k = 0; k < 3; ++k) {
      double expect = std::pow(double(c[k]), double(d) / double(D));
      EXPECT_NEAR(double(tv[k]), expect, 2e-6 * std::max(expect, 1e-30) + 1e-30) << "d " << d << " channel " << k;
    }
  }
  float3 at_d = fog_transmittance(C, D, 1, D);
  EXPECT_NEAR(at_d.x, C.x, 1e-7f);
  EXPECT_NEAR(at_d.y, C.y, 1e-7f);
  EXPECT_NEAR(at_d.z, C.z, 1e-7f);
  float3 at_0 = fog_transmittance(C, D, 1, 0.0f);
  EXPECT_EQ(at_0.x, 1.0f);
  EXPECT_EQ(at_0.y, 1.0f);
  EXPECT_EQ(at_0.z, 1.0f);
  // Beer–Lambert is memoryless: two segments equal one of the summed length.
  float3 a = fog_transmittance(C, D, 1, 0.7f), b = fog_transmittance(C, D, 1, 1.9f);
  float3 ab = fog_transmittance(C, D, 1, 2.6f);
  EXPECT_NEAR(a.y * b.y, ab.y, 1e-6f);
  // A black channel is opaque for any d > 0, a white one clear; both clear at d = 0.
  float3 k = fog_transmittance(make_float3(0.0f, 1.0f, 0.5f), D, 1, 1e-6f);
  EXPECT_EQ(k.x, 0.0f);
  EXPECT_EQ(k.y, 1.0f);
  float3 k0 = fog_transmittance(make_float3(0.0f, 1.0f, 0.5f), D, 1, 0.0f);
  EXPECT_EQ(k0.x, 1.0f);
}

TEST(Fog, FadeToBlackIsMonotonicAndStopsAtDistance) {
  const float D = 3.0f;
  float prev = 2.0f;
  for (int i = 0; i <= 4000; ++i) {
    float d = float(i) * (2.0f * D / 4000.0f);
    float3 t = fog_transmittance(make_float3(0.2f, 0.5f, 0.9f), D, 0, d);  // end colour unused
    EXPECT_EQ(t.x, t.y);
    EXPECT_EQ(t.x, t.z);
    EXPECT_LE(t.x, prev) << "d " << d;
    EXPECT_GE(t.x, 0.0f);
    if (d >= D) {
      EXPECT_EQ(t.x, 0.0f) << "d " << d;
    } else {
      EXPECT_GT(t.x, 0.0f) << "d " << d;
    }
    prev = t.x;
  }
  EXPECT_EQ(fog_transmittance(make_float3(0, 0, 0), D, 0, 0.0f).x, 1.0f);
  // Just before the distance the segment has faded to AW_FOG_BLACK_LEVEL (black).
  EXPECT_NEAR(fog_transmittance(make_float3(0, 0, 0), D, 0, std::nextafter(D, 0.0f)).x, AW_FOG_BLACK_LEVEL, 1e-8f);
  // Half way: exp(-ln(1000)/2) = 1/sqrt(1000).
  EXPECT_NEAR(fog_transmittance(make_float3(0, 0, 0), D, 0, 0.5f * D).x, 1.0 / std::sqrt(1000.0), 1e-7);
}

TEST(Fog, DisabledAndExtremeInputsAreFinite) {
  const float3 cs[] = {make_float3(0, 0, 0), make_float3(1, 1, 1), make_float3(0.5f, 1e-30f, 0.999999f),
                       make_float3(2.0f, -1.0f, 0.5f)};
  const float Ds[] = {-1.0f, 0.0f, 1e-38f, 1e-30f, 1e-6f, 1.0f, 1e30f, std::nanf("")};
  const float ds[] = {0.0f, 1e-38f, 1e-6f, 1.0f, 1e6f, 1e38f, std::numeric_limits<float>::infinity()};
  for (float3 c : cs)
    for (float D : Ds)
      for (int use : {0, 1})
        for (float d : ds) {
          float3 t = fog_transmittance(c, D, use, d);
          EXPECT_TRUE(finite3(t)) << fmt3(c) << " D " << D << " d " << d;
          EXPECT_GE(t.x, 0.0f);
          EXPECT_LE(t.x, 1.0f);
          EXPECT_GE(t.y, 0.0f);
          EXPECT_LE(t.y, 1.0f);
          EXPECT_LE(t.z, 1.0f);
          if (!(D > 0.0f) || d == 0.0f) {
            EXPECT_EQ(t.x, 1.0f);  // fog disabled (distance <= 0) or nothing travelled
            EXPECT_EQ(t.y, 1.0f);
            EXPECT_EQ(t.z, 1.0f);
          }
        }
}

// ------------------------------------------------------------------------------------------
// Host vs device: the same headers compiled as OpenCL C on the device and as C++ here, on
// fixed inputs (every output: eval, pdf, sampled direction, weight, sample pdf, flags, cos_t,
// radiance scale; R', T'; fog). Tolerance: kHostDeviceRelTol (1e-5 relative, floor 1e-6) from
// the harness. Measured on PoCL 3.1 (CPU): max relative difference 1.1e-6 (refraction),
// 1.3e-6 (thin walls), 8.4e-8 (fog), from the device's own sqrt/pow/exp/log and divisions;
// the test prints the maxima.
// ------------------------------------------------------------------------------------------
TEST(TransmissionDevice, RefractionMatchesHost) {
  std::vector<float> in;
  Uniform uni(71u);
  for (uint d : {AW_MF_GGX, AW_MF_BECKMANN})
    for (float a : {1e-4f, 0.01f, 0.09f, 0.49f, 1.0f})
      for (float eta : {kEtaIn, kEtaOut, 1.0f, 1.0005f, 1.33f})
        for (double th : {0.0, 45.0, 80.0}) {
          for (int j = 0; j < 4; ++j) {
            float3 wo = direction_from_theta_deg(th, 17.0 + 50.0 * j);
            float2 u = uni.next2();
            RefractionParams p;
            p.mf.ax = a;
            p.mf.ay = j == 3 ? 0.5f * a : a;
            p.mf.dist = d;
            p.eta = eta;
            // wi: a direction the lobe samples (in its support), or a random lower one.
            LobeSample s = lobe_refraction_sample(p, wo, uni.next2());
            float3 wi = (s.flags && (j & 1)) ? s.wi : uniform_sphere(uni.next2());
            if (wi.z > 0.0f) wi.z = -wi.z;
            const float v[12] = {p.mf.ax, p.mf.ay, float(d), eta, wo.x, wo.y, wo.z, wi.x, wi.y, wi.z, u.x, u.y};
            in.insert(in.end(), v, v + 12);
          }
        }
  const size_t n = in.size() / 12;
  std::vector<float> host(n * 10);
  for (size_t i = 0; i < n; ++i) {
    const float* a = &in[i * 12];
    RefractionParams p;
    p.mf.ax = a[0];
    p.mf.ay = a[1];
    p.mf.dist = uint(a[2]);
    p.eta = a[3];
    float3 wo = make_float3(a[4], a[5], a[6]), wi = make_float3(a[7], a[8], a[9]);
    LobeSample s = lobe_refraction_sample(p, wo, make_float2(a[10], a[11]));
    const float o[10] = {lobe_refraction_eval(p, wo, wi).x, lobe_refraction_pdf(p, wo, wi), s.wi.x, s.wi.y, s.wi.z,
                         s.weight.x, s.pdf, float(s.flags), refraction_cos_t(wo.z, p.eta),
                         refraction_radiance_scale(p.eta)};
    std::memcpy(&host[i * 10], o, sizeof o);
  }
  std::vector<float> dev = run_device_probe("tests/probe_transmission.cl", "probe_refraction", in, 10, n);
  size_t nonzero_eval = 0;
  for (size_t i = 0; i < n; ++i) nonzero_eval += host[i * 10] > 0.0f;
  EXPECT_GT(nonzero_eval, n / 5);  // many inputs are delta or pass-through (eval 0)
  ::testing::AssertionResult r = host_matches_device(host, dev, kHostDeviceRelTol, kHostDeviceAbsFloor, "refraction");
  std::printf("[ info     ] %s\n", r.message());
  EXPECT_TRUE(r);
}

TEST(TransmissionDevice, ThinWalledAndFogMatchHost) {
  std::vector<float> in;
  Uniform uni(73u);
  for (float g : {0.0f, 0.3f, 0.6f, 0.9f, 1.0f})
    for (double th : {0.0, 45.0, 80.0})
      for (int j = 0; j < 4; ++j) {
        float3 wo = direction_from_theta_deg(th, 10.0 + 70.0 * j);
        LobeSample s = lobe_thin_transmission_sample(g, wo, uni.next2());
        float3 wi = (s.flags && (j & 1)) ? s.wi : uniform_sphere(uni.next2());
        if (wi.z > 0.0f) wi.z = -wi.z;
        float2 u = uni.next2();
        float R = fresnel_dielectric(wo.z, kEtaIn);
        const float v[10] = {g, wo.x, wo.y, wo.z, wi.x, wi.y, wi.z, u.x, u.y, R};
        in.insert(in.end(), v, v + 10);
      }
  const size_t n = in.size() / 10;
  std::vector<float> host(n * 10);
  for (size_t i = 0; i < n; ++i) {
    const float* a = &in[i * 10];
    float3 wo = make_float3(a[1], a[2], a[3]), wi = make_float3(a[4], a[5], a[6]);
    LobeSample s = lobe_thin_transmission_sample(a[0], wo, make_float2(a[7], a[8]));
    const float o[10] = {lobe_thin_transmission_eval(a[0], wo, wi).x, lobe_thin_transmission_pdf(a[0], wo, wi),
                         s.wi.x, s.wi.y, s.wi.z, s.weight.x, s.pdf, float(s.flags), thin_wall_reflectance(a[9]),
                         thin_wall_transmittance(a[9])};
    std::memcpy(&host[i * 10], o, sizeof o);
  }
  std::vector<float> dev = run_device_probe("tests/probe_transmission.cl", "probe_thin_walled", in, 10, n);
  ::testing::AssertionResult r = host_matches_device(host, dev, kHostDeviceRelTol, kHostDeviceAbsFloor, "thin walled");
  std::printf("[ info     ] %s\n", r.message());
  EXPECT_TRUE(r);

  std::vector<float> fin;
  for (int use : {0, 1})
    for (float D : {-1.0f, 0.0f, 1e-30f, 0.5f, 2.0f, 1e4f})
      for (float d : {0.0f, 0.01f, 0.3f, 1.0f, 1.99f, 2.0f, 7.0f, 1e6f}) {
        const float v[6] = {0.9f, 0.25f, 0.0f, D, float(use), d};
        fin.insert(fin.end(), v, v + 6);
      }
  const size_t nf = fin.size() / 6;
  std::vector<float> fhost(nf * 3);
  for (size_t i = 0; i < nf; ++i) {
    const float* a = &fin[i * 6];
    float3 t = fog_transmittance(make_float3(a[0], a[1], a[2]), a[3], a[4] != 0.0f ? 1 : 0, a[5]);
    fhost[i * 3 + 0] = t.x;
    fhost[i * 3 + 1] = t.y;
    fhost[i * 3 + 2] = t.z;
  }
  std::vector<float> fdev = run_device_probe("tests/probe_transmission.cl", "probe_fog", fin, 3, nf);
  ::testing::AssertionResult rf = host_matches_device(fhost, fdev, kHostDeviceRelTol, kHostDeviceAbsFloor, "fog");
  std::printf("[ info     ] %s\n", rf.message());
  EXPECT_TRUE(rf);
}

}  // namespace
}  // namespace aw
