// Environment-map importance sampling (kernels/lights/environment.h, host/render/environment_pack.h):
// the directions env_sample draws follow the density env_pdf reports, which is what MIS reads
// when a BSDF-sampled ray escapes (classify_hit.h). A chi-square test over the map's texels
// (the distribution is piecewise constant per texel, so the texel is the natural cell), at
// significance 1e-3 per case with fixed seeds; plus the mapping's fixed points and rotation.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "host/render/environment_pack.h"
#include "kernels/common/compat.h"
#include "kernels/lights/environment.h"
#include "tests/lobes/lobe_harness.h"

namespace {

RenderParams params_for(int w, int h, float rotation_deg) {
  RenderParams rp{};
  rp.env_width = uint32_t(w);
  rp.env_height = uint32_t(h);
  rp.env_rot_cos = std::cos(rotation_deg * M_PI_F / 180.0f);
  rp.env_rot_sin = std::sin(rotation_deg * M_PI_F / 180.0f);
  return rp;
}

// A map with structure: a smooth gradient, a hot texel and a black row (never sampled).
std::vector<float> test_map(int w, int h) {
  std::vector<float> rgb(size_t(w) * h * 3);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      float* p = &rgb[3 * (size_t(j) * w + i)];
      p[0] = 0.1f + float(i) / w;
      p[1] = 0.2f + 0.5f * float(j) / h;
      p[2] = 0.05f;
      if (j == h / 2 + 1) p[0] = p[1] = p[2] = 0.0f;
    }
  float* hot = &rgb[3 * (size_t(2) * w + 5)];
  hot[0] = hot[1] = hot[2] = 40.0f;
  return rgb;
}

void check_chi_square(int w, int h, float rotation) {
  const std::vector<float> rgb = test_map(w, h);
  aw::PackedEnvironment pe = aw::pack_environment(rgb, w, h, 1.0f);
  const RenderParams rp = params_for(w, h, rotation);
  const float* env = pe.buffer.data();
  std::mt19937 rng(20261202u);
  std::uniform_real_distribution<float> uni(0.0f, 1.0f);
  const size_t n = 400000;
  std::vector<double> count(size_t(w) * h, 0.0);
  size_t pdf_mismatch = 0;
  for (size_t k = 0; k < n; ++k) {
    float pdf;
    uint texel;
    float3 d = env_sample(env, &rp, make_float2(uni(rng), uni(rng)), &pdf, &texel);
    ASSERT_NEAR(length(d), 1.0f, 1e-5f);
    ASSERT_GT(pdf, 0.0f);
    // The cell the lookup puts the direction in: the radiance MIS sees on an escaping ray.
    uint t = env_texel(&rp, env_to_map(&rp, d));
    count[t] += 1.0;
    // The density MIS computes from the direction equals the sampler's own (rounding aside,
    // and except on a texel border, where the lookup may land in the neighbour).
    float q = env_pdf(env, &rp, d);
    if (std::fabs(q / pdf - 1.0f) > 1e-3f && t == texel) ++pdf_mismatch;
  }
  EXPECT_EQ(pdf_mismatch, 0u);
  // Expected probability of each texel from the density MIS uses: env_pdf at the texel's
  // centre times the texel's solid angle 2 pi^2 sin(theta) / (w h), sin(theta) taken at the
  // same centre (the density is pdf_uv / (2 pi^2 sin theta): the sines cancel exactly).
  std::vector<double> observed, expected;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const float th = M_PI_F * (j + 0.5f) / h, ph = 2.0f * M_PI_F * ((i + 0.5f) / w - 0.5f);
      float3 dm = make_float3(std::sin(th) * std::sin(ph), std::cos(th), -std::sin(th) * std::cos(ph));
      float3 d = env_from_map(&rp, dm);
      const double p = double(env_pdf(env, &rp, d)) * 2.0 * M_PI * M_PI * std::sin(th) / (double(w) * h);
      const double e = p * n;
      const double o = count[size_t(j) * w + i];
      if (p == 0.0) {
        EXPECT_EQ(o, 0.0) << "texel " << i << "," << j << " has no power but was sampled";
        continue;
      }
      observed.push_back(o);
      expected.push_back(e);
    }
  const aw::lobe_test::PooledChiSquare c = aw::lobe_test::pooled_chi_square(observed, expected);
  std::printf("env %dx%d rot %.0f: chi2 %.1f dof %d p %.3g\n", w, h, rotation, c.statistic, c.dof, c.p_value);
  EXPECT_GT(c.p_value, 1e-3) << "chi2 " << c.statistic << " dof " << c.dof;
}

