// Translucency: diffuse transmission (kernels/lobes/translucency.h). Chi-square over the whole
// sphere (the lobe lives on the far side), white furnace, reciprocity across the surface,
// eval/pdf/sample consistency, extremes, host vs device.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "kernels/tests/probe_basic_lobes.cl"
#include "tests/lobes/lobe_harness.h"

namespace aw {
namespace lobe_test {
namespace {

LobeFns translucency_fns(float3 color) {
  return LobeFns{[=](float3 wo, float3 wi) { return lobe_translucency_eval(color, wo, wi); },
                 [=](float3 wo, float3 wi) { return lobe_translucency_pdf(wo, wi); },
                 [=](float3 wo, float2 u) { return lobe_translucency_sample(color, wo, u); }};
}

const double kThetaDeg[] = {0.0, 45.0, 85.0, 89.9, 120.0, 180.0};  // > 90: wo below the surface

TEST(Translucency, EvalIsCosineLobeOnTheFarSide) {
  const float3 color = make_float3(0.7f, 0.6f, 0.5f);
  float3 wo = direction_from_theta_deg(30.0);
  float3 below = direction_from_theta_deg(140.0, 200.0);
  float3 above = direction_from_theta_deg(40.0, 200.0);
  float3 e = lobe_translucency_eval(color, wo, below);
  EXPECT_FLOAT_EQ(e.x, 0.7f * std::fabs(below.z) / M_PI_F);
  EXPECT_FLOAT_EQ(e.z, 0.5f * std::fabs(below.z) / M_PI_F);
  EXPECT_FLOAT_EQ(lobe_translucency_pdf(wo, below), std::fabs(below.z) / M_PI_F);
  // Nothing on wo's own side, nothing exactly at the horizon.
  EXPECT_EQ(lobe_translucency_eval(color, wo, above).x, 0.0f);
  EXPECT_EQ(lobe_translucency_pdf(wo, above), 0.0f);
  EXPECT_EQ(lobe_translucency_eval(color, wo, make_float3(1.0f, 0.0f, 0.0f)).x, 0.0f);
  EXPECT_EQ(lobe_translucency_pdf(make_float3(0.0f, 1.0f, 0.0f), below), 0.0f);
  // Samples go to the far side, with the transmission flags and weight = colour.
  Uniform uni(5);
  for (int i = 0; i < 1000; ++i) {
    LobeSample s = lobe_translucency_sample(color, wo, uni.next2());
    if (s.flags == 0u) continue;
    EXPECT_LT(s.wi.z, 0.0f);
    EXPECT_EQ(s.flags, AW_LOBE_DIFFUSE | AW_LOBE_TRANSMISSION);
    EXPECT_EQ(s.weight.x, color.x);
    EXPECT_EQ(s.weight.z, color.z);
  }
  LobeSample from_below = lobe_translucency_sample(color, direction_from_theta_deg(150.0), make_float2(0.3f, 0.3f));
  EXPECT_GT(from_below.wi.z, 0.0f);
  LobeSample grazing = lobe_translucency_sample(color, make_float3(1.0f, 0.0f, 0.0f), make_float2(0.3f, 0.3f));
  EXPECT_EQ(grazing.flags, 0u);
  EXPECT_EQ(grazing.pdf, 0.0f);
}

TEST(Translucency, ChiSquareOverTheWholeSphere) {
  ChiSquareConfig cfg;
  cfg.samples = lobe_test_samples(1000000);
  cfg.n_cases = int(sizeof(kThetaDeg) / sizeof(kThetaDeg[0]));
  for (double th : kThetaDeg) {
    ++cfg.seed;  // independent cases, as Sidak assumes
    EXPECT_TRUE(chi_square_passes(translucency_fns(make_float3(0.7f, 0.6f, 0.5f)), direction_from_theta_deg(th), cfg))
        << "theta " << th;
  }
}

TEST(Translucency, WhiteFurnaceIsLosslessAndColourIsTheAlbedo) {
  const size_t n = lobe_test_samples(1000000);
  for (double th : kThetaDeg) {
    float3 wo = direction_from_theta_deg(th);
    EXPECT_TRUE(white_furnace(translucency_fns(make_float3(1.0f, 1.0f, 1.0f)), wo, n, 7, /*lossless*/ true))
        << "theta " << th;
    const float3 color = make_float3(0.7f, 0.6f, 0.5f);
    LobeFns f = translucency_fns(color);
    EXPECT_TRUE(albedo_near(albedo_by_uniform_sphere(f, wo, n, 8), color)) << "theta " << th;
    EXPECT_TRUE(albedo_near(albedo_by_quadrature(f, wo), color, 0.0, 2e-5)) << "theta " << th;
    float3 a = lobe_translucency_albedo(color, wo.z);
    EXPECT_EQ(a.x, color.x);
  }
  EXPECT_EQ(lobe_translucency_albedo(make_float3(1.0f, 1.0f, 1.0f), 0.0f).x, 0.0f);
}

TEST(Translucency, ReciprocalAcrossTheSurface) {
  EXPECT_TRUE(reciprocal(translucency_fns(make_float3(0.7f, 0.6f, 0.5f)), 20000, 9, 1e-5, 1e-7, /*transmission*/ true));
}

TEST(Translucency, SampleWeightAndPdfMatchEvalAndPdf) {
  for (double th : kThetaDeg) {
    EXPECT_TRUE(sample_matches_eval_pdf(translucency_fns(make_float3(0.7f, 0.6f, 0.5f)), direction_from_theta_deg(th),
                                        20000, 10))
        << "theta " << th;
  }
}

TEST(Translucency, FiniteAtTheExtremes) {
  EXPECT_TRUE(eval_pdf_sample_finite(translucency_fns(make_float3(1.0f, 0.5f, 0.0f)), 20000, 11));
}

// Host vs device (kernels/tests/probe_basic_lobes.cl). Measured on PoCL 3.1 / LLVM 15: eval,
// pdf, weight and sampled x, y within 2e-7 relative; the sampled z is compared through z^2
// (see test_diffuse.cpp: the cosine warp's sqrt(1 - r^2) magnifies one-ulp cos/sin
// differences near the horizon).
TEST(Translucency, HostMatchesDevice) {
  Uniform uni(12);
  std::vector<float> in;
  for (int i = 0; i < 4000; ++i) {
    float3 wo = uniform_sphere(uni.next2());
    float3 wi = uniform_sphere(uni.next2());
    if (i % 7 == 0) wo.z = 0.0f;
    float2 u = uni.next2();
    for (float v : {uni.next(), uni.next(), uni.next(), wo.x, wo.y, wo.z, wi.x, wi.y, wi.z, u.x, u.y}) in.push_back(v);
  }
  size_t n = in.size() / AW_PROBE_TRANSLUCENCY_IN;
  std::vector<float> host(n * AW_PROBE_TRANSLUCENCY_OUT);
  for (size_t i = 0; i < n; ++i) {
    probe_translucency_item(&in[i * AW_PROBE_TRANSLUCENCY_IN], &host[i * AW_PROBE_TRANSLUCENCY_OUT]);
  }
  std::vector<float> device =
      run_device_probe("tests/probe_basic_lobes.cl", "probe_translucency", in, AW_PROBE_TRANSLUCENCY_OUT, n);
  const char* names[AW_PROBE_TRANSLUCENCY_OUT] = {"eval.x", "eval.y", "eval.z", "pdf",
                                                  "sample.wi.x", "sample.wi.y", "sample.wi.z", "sample.weight.x",
                                                  "sample.weight.y", "sample.weight.z", "sample.pdf", "sample.flags"};
  for (size_t k = 0; k < AW_PROBE_TRANSLUCENCY_OUT; ++k) {
    std::vector<float> h = probe_column(host, AW_PROBE_TRANSLUCENCY_OUT, k);
    std::vector<float> d = probe_column(device, AW_PROBE_TRANSLUCENCY_OUT, k);
    // Outputs 6 and 10 are the sampled z and the sample pdf = |z| / pi.
    ::testing::AssertionResult r =
        (k == 6 || k == 10) ? host_matches_device_squared(h, d, k == 10 ? M_PI : 1.0, 1e-6, names[k])
                            : host_matches_device(h, d, kHostDeviceRelTol, kHostDeviceAbsFloor, names[k]);
    EXPECT_TRUE(r);
    if (verbose()) std::printf("  [host/device] %s\n", r.message());
  }
}

}  // namespace
}  // namespace lobe_test
}  // namespace aw
