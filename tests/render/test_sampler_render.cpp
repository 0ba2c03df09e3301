// render.sampler (kernels/common/rng.h) end to end: the Sobol' samplers converge to the same
// image as the independent one, both renderers draw the same numbers with either, and the
// scene key is validated.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "host/render/render.h"
#include "host/render/scene_pack.h"
#include "host/scene/scene.h"
#include "tests/render/render_test_util.h"
#include "kernels/common/rng.h"

namespace {

std::string src(const std::string& rel) { return std::string(ARCHWAVE_SOURCE_DIR) + "/" + rel; }

aw::RenderOptions quiet() {
  aw::RenderOptions o;
  o.progress = false;
  return o;
}

aw::Scene cornell(const std::string& sampler, int spp, int seed, int size) {
  return aw::load_scene(src("scenes/cornell.json"),
                        {"render.width=" + std::to_string(size), "render.height=" + std::to_string(size),
                         "render.spp=" + std::to_string(spp), "render.seed=" + std::to_string(seed),
                         "render.sampler=" + sampler});
}

TEST(Sampler, SceneKeyChoosesTheSampler) {
  EXPECT_EQ(aw::pack_scene(aw::load_scene(src("scenes/cornell.json")), nullptr).params.sampler, AW_SAMPLER_SOBOL);
  EXPECT_EQ(aw::pack_scene(cornell("independent", 1, 0, 8), nullptr).params.sampler, AW_SAMPLER_INDEPENDENT);
  // zsobol also gets its index layout: 48 spp -> blocks of 2^6, a 100 x 60 image inside 128^2.
  aw::Scene z = aw::load_scene(src("scenes/cornell.json"), {"render.width=100", "render.height=60",
                                                            "render.spp=48", "render.sampler=zsobol"});
  RenderParams zp = aw::pack_scene(z, nullptr).params;
  EXPECT_EQ(zp.sampler, AW_SAMPLER_ZSOBOL);
  EXPECT_EQ(zp.sampler_log2_spp, 6u);
  EXPECT_EQ(zp.sampler_bits, 2u * 7u + 6u);
  try {
    cornell("halton", 1, 0, 8);
    FAIL() << "an unknown sampler was accepted";
  } catch (const aw::SceneError& e) {
    std::string m = e.what();
    EXPECT_NE(m.find("render.sampler"), std::string::npos) << m;
    EXPECT_NE(m.find("sobol, zsobol, independent"), std::string::npos) << m;
  }
}

// Unbiased: the Sobol' and the independent sampler, with different seeds, converge to the
// same image. Both decorrelate pixels (every pixel has its own scrambles and shuffles), so
// the mean of the per-pixel differences over N pixels is ~normal with standard error
// sd / sqrt(N): two-sided z test at significance 1e-4 (|z| < 3.89).
TEST(Sampler, SobolIsUnbiasedAgainstIndependent) {
  aw::RenderResult a = aw::render_wavefront(cornell("sobol", 64, 1, 64), quiet());
  aw::RenderResult b = aw::render_wavefront(cornell("independent", 64, 2, 64), quiet());
  double z = aw_test::mean_difference_z(a, b, "sobol vs independent");
  EXPECT_LT(std::fabs(z), 3.89);
}

// The same for zsobol. Its pixels are not independent (neighbours' errors are anti-correlated
// on purpose), which makes the true standard error of the mean difference smaller than
// sd / sqrt(N): the test is conservative (it rejects less often than 1e-4), never too strict.
TEST(Sampler, ZSobolIsUnbiasedAgainstIndependent) {
  aw::RenderResult a = aw::render_wavefront(cornell("zsobol", 64, 1, 64), quiet());
  aw::RenderResult b = aw::render_wavefront(cornell("independent", 64, 2, 64), quiet());
  double z = aw_test::mean_difference_z(a, b, "zsobol vs independent");
  EXPECT_LT(std::fabs(z), 3.89);
}

// With either sampler the wavefront and the scalar path consume the same numbers, so they
// agree per pixel (the threshold of KernelVsScalar.CornellBoxAgreesPerPixel).
TEST(Sampler, KernelAndScalarAgreePerPixelWithEither) {
  for (const char* sampler : {"sobol", "zsobol", "independent"}) {
    aw::Scene s = cornell(sampler, 8, 3, 48);
    aw::RenderResult w = aw::render_wavefront(s, quiet()), c = aw::render_scalar(s, quiet());
    size_t agree = 0, n = w.count.size();
    for (size_t p = 0; p < n; ++p) {
      bool ok = true;
      for (int k = 0; k < 3; ++k) {
        double a = w.sum[p * 3 + k], b = c.sum[p * 3 + k];
        ok = ok && std::fabs(a - b) <= 1e-3 * std::max(std::fabs(a), std::fabs(b)) + 1e-6;
      }
      agree += ok;
    }
    EXPECT_GE(double(agree) / double(n), 0.99) << sampler;
  }
}

}  // namespace
