// Per-lobe samples split at the first hit (docs/material.md §6, kernels/integrator/split.h):
// the split count, when the kernels split at all, that splitting is unbiased, and that the
// wavefront and the scalar path (and the specialised and generic builds) still agree.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "host/film/image_io.h"
#include "host/render/features.h"
#include "host/render/render.h"
#include "host/render/scene_pack.h"
#include "host/scene/scene.h"
#include "tests/render/render_test_util.h"
#include "kernels/integrator/split.h"

namespace {

std::string src(const std::string& rel) { return std::string(ARCHWAVE_SOURCE_DIR) + "/" + rel; }

// The documentation's glossy Fresnel example: reflection glossiness 0.6, samples 64.
aw::Scene glossy(int spp, bool splitting = true, int seed = 0, int w = 64, int h = 48,
                 std::vector<std::string> more = {}) {
  std::vector<std::string> o = {"render.width=" + std::to_string(w), "render.height=" + std::to_string(h),
                                "render.spp=" + std::to_string(spp), "render.seed=" + std::to_string(seed),
                                std::string("render.lobe_splitting=") + (splitting ? "true" : "false")};
  o.insert(o.end(), more.begin(), more.end());
  return aw::load_scene(src("scenes/docs/glossy_fresnel.json"), o);
}

aw::RenderOptions quiet() {
  aw::RenderOptions o;
  o.progress = false;
  return o;
}

TEST(Splitting, CountIsRoundedSamplesOverSpp) {
  EXPECT_EQ(split_count(64, 4), 16u);
  EXPECT_EQ(split_count(8, 64), 1u);    // samples < spp: one ray (max(1, round(1/8)))
  EXPECT_EQ(split_count(64, 128), 1u);  // 0.5 rounds up to 1
  EXPECT_EQ(split_count(96, 64), 2u);   // 1.5 rounds up to 2
  EXPECT_EQ(split_count(80, 64), 1u);   // 1.25 rounds to 1
  EXPECT_EQ(split_count(0, 4), 1u);
  EXPECT_EQ(split_count(7, 0), 1u);
  EXPECT_EQ(split_count(4000000u, 1), AW_SPLIT_MAX);
}

TEST(Splitting, KernelsSplitOnlyWhenSomeLobeDoes) {
  auto split_spp = [](const aw::Scene& s) { return aw::pack_scene(s, nullptr).params.split_spp; };
  auto has = [](const aw::Scene& s) { return aw::pack_scene(s, nullptr).features.on[aw::FeatureSet::SPLIT]; };
  EXPECT_EQ(split_spp(glossy(4)), 4u);  // 64 samples at 4 spp: 16 rays
  EXPECT_TRUE(has(glossy(4)));
  EXPECT_EQ(split_spp(glossy(4, false)), 0u);  // render.lobe_splitting = false
  EXPECT_FALSE(has(glossy(4, false)));
  EXPECT_EQ(split_spp(glossy(128)), 0u);  // round(64 / 128) = 1: nothing to split
  // Default samples (8) at the Cornell box's spp: no lobe has samples at all there.
  EXPECT_FALSE(has(aw::load_scene(src("scenes/cornell.json"))));
}

// Same random numbers, same summation order (split 0, 1, …, n-1 of a job, then the jobs in
// sample order): the two renderers agree per pixel as they do without splitting.
TEST(Splitting, KernelAndScalarAgree) {
  aw::Scene s = glossy(4);
  aw::RenderResult w = aw::render_wavefront(s, quiet());
  aw::RenderResult c = aw::render_scalar(s, quiet());
  aw::ImageDiff d = aw::compare_images(w.image(s), c.image(s), 1e-3, 1e-4);
  std::printf("split glossy: %.4f%% of pixels within 1e-3, rays %llu vs %llu\n", d.frac_pixels_within * 100,
              (unsigned long long)w.stats.closest_rays, (unsigned long long)c.stats.closest_rays);
  EXPECT_GE(d.frac_pixels_within, 0.99);
  // The splits were traced: many more closest rays than one path per sample would need.
  aw::RenderResult u = aw::render_scalar(glossy(4, false), quiet());
  EXPECT_GT(double(c.stats.closest_rays), 1.5 * double(u.stats.closest_rays));
}

// The film does not depend on the pool or batch size, with splits in flight too.
TEST(Splitting, BitIdenticalAcrossPoolSizes) {
  aw::Scene s = glossy(4);
  aw::RenderResult a = aw::render_wavefront(s, quiet());
  aw::RenderOptions small = quiet();
  small.pool_size = 1000;
  small.max_batch = 777;
  aw::RenderResult b = aw::render_wavefront(s, small);
  ASSERT_EQ(a.sum.size(), b.sum.size());
  size_t differ = 0;
  for (size_t i = 0; i < a.sum.size(); ++i) differ += a.sum[i] != b.sum[i];
  EXPECT_EQ(differ, 0u);
}

TEST(Splitting, SpecialisedAndGenericAgreeAndMissingSplitFails) {
  aw::Scene s = glossy(4, true, 0, 32, 24);
  aw::RenderOptions gen = quiet();
  gen.generic_kernels = true;
  aw::RenderResult a = aw::render_wavefront(s, quiet()), b = aw::render_wavefront(s, gen);
  size_t differ = 0;
  for (size_t i = 0; i < a.sum.size(); ++i) differ += a.sum[i] != b.sum[i];
  EXPECT_EQ(differ, 0u);
  aw::RenderOptions off = quiet();
  off.force_off = {"SPLIT"};
  EXPECT_THROW(aw::render_wavefront(s, off), std::logic_error);
}

// Unbiased: splitting (16 spp x 16 reflection rays) and plain path tracing (256 spp), with
// different seeds, converge to the same image. The sphere is made a pure glossy reflector
// (facing 1: all its energy goes through the split lobe) so a weighting error shows. Pixels
// are independent (their random streams differ), so the mean of the per-pixel differences
// over N pixels is ~normal with standard error sd / sqrt(N): two-sided z test at
// significance 1e-4 (|z| < 3.89). Weighting the splits 1/(n-1) instead of 1/n (a 6.7% error
// on the sphere) gives |z| ~ 11 here: checked by mutating split_next.
TEST(Splitting, Unbiased) {
  std::vector<std::string> mirror = {"materials.s.reflection.fresnel.facing=1", "materials.s.reflection.samples=256"};
  aw::Scene a_scene = glossy(16, true, 11, 128, 96, mirror), b_scene = glossy(256, false, 12, 128, 96, mirror);
  aw::RenderResult a = aw::render_scalar(a_scene, quiet());
  aw::RenderResult b = aw::render_scalar(b_scene, quiet());
  double z = aw_test::mean_difference_z(a, b, "split vs unsplit");
  EXPECT_LT(std::fabs(z), 3.89);
}

}  // namespace