TEST(EnvSampling, DirectionsFollowThePdfMisUses) { check_chi_square(32, 16, 0.0f); }
TEST(EnvSampling, RotatedMapToo) { check_chi_square(24, 12, 75.0f); }
TEST(EnvSampling, OnePixelMapIsUniformOverTheSphere) {
  const std::vector<float> rgb = {2.0f, 2.0f, 2.0f};
  aw::PackedEnvironment pe = aw::pack_environment(rgb, 1, 1, 1.0f);
  const RenderParams rp = params_for(1, 1, 0.0f);
  // pdf_uv = 1, so the density is 1 / (2 pi^2 sin theta), which integrates to one over the
  // sphere. The luminance integral takes sin(theta) at the one row's centre (1): 2 * 2 pi^2.
  EXPECT_NEAR(pe.luminance_integral, 2.0 * 2.0 * M_PI * M_PI, 1e-5);
  float pdf;
  uint texel;
  float3 d = env_sample(pe.buffer.data(), &rp, make_float2(0.3f, 0.7f), &pdf, &texel);
  EXPECT_EQ(texel, 0u);
  EXPECT_NEAR(pdf, env_pdf(pe.buffer.data(), &rp, d), 1e-4f * pdf);
  float3 c = env_radiance(pe.buffer.data(), &rp, make_float3(0.0f, 1.0f, 0.0f));
  EXPECT_EQ(c.x, 2.0f);
}

TEST(EnvSampling, MappingFixedPoints) {
  // 4 x 2: u = 0.5 looks along -Z, u grows towards +X, the top row is +Y.
  std::vector<float> rgb(4 * 2 * 3, 0.0f);
  for (int t = 0; t < 8; ++t) rgb[3 * t] = float(t);  // red = texel index
  aw::PackedEnvironment pe = aw::pack_environment(rgb, 4, 2, 1.0f);
  const float* env = pe.buffer.data();
  RenderParams rp = params_for(4, 2, 0.0f);
  auto texel_of = [&](const RenderParams& r, float x, float y, float z) {
    return int(env_radiance(env, &r, normalize(make_float3(x, y, z))).x);
  };
  // Column centres phi = -3pi/4, -pi/4, pi/4, 3pi/4, with d = (sin phi, y, -cos phi).
  const float a = 0.70710678f;
  EXPECT_EQ(texel_of(rp, -a, 0.3f, a), 0);
  EXPECT_EQ(texel_of(rp, -a, 0.3f, -a), 1);
  EXPECT_EQ(texel_of(rp, a, 0.3f, -a), 2);
  EXPECT_EQ(texel_of(rp, a, 0.3f, a), 3);
  EXPECT_EQ(texel_of(rp, a, -0.3f, a), 7);  // lower row
  // Rotation by +90 degrees about +Y (right-handed) carries the map's -Z to the world's -X:
  // the texel seen along map direction (a, 0.3, -a) is now seen along (-a, 0.3, -a).
  RenderParams r90 = params_for(4, 2, 90.0f);
  EXPECT_EQ(texel_of(r90, -a, 0.3f, -a), 2);
  EXPECT_EQ(texel_of(r90, a, 0.3f, -a), 3);
}

}  // namespace
