// Tests of the diffuse lobe (kernels/lobes/diffuse.h: EON, Lambert at roughness 0) and of the
// lobe harness itself (tests/lobes/lobe_harness.h: its statistics, and that it can fail).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "kernels/common/sampling.h"
#include "kernels/tests/probe_basic_lobes.cl"
#include "tests/lobes/lobe_harness.h"

namespace aw {
namespace lobe_test {
namespace {

// ---- the harness itself: statistics it relies on, and that it can fail ---------------------

TEST(LobeHarness, IncompleteGammaMatchesClosedForms) {
  // Integer a: Q(a, x) = e^-x sum_{k<a} x^k / k!.
  EXPECT_NEAR(regularized_gamma_q(1.0, 2.5), std::exp(-2.5), 1e-13);
  EXPECT_NEAR(regularized_gamma_q(5.0, 3.0), std::exp(-3.0) * (1 + 3 + 4.5 + 4.5 + 3.375), 1e-12);   // series
  EXPECT_NEAR(regularized_gamma_q(5.0, 10.0), std::exp(-10.0) * (1 + 10 + 50 + 1000.0 / 6 + 10000.0 / 24),
              1e-12);  // continued fraction
  // Chi-square with 1 dof: P(X >= s) = erfc(sqrt(s / 2)); with 2 dof: exp(-s / 2).
  for (double s : {0.1, 1.0, 3.84, 10.0, 40.0}) {
    EXPECT_NEAR(chi_square_p_value(s, 1), std::erfc(std::sqrt(s / 2.0)), 1e-12) << s;
    EXPECT_NEAR(chi_square_p_value(s, 2), std::exp(-s / 2.0), 1e-12) << s;
  }
  EXPECT_NEAR(sidak_alpha(0.01, 1), 0.01, 1e-15);
  EXPECT_NEAR(1.0 - std::pow(1.0 - sidak_alpha(0.01, 20), 20.0), 0.01, 1e-12);
}

TEST(LobeHarness, AdaptiveSimpsonIntegrates) {
  EXPECT_NEAR(adaptive_simpson([](double x) { return std::sin(x); }, 0.0, 3.14159265358979323846, 1e-10), 2.0,
              1e-9);
  // A narrow peak (width 1e-3 in [0, 1]) is found thanks to the forced minimum depth.
  auto peak = [](double x) { return std::exp(-0.5 * sqr(float((x - 0.37) / 1e-3))); };
  EXPECT_NEAR(adaptive_simpson(peak, 0.0, 1.0, 1e-10, 2, 20), 1e-3 * std::sqrt(2.0 * 3.14159265358979323846), 1e-6);
}

LobeFns cosine_lobe() {
  return LobeFns{[](float3 wo, float3 wi) {
                   float v = (wo.z > 0.0f && wi.z > 0.0f) ? wi.z / M_PI_F : 0.0f;
                   return make_float3(v, v, v);
                 },
                 [](float3 wo, float3 wi) { return (wo.z > 0.0f && wi.z > 0.0f) ? wi.z / M_PI_F : 0.0f; },
                 [](float3 wo, float2 u) {
                   LobeSample s;
                   s.wi = sample_cosine_hemisphere(u);
                   s.pdf = s.wi.z / M_PI_F;
                   s.weight = make_float3(1.0f, 1.0f, 1.0f);
                   s.flags = (wo.z > 0.0f && s.pdf > 0.0f) ? AW_LOBE_DIFFUSE_REFLECTION : 0u;
                   if (!s.flags) {
                     s.pdf = 0.0f;
                     s.weight = make_float3(0.0f, 0.0f, 0.0f);
                   }
                   return s;
                 }};
}

TEST(LobeHarness, CorrectLobePassesEveryCheck) {
  LobeFns f = cosine_lobe();
  ChiSquareConfig cfg;
  cfg.samples = lobe_test_samples(1000000);
  float3 wo = direction_from_theta_deg(40.0);
  EXPECT_TRUE(chi_square_passes(f, wo, cfg));
  EXPECT_TRUE(sample_matches_eval_pdf(f, wo, 10000, 3));
  EXPECT_TRUE(eval_pdf_sample_finite(f, 10000, 4));
  EXPECT_TRUE(reciprocal(f, 10000, 5));
  EXPECT_TRUE(white_furnace(f, wo, 100000, 6, true));
}

// The harness must be able to fail: a pdf off by a factor, a pdf of the wrong shape, a
// sampler that fails where the pdf says it always succeeds, a lossy lobe called lossless.
TEST(LobeHarness, DetectsBrokenLobes) {
  float3 wo = direction_from_theta_deg(40.0);
  ChiSquareConfig cfg;
  cfg.samples = lobe_test_samples(1000000);

  LobeFns wrong_shape = cosine_lobe();  // claims uniform-hemisphere density
  wrong_shape.pdf = [](float3 wo, float3 wi) { return (wo.z > 0.0f && wi.z > 0.0f) ? 0.5f / M_PI_F : 0.0f; };
  ChiSquareResult r = run_chi_square(wrong_shape, wo, cfg);
  EXPECT_FALSE(r.passed) << r.message;
  EXPECT_LT(r.p_value, 1e-10) << r.message;

  LobeFns wrong_factor = cosine_lobe();  // pdf 10% too large: integral > 1
  wrong_factor.pdf = [](float3 wo, float3 wi) { return (wo.z > 0.0f && wi.z > 0.0f) ? 1.1f * wi.z / M_PI_F : 0.0f; };
  EXPECT_FALSE(run_chi_square(wrong_factor, wo, cfg).passed);
  EXPECT_FALSE(sample_matches_eval_pdf(wrong_factor, wo, 1000, 3));

  LobeFns lossy_sampler = cosine_lobe();  // fails 5% of the time
  auto inner = lossy_sampler.sample;
  lossy_sampler.sample = [inner](float3 wo, float2 u) {
    LobeSample s = inner(wo, u);
    if (u.x > 0.95f) {
      s.flags = 0u;
      s.pdf = 0.0f;
      s.weight = make_float3(0.0f, 0.0f, 0.0f);
    }
    return s;
  };
  EXPECT_FALSE(run_chi_square(lossy_sampler, wo, cfg).passed);
  EXPECT_FALSE(white_furnace(lossy_sampler, wo, 100000, 6, true));

  LobeFns nan_eval = cosine_lobe();
  nan_eval.eval = [](float3 wo, float3 wi) {
    float v = wi.z / M_PI_F / wo.z;  // NaN/Inf at wo.z = 0
    return make_float3(v, v, v);
  };
  EXPECT_FALSE(eval_pdf_sample_finite(nan_eval, 100, 4));

  LobeFns not_reciprocal = cosine_lobe();
  not_reciprocal.eval = [](float3 wo, float3 wi) {
    float v = (wo.z > 0.0f && wi.z > 0.0f) ? wi.z * wo.z : 0.0f;
    return make_float3(v, v, v);
  };
  EXPECT_FALSE(reciprocal(not_reciprocal, 1000, 5));
}

// ---- the diffuse lobe ------------------------------------------------------------------------

LobeFns diffuse_fns(float3 albedo, float roughness) {
  return LobeFns{[=](float3 wo, float3 wi) { return lobe_diffuse_eval(albedo, roughness, wo, wi); },
                 [=](float3 wo, float3 wi) { return lobe_diffuse_pdf(roughness, wo, wi); },
                 [=](float3 wo, float2 u) { return lobe_diffuse_sample(albedo, roughness, wo, u); }};
}

const float kRoughness[] = {0.0f, 1e-6f, 0.1f, 0.25f, 0.5f, 0.75f, 1.0f};
const double kThetaDeg[] = {0.0, 30.0, 60.0, 80.0, 89.0};

// The EON paper's formulas in double, in their direct form (1 - E, (S/mu)(1 - S^3) as
// written), independent of the cancellation-free rewriting in diffuse.h.
struct EonReference {
  double sigma;
  double a_f() const { return 1.0 / (1.0 + (0.5 - 2.0 / (3.0 * M_PI)) * sigma); }
  double e_f(double mu) const {
    double s = std::sqrt(1.0 - mu * mu);
    double g = s * (std::acos(mu) - s * mu) + (2.0 / 3.0) * ((s / mu) * (1.0 - s * s * s) - s);
    return a_f() * (1.0 + sigma * g / M_PI);
  }
  double e_avg() const { return a_f() * (1.0 + (2.0 / 3.0 - 28.0 / (15.0 * M_PI)) * sigma); }
  double rho_ms(double rho) const { return rho * rho * e_avg() / (1.0 - rho * (1.0 - e_avg())); }
  // f * cos theta_i
  double eval(double rho, const double* wo, const double* wi) const {
    double mu_i = wi[2], mu_o = wo[2];
    double s = wi[0] * wo[0] + wi[1] * wo[1] + wi[2] * wo[2] - mu_i * mu_o;
    double s_over_t = s > 0.0 ? s / std::max(mu_i, mu_o) : s;
    double f_ss = rho / M_PI * a_f() * (1.0 + sigma * s_over_t);
    double f_ms = rho_ms(rho) / M_PI * (1.0 - e_f(mu_o)) * (1.0 - e_f(mu_i)) / (1.0 - e_avg());
    return (f_ss + f_ms) * mu_i;
  }
  double albedo(double rho, double mu_o) const { return rho * e_f(mu_o) + rho_ms(rho) * (1.0 - e_f(mu_o)); }
};

TEST(Diffuse, RoughnessZeroIsLambertBitForBit) {
  // The pre-EON lobe, verbatim: f = albedo / pi, cosine sampling with weight = albedo.
  Uniform uni(21);
  for (int i = 0; i < 20000; ++i) {
    float3 albedo = make_float3(uni.next(), uni.next(), uni.next());
    float3 wo = uniform_sphere(uni.next2());
    float3 wi = uniform_sphere(uni.next2());
    float2 u = uni.next2();
    float3 e = lobe_diffuse_eval(albedo, 0.0f, wo, wi);
    float3 lambert = (wo.z <= 0.0f || wi.z <= 0.0f) ? make_float3(0.0f, 0.0f, 0.0f) : albedo * (wi.z * (1.0f / M_PI_F));
    ASSERT_EQ(e.x, lambert.x);
    ASSERT_EQ(e.y, lambert.y);
    ASSERT_EQ(e.z, lambert.z);
    float pdf = (wo.z <= 0.0f || wi.z <= 0.0f) ? 0.0f : pdf_cosine_hemisphere(wi.z);
    ASSERT_EQ(lobe_diffuse_pdf(0.0f, wo, wi), pdf);
    LobeSample s = lobe_diffuse_sample(albedo, 0.0f, wo, u);
    float3 wc = sample_cosine_hemisphere(u);
    float pc = (wo.z <= 0.0f || wc.z <= 0.0f) ? 0.0f : pdf_cosine_hemisphere(wc.z);
    ASSERT_EQ(s.wi.x, wc.x);
    ASSERT_EQ(s.wi.y, wc.y);
    ASSERT_EQ(s.wi.z, wc.z);
    ASSERT_EQ(s.pdf, pc);
    if (pc > 0.0f) {
      ASSERT_EQ(s.flags, AW_LOBE_DIFFUSE_REFLECTION);
      ASSERT_EQ(s.weight.x, albedo.x);
      ASSERT_EQ(s.weight.y, albedo.y);
      ASSERT_EQ(s.weight.z, albedo.z);
    } else {
      ASSERT_EQ(s.flags, 0u);
    }
    float3 a = lobe_diffuse_albedo(albedo, 0.0f, wo.z);
    ASSERT_EQ(a.x, wo.z > 0.0f ? albedo.x : 0.0f);
  }
}

TEST(Diffuse, EonMatchesThePaperFormulasInDouble) {
  Uniform uni(22);
  double worst = 0.0, worst_albedo = 0.0;
  for (float r : {0.05f, 0.25f, 0.5f, 1.0f}) {
    EonReference ref{double(r)};
    for (int i = 0; i < 5000; ++i) {
      float rho = uni.next();
      // |cos| >= 0.01 keeps the reference's own (S/mu)(1 - S^3) cancellation out of it.
      float3 wo = direction_from_cos_phi(0.01 + 0.99 * uni.next(), 6.2831853 * uni.next());
      float3 wi = direction_from_cos_phi(0.01 + 0.99 * uni.next(), 6.2831853 * uni.next());
      const double o[3] = {wo.x, wo.y, wo.z}, in[3] = {wi.x, wi.y, wi.z};
      double expect = ref.eval(rho, o, in);
      double got = lobe_diffuse_eval(make_float3(rho, rho, rho), r, wo, wi).x;
      double d = relative_difference(got, expect, 1e-6);
      worst = std::max(worst, d);
      ASSERT_LE(d, 2e-5) << "roughness " << r << " rho " << rho << " wo " << fmt3(wo) << " wi " << fmt3(wi);
      double ea = ref.albedo(rho, wo.z);
      double ga = lobe_diffuse_albedo(make_float3(rho, rho, rho), r, wo.z).x;
      worst_albedo = std::max(worst_albedo, relative_difference(ga, ea, 1e-6));
      ASSERT_LE(relative_difference(ga, ea, 1e-6), 2e-5) << "roughness " << r << " cos_o " << wo.z;
    }
  }
  if (verbose()) std::printf("  eval vs double reference: %.3g, albedo: %.3g\n", worst, worst_albedo);
}

TEST(Diffuse, FonAlbedoClosedFormsMatchQuadrature) {
  // The paper's closed forms for the FON albedo at rho = 1, checked by direct quadrature of
  // f_ss cos over the hemisphere (in double): E_F(mu_o), and E_avg = 2 int E_F(mu) mu dmu.
  const double c1 = 0.5 - 2.0 / (3.0 * M_PI), c2 = 2.0 / 3.0 - 28.0 / (15.0 * M_PI);
  for (double sigma : {0.3, 1.0}) {
    double a_f = 1.0 / (1.0 + c1 * sigma);
    for (double mu_o : {0.05, 0.3, 0.7, 1.0}) {
      double so = std::sqrt(1.0 - mu_o * mu_o);
      auto over_phi = [&](double mu_i) {
        double si = std::sqrt(std::max(0.0, 1.0 - mu_i * mu_i));
        auto f = [&](double phi) {
          double s = si * so * std::cos(phi);
          double st = s > 0.0 ? s / std::max(mu_i, mu_o) : s;
          return a_f / M_PI * (1.0 + sigma * st) * mu_i;
        };
        return adaptive_simpson(f, 0.0, 2.0 * M_PI, 1e-11, 3, 18);
      };
      double e = adaptive_simpson(over_phi, 0.0, 1.0, 1e-10, 3, 18);
      double g = eon_g(float(mu_o));
      EXPECT_NEAR(e, a_f * (1.0 + sigma * g / M_PI), 2e-6) << "sigma " << sigma << " mu_o " << mu_o;
    }
    double avg = adaptive_simpson(
        [&](double mu) { return 2.0 * mu * a_f * (1.0 + sigma * double(eon_g(float(mu))) / M_PI); }, 0.0, 1.0, 1e-10);
    EXPECT_NEAR(avg, a_f * (1.0 + c2 * sigma), 2e-6) << "sigma " << sigma;
  }
  EXPECT_NEAR(eon_g(1.0f), 0.0f, 1e-7f);
  EXPECT_NEAR(eon_g(0.0f), M_PI / 2.0 - 2.0 / 3.0, 1e-6);
}

// EON's point: with albedo 1 the lobe is lossless at every roughness and angle.
TEST(Diffuse, WhiteFurnaceIsOneForEveryRoughness) {
  const size_t n = lobe_test_samples(1000000);
  for (float r : kRoughness) {
    LobeFns f = diffuse_fns(make_float3(1.0f, 1.0f, 1.0f), r);
    for (double th : kThetaDeg) {
      float3 wo = direction_from_theta_deg(th);
      ::testing::AssertionResult res = white_furnace(f, wo, n, 31, /*lossless*/ true);
      EXPECT_TRUE(res) << "roughness " << r << " theta " << th;
      if (verbose()) std::printf("  [furnace] r %.2f theta %4.1f: %s\n", r, th, res.message());
      float3 a = lobe_diffuse_albedo(make_float3(1.0f, 1.0f, 1.0f), r, wo.z);
      EXPECT_NEAR(a.x, 1.0f, 2e-6f) << "roughness " << r << " theta " << th;
      // Deterministic quadrature of eval: no statistical slack at all.
      AlbedoEstimate q = albedo_by_quadrature(f, wo);
      EXPECT_NEAR(q.mean[0], 1.0, 2e-5) << "roughness " << r << " theta " << th;
      if (verbose()) std::printf("  [furnace] r %.2f theta %4.1f: quadrature %.7f\n", r, th, q.mean[0]);
    }
  }
}

TEST(Diffuse, ColouredAlbedoMatchesLobeDiffuseAlbedoAndStaysBelowOne) {
  const size_t n = lobe_test_samples(1000000);
  const float3 albedo = make_float3(0.9f, 0.5f, 0.05f);
  for (float r : {0.0f, 0.25f, 0.5f, 1.0f}) {
    LobeFns f = diffuse_fns(albedo, r);
    for (double th : kThetaDeg) {
      float3 wo = direction_from_theta_deg(th);
      float3 expected = lobe_diffuse_albedo(albedo, r, wo.z);
      EXPECT_TRUE(albedo_near(albedo_by_sampling(f, wo, n, 41), expected)) << "roughness " << r << " theta " << th;
      EXPECT_TRUE(albedo_near(albedo_by_uniform_sphere(f, wo, n, 42), expected))
          << "roughness " << r << " theta " << th;
      EXPECT_TRUE(white_furnace(f, wo, n / 4, 43, /*lossless*/ false));
      EXPECT_TRUE(albedo_near(albedo_by_quadrature(f, wo), expected, 0.0, 2e-5))
          << "roughness " << r << " theta " << th;
      // Energy compensation adds (never removes) energy relative to single scattering, and
      // never exceeds the albedo itself.
      EXPECT_LE(expected.x, albedo.x * (1.0f + 1e-6f));
      EXPECT_LE(expected.z, albedo.z * (1.0f + 1e-6f));
    }
  }
}

TEST(Diffuse, ChiSquareCosineSampling) {
  const float rs[] = {0.0f, 0.5f, 1.0f};
  const double ths[] = {0.0, 45.0, 85.0};
  ChiSquareConfig cfg;
  cfg.samples = lobe_test_samples(1000000);
  cfg.n_cases = 9;
  for (float r : rs) {
    for (double th : ths) {
      ++cfg.seed;  // independent cases, as Sidak assumes
      EXPECT_TRUE(chi_square_passes(diffuse_fns(make_float3(0.8f, 0.8f, 0.8f), r), direction_from_theta_deg(th), cfg))
          << "roughness " << r << " theta " << th;
    }
  }
}

TEST(Diffuse, SampleWeightAndPdfMatchEvalAndPdf) {
  for (float r : kRoughness) {
    LobeFns f = diffuse_fns(make_float3(0.7f, 0.4f, 1.0f), r);
    for (double th : kThetaDeg) {
      EXPECT_TRUE(sample_matches_eval_pdf(f, direction_from_theta_deg(th), 20000, 51))
          << "roughness " << r << " theta " << th;
    }
    // Below the surface: the lobe is one-sided, every sample fails cleanly.
    LobeSample s = f.sample(direction_from_theta_deg(120.0), make_float2(0.3f, 0.6f));
    EXPECT_EQ(s.flags, 0u);
    EXPECT_EQ(s.pdf, 0.0f);
  }
}

TEST(Diffuse, Reciprocal) {
  for (float r : kRoughness) {
    EXPECT_TRUE(reciprocal(diffuse_fns(make_float3(0.7f, 0.4f, 1.0f), r), 20000, 61)) << "roughness " << r;
  }
}

TEST(Diffuse, FiniteAtTheExtremes) {
  for (float r : {0.0f, 1e-30f, 1e-7f, 0.5f, 1.0f, -1.0f, 2.0f}) {
    EXPECT_TRUE(eval_pdf_sample_finite(diffuse_fns(make_float3(1.0f, 0.5f, 0.0f), r), 20000, 71)) << "roughness " << r;
    for (float c : {-1.0f, 0.0f, 1e-30f, 1e-7f, 0.5f, 1.0f}) {
      float3 a = lobe_diffuse_albedo(make_float3(1.0f, 0.5f, 0.0f), r, c);
      EXPECT_TRUE(finite3(a) && a.x >= 0.0f && a.x <= 1.0f + 1e-6f) << "roughness " << r << " cos " << c;
    }
  }
}

TEST(Diffuse, RoughnessFlattensAndBackscatters) {
  // Oren–Nayar's qualitative signature: at high roughness a retro-reflective configuration
  // (light behind the viewer, both grazing) is brighter than Lambert, a forward one darker.
  float3 wo = direction_from_theta_deg(70.0, 0.0);
  float3 back = direction_from_theta_deg(70.0, 0.0);
  float3 fwd = direction_from_theta_deg(70.0, 180.0);
  float3 white = make_float3(1.0f, 1.0f, 1.0f);
  EXPECT_GT(lobe_diffuse_eval(white, 1.0f, wo, back).x, lobe_diffuse_eval(white, 0.0f, wo, back).x);
  EXPECT_LT(lobe_diffuse_eval(white, 1.0f, wo, fwd).x, lobe_diffuse_eval(white, 0.0f, wo, fwd).x);
}

// The quarter-range sine and cosine of the concentric map (common/sampling.h) against double
// precision over a dense grid of [-pi/4, pi/4] (about one ulp measured; checked at 2.5e-7
// relative, four ulps of 1/2), and the map itself against its polar definition with the
// library's trigonometry: on the unit disk, in the right wedge, within 3e-7 of the reference.
TEST(Diffuse, ConcentricMapTrigonometryIsAccurate) {
  const double q = M_PI / 4.0;
  double worst_s = 0.0, worst_c = 0.0;
  for (int i = -200000; i <= 200000; ++i) {
    float x = float(q * i / 200000.0);
    float s, c;
    sincos_quarter(x, &s, &c);
    double es = std::sin(double(x)), ec = std::cos(double(x));
    if (es != 0.0) worst_s = std::fmax(worst_s, std::fabs(s - es) / std::fabs(es));
    worst_c = std::fmax(worst_c, std::fabs(c - ec) / ec);
  }
  EXPECT_LT(worst_s, 2.5e-7);
  EXPECT_LT(worst_c, 2.5e-7);
  Uniform uni(7);
  double worst_map = 0.0;
  for (int i = 0; i < 100000; ++i) {
    float2 u = uni.next2();
    float2 d = sample_concentric_disk(u);
    double a = 2.0 * u.x - 1.0, b = 2.0 * u.y - 1.0, r, phi;
    if (std::fabs(a) > std::fabs(b)) r = a, phi = q * (b / a);
    else r = b, phi = 2.0 * q - q * (a / b);
    worst_map = std::fmax(worst_map, std::fmax(std::fabs(d.x - r * std::cos(phi)), std::fabs(d.y - r * std::sin(phi))));
    EXPECT_LE(double(d.x) * d.x + double(d.y) * d.y, 1.0 + 1e-6);
  }
  EXPECT_LT(worst_map, 3e-7);
}

// The azimuth's sine and cosine (sincos_turn: octant reduction of 2 pi u, then the quarter-range
// polynomials) against double precision, over a dense grid of u in [0, 1] that includes every
// octant boundary: within 2.5e-7 absolute, and on the unit circle.
TEST(Diffuse, AzimuthSineAndCosineAreAccurate) {
  double worst = 0.0;
  const int n = 800000;  // a multiple of 8: the octant boundaries are grid points
  for (int i = 0; i <= n; ++i) {
    float u = float(double(i) / n);
    float s, c;
    sincos_turn(u, &s, &c);
    double phi = 2.0 * M_PI * double(u);
    worst = std::fmax(worst, std::fmax(std::fabs(s - std::sin(phi)), std::fabs(c - std::cos(phi))));
    ASSERT_NEAR(double(s) * s + double(c) * c, 1.0, 5e-7) << "u = " << u;
  }
  EXPECT_LT(worst, 2.5e-7);
  float s, c;
  sincos_turn(0.0f, &s, &c);
  EXPECT_EQ(s, 0.0f);
  EXPECT_EQ(c, 1.0f);
  sincos_turn(0.25f, &s, &c);
  EXPECT_EQ(s, 1.0f);
  EXPECT_EQ(c, 0.0f);
}

// The OpenCL build of the same functions (kernels/tests/probe_basic_lobes.cl) against the
// host build, output by output, at the suite's 1e-5 relative tolerance. Measured on PoCL 3.1 /
// LLVM 15 (x86-64): eval, albedo, weight and sampled x, y within 6e-7 relative.
// The sampled z (and the sample pdf = z/pi) is the exception, and not a lobe disagreement:
// the cosine warp forms z = sqrt(1 - x^2 - y^2) from cos/sin of the concentric map, which
// differ by an ulp between the two math libraries; the error in 1 - r^2 is ~1e-7 absolute,
// and near the horizon z magnifies it (relative 2e-5 at z = 0.05). So z is compared through
// z^2 in absolute terms (tolerance 1e-6; measured 2.2e-7), the quantity the warp computes.
TEST(Diffuse, HostMatchesDevice) {
  Uniform uni(81);
  std::vector<float> in;
  const float rs[] = {0.0f, 1e-6f, 0.25f, 0.5f, 1.0f};
  for (int i = 0; i < 4000; ++i) {
    float r = rs[i % 5];
    float3 wo = uniform_sphere(uni.next2());
    float3 wi = uniform_sphere(uni.next2());
    if (i % 7 == 0) wo.z = 0.0f;
    if (i % 11 == 0) wi = make_float3(-wo.x, -wo.y, wo.z);
    float2 u = uni.next2();
    // (A braced list is evaluated left to right, so the draws are in a fixed order.)
    for (float v : {uni.next(), uni.next(), uni.next(), r, wo.x, wo.y, wo.z, wi.x, wi.y, wi.z, u.x, u.y}) {
      in.push_back(v);
    }
  }
  size_t n = in.size() / AW_PROBE_DIFFUSE_IN;
  std::vector<float> host(n * AW_PROBE_DIFFUSE_OUT);
  for (size_t i = 0; i < n; ++i) probe_diffuse_item(&in[i * AW_PROBE_DIFFUSE_IN], &host[i * AW_PROBE_DIFFUSE_OUT]);
  std::vector<float> device =
      run_device_probe("tests/probe_basic_lobes.cl", "probe_diffuse", in, AW_PROBE_DIFFUSE_OUT, n);
  const char* names[AW_PROBE_DIFFUSE_OUT] = {"eval.x", "eval.y", "eval.z", "pdf", "sample.wi.x", "sample.wi.y",
                                             "sample.wi.z", "sample.weight.x", "sample.weight.y", "sample.weight.z",
                                             "sample.pdf", "sample.flags", "albedo.x", "albedo.y", "albedo.z"};
  for (size_t k = 0; k < AW_PROBE_DIFFUSE_OUT; ++k) {
    std::vector<float> h = probe_column(host, AW_PROBE_DIFFUSE_OUT, k);
    std::vector<float> d = probe_column(device, AW_PROBE_DIFFUSE_OUT, k);
    ::testing::AssertionResult r =
        (k == 6 || k == 10) ? host_matches_device_squared(h, d, k == 10 ? M_PI : 1.0, 1e-6, names[k])  // z, pdf = z/pi
                            : host_matches_device(h, d, kHostDeviceRelTol, kHostDeviceAbsFloor, names[k]);
    EXPECT_TRUE(r);
    if (verbose()) std::printf("  [host/device] %s\n", r.message());
  }
}

// l_acos (common/lanes.h, Cephes' acosf) against double precision over [-1, 1]: 2^20 + 1
// evenly spaced points plus the ends, 0 and +-1/2 (where it switches form); its result is in
// [0, pi] and never increases with x.
TEST(LaneMath, AcosIsCephesAccurate) {
  double max_err = 0.0, worst = 0.0;
  float prev = l_acos(-1.0f);
  bool monotone = true;
  const int n = 1 << 20;
  for (int i = 0; i <= n; ++i) {
    float x = -1.0f + 2.0f * float(i) / float(n);
    float y = l_acos(x);
    double e = std::fabs(double(y) - std::acos(double(x)));
    if (e > max_err) max_err = e, worst = x;
    if (y > prev) monotone = false;
    prev = y;
    ASSERT_TRUE(y >= 0.0f && y <= float(M_PI)) << x;
  }
  for (float x : {-1.0f, -0.5f, 0.0f, 0.5f, 1.0f, std::nextafter(0.5f, 1.0f), std::nextafter(-0.5f, -1.0f)})
    max_err = std::max(max_err, std::fabs(double(l_acos(x)) - std::acos(double(x))));
  std::printf("  l_acos: max abs error %.3g (at %.9g)\n", max_err, worst);
  EXPECT_LT(max_err, 4e-7);  // measured 3.0e-7 (about 1.3 ulp of the result near x = -0.5)
  EXPECT_TRUE(monotone);
  EXPECT_EQ(l_acos(1.0f), 0.0f);
}

// pow on 16 lanes against pow on one float, on the device (kernels/tests/probe_lanes.cl,
// probe_pow_lanes): the artist curve's Fresnel (lobes/fresnel.h, fresnel_curve) is the one
// library call of the lane classification stage, whose film must equal the one-path kernels'
// bit for bit (Lanes.SameFilmWithAndWithoutLanes); PoCL's acos did not round alike (l_acos
// above). The two agree wherever the result is a normal float; PoCL 3.1 rounds subnormal
// results differently on a vector (this test found it), which fresnel_curve takes as 0, so
// fresnel_curve itself agrees everywhere. Bases over [0, 1] (1 - cos), with 0, 1/2, 1 and a
// subnormal; exponents over [0, 20], with 0 and small integers (the curve's default is 5).
// Runs on every device (@intel, @gpu).
TEST(LaneMath, PowRoundsAsOnAScalar) {
  const uint32_t n = 1u << 16;
  Uniform uni(5077);
  std::vector<float> in(2 * n);
  for (uint32_t i = 0; i < n; ++i) {
    float x = uni.next(), y = 20.0f * uni.next();
    if (i % 11 == 0) x = float(i % 3) * 0.5f;
    if (i % 13 == 0) x = 1e-40f;
    if (i % 7 == 0) y = float(i % 8);
    in[i] = x;
    in[n + i] = y;
  }
  std::vector<float> dev = run_device_probe("tests/probe_lanes.cl", "probe_pow_lanes", in, 4, n);
  size_t pow_differ = 0, curve_differ = 0, subnormal = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const float lanes = dev[i], one = dev[n + i];
    subnormal += std::fabs(one) < 1.17549435e-38f && one != 0.0f;
    if (std::memcmp(&lanes, &one, 4) != 0 && std::fabs(one) >= 1.17549435e-38f && pow_differ++ < 10)
      ADD_FAILURE() << "pow(" << in[i] << ", " << in[n + i] << "): 16 lanes " << lanes << ", one float " << one;
    if (std::memcmp(&dev[2 * n + i], &dev[3 * n + i], 4) != 0 && curve_differ++ < 10)
      ADD_FAILURE() << "fresnel_curve at 1 - " << in[i] << ", exponent " << in[n + i] << ": 16 lanes " << dev[2 * n + i]
                    << ", one float " << dev[3 * n + i];
  }
  EXPECT_EQ(pow_differ, 0u);
  EXPECT_EQ(curve_differ, 0u);
  EXPECT_GT(subnormal, 10u);  // the inputs do reach the subnormal results that fresnel_curve flushes
}

// The diffuse lobe on lanes (lobes/diffuse.h, common/lanes.h): built with 16 paths per
// work-item (kernels/tests/probe_lanes.cl, probe_diffuse_lanes), its eval, pdf, sample and
// directional albedo equal the host's one-path C++ bit for bit (EON's arccos is l_acos, which
// rounds the same everywhere; PoCL's own acos did not, between float16 and float). Lambert
// and rough paths mixed in every group of 16 (the EON branch runs for some lanes and is
// selected away for others), directions below the surface, grazing and at the pole, albedos
// up to 8 (the rho_ms floor).
// Runs on every device (@intel, @gpu).
TEST(DiffuseLanes, SixteenPathsPerWorkItemEqualTheHostBitForBit) {
  const uint32_t n = 4096;
  Uniform uni(1204);
  std::vector<float> in(12 * n);
  for (uint32_t i = 0; i < n; ++i) {
    float3 wo = uniform_sphere(uni.next2()), wi = uniform_sphere(uni.next2());
    if (i % 17 == 0) wo = make_float3(0.0f, 0.0f, 1.0f);
    if (i % 19 == 0) wi = normalize(make_float3(1.0f, 0.0f, 1e-7f));
    float rough = i % 3 == 0 ? 0.0f : i % 3 == 1 ? uni.next() : 1.0f;
    float amax = i % 23 == 0 ? 8.0f : 1.0f;
    float vals[12] = {amax * uni.next(), amax * uni.next(), amax * uni.next(), rough, wo.x, wo.y, wo.z,
                      wi.x, wi.y, wi.z, uni.next(), uni.next()};
    for (uint32_t k = 0; k < 12; ++k) in[k * n + i] = vals[k];
  }
  const uint32_t outs = 15;
  std::vector<float> dev = run_device_probe("tests/probe_lanes.cl", "probe_diffuse_lanes", in, outs, n);
  size_t differ = 0;
  for (uint32_t i = 0; i < n; ++i) {
    float3 albedo = make_float3(in[i], in[n + i], in[2 * n + i]), wo = make_float3(in[4 * n + i], in[5 * n + i], in[6 * n + i]);
    float3 wi = make_float3(in[7 * n + i], in[8 * n + i], in[9 * n + i]);
    float rough = in[3 * n + i];
    float3 e = lobe_diffuse_eval(albedo, rough, wo, wi);
    LobeSample smp = lobe_diffuse_sample(albedo, rough, wo, make_float2(in[10 * n + i], in[11 * n + i]));
    float3 a = lobe_diffuse_albedo(albedo, rough, wo.z);
    float flags;
    std::memcpy(&flags, &smp.flags, 4);
    float r[outs] = {e.x, e.y, e.z, lobe_diffuse_pdf(rough, wo, wi), smp.wi.x, smp.wi.y, smp.wi.z,
                     smp.weight.x, smp.weight.y, smp.weight.z, smp.pdf, flags, a.x, a.y, a.z};
    for (uint32_t k = 0; k < outs; ++k) {
      float d = dev[k * n + i];
      if (std::memcmp(&r[k], &d, 4) != 0 && differ++ < 10)
        ADD_FAILURE() << "output " << k << " at item " << i << " (roughness " << rough << "): host " << r[k]
                      << ", 16 lanes " << d;
    }
  }
  EXPECT_EQ(differ, 0u);
}

}  // namespace
}  // namespace lobe_test
}  // namespace aw
