// End-to-end tests of the two renderers: the wavefront (OpenCL on device 0, PoCL in CI) and
// the host scalar path (same kernel headers, Embree rays).
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <numeric>
#include <string>
#include <vector>

#include "host/film/image_io.h"
#include "host/render/render.h"
#include "host/scene/scene.h"
#include "tests/render/render_test_util.h"

namespace {

std::string src(const std::string& rel) { return std::string(ARCHWAVE_SOURCE_DIR) + "/" + rel; }

using aw_test::image_mean;
using aw_test::quiet_options;

// Kernel vs scalar on the default scene: the two consume the same random numbers and sum
// each pixel in the same order, so they agree per pixel, except where float differences
// between Embree's and our traversal (or device vs host libm) flip a branch on a path.
// Thresholds are the issue's: >= 99% of pixels within 1e-3 relative, mean within 0.1%.
TEST(KernelVsScalar, CornellBoxAgreesPerPixel) {
  aw::Scene scene = aw::load_scene(src("scenes/cornell.json"), {"render.width=160", "render.height=160", "render.spp=16"});
  aw::RenderResult w = aw::render_wavefront(scene, quiet_options());
  aw::RenderResult s = aw::render_scalar(scene, quiet_options());
  aw::Image iw = w.image(scene), is = s.image(scene);
  // abs_floor: a pixel whose value is below 1e-4 of the image's brightest is compared
  // absolutely (a relative test of two near-zero numbers measures only noise).
  aw::ImageDiff d = aw::compare_images(iw, is, 1e-3, 1e-4);
  std::printf("cornell: %.4f%% of pixels within 1e-3, means %.6f vs %.6f\n", d.frac_pixels_within * 100,
              d.mean_a, d.mean_b);
  EXPECT_GE(d.frac_pixels_within, 0.99) << "only " << d.frac_pixels_within * 100 << "% of pixels agree";
  EXPECT_LE(d.rel_mean_diff, 1e-3) << "means " << d.mean_a << " vs " << d.mean_b;
  EXPECT_EQ(w.stats.bad_samples, 0u);
  EXPECT_EQ(s.stats.bad_samples, 0u);
  // Same paths: the ray counts agree to within the few paths that diverged.
  double rays_w = double(w.stats.closest_rays), rays_s = double(s.stats.closest_rays);
  EXPECT_NEAR(rays_w / rays_s, 1.0, 1e-3);
}

TEST(KernelVsScalar, MeshSceneAgreesPerPixel) {
  aw::Scene scene = aw::load_scene(src("scenes/knot.json"), {"render.width=120", "render.height=90", "render.spp=8"});
  aw::RenderResult w = aw::render_wavefront(scene, quiet_options());
  aw::RenderResult s = aw::render_scalar(scene, quiet_options());
  aw::ImageDiff d = aw::compare_images(w.image(scene), s.image(scene), 1e-3, 1e-4);
  std::printf("knot: %.4f%% of pixels within 1e-3, means %.6f vs %.6f\n", d.frac_pixels_within * 100,
              d.mean_a, d.mean_b);
  EXPECT_GE(d.frac_pixels_within, 0.99);
  EXPECT_LE(d.rel_mean_diff, 1e-3);
}

// Inside a closed diffuse sphere of albedo rho and radius R with a point light of intensity I
// at its centre, every wall point receives E = I / R^2 directly, and the multiply-scattered
// radiance is uniform, so L = rho/pi (E + pi L)  =>  L = rho I / (pi R^2 (1 - rho)).
// With rho = 0.5, R = 1, I = pi the exact answer is L = 1 everywhere. The sphere is
// tessellated (256 x 128 facets: the facet planes sit at most 1 - cos(pi/128) = 3e-4 inside
// the sphere), so 1% covers geometry and noise (the std. error of the mean at 64 spp over
// 4096 pixels is ~0.1%).
void check_sphere_interior(const aw::RenderResult& r, const char* who) {
  double mean = image_mean(r);
  std::printf("%s: mean radiance inside the sphere %.5f (exact 1)\n", who, mean);
  EXPECT_NEAR(mean, 1.0, 0.01) << who;
  // And no region is off: 8x8 blocks are within 5% (each block's noise is ~1%).
  for (int by = 0; by < r.height; by += 8)
    for (int bx = 0; bx < r.width; bx += 8) {
      double s = 0.0;
      int n = 0;
      for (int y = by; y < by + 8; ++y)
        for (int x = bx; x < bx + 8; ++x) {
          size_t p = size_t(y) * r.width + x;
          for (int c = 0; c < 3; ++c) s += r.sum[p * 3 + c] / r.count[p];
          n += 3;
        }
      EXPECT_NEAR(s / n, 1.0, 0.05) << who << " block " << bx << "," << by;
    }
}

TEST(Analytic, InsideDiffuseSphereWavefront) {
  aw::Scene scene = aw::load_scene(src("tests/render/data/sphere_interior.json"));
  check_sphere_interior(aw::render_wavefront(scene, quiet_options()), "wavefront");
}

TEST(Analytic, InsideDiffuseSphereScalar) {
  aw::Scene scene = aw::load_scene(src("tests/render/data/sphere_interior.json"));
  check_sphere_interior(aw::render_scalar(scene, quiet_options()), "scalar");
}

// The global cut-off (render.cutoff) is Russian roulette with survival throughput / cutoff:
// unbiased, so a harsh 0.3 (paths inside the sphere carry 0.5^k) keeps the exact answer.
TEST(Analytic, InsideDiffuseSphereWithAHarshCutoffStaysExact) {
  aw::Scene scene = aw::load_scene(src("tests/render/data/sphere_interior.json"), {"render.cutoff=0.3"});
  check_sphere_interior(aw::render_wavefront(scene, quiet_options()), "wavefront, cutoff 0.3");
}

// render.clamp bounds every sample's largest channel (biased, off by default). Inside the
// sphere every sample is at least the direct light's 0.5: clamped at 0.25 each is exactly it.
TEST(Analytic, ClampBoundsEverySample) {
  EXPECT_EQ(aw::load_scene(src("tests/render/data/sphere_interior.json")).render.clamp, 0.0f);
  aw::Scene scene = aw::load_scene(src("tests/render/data/sphere_interior.json"), {"render.clamp=0.25"});
  aw::RenderResult r = aw::render_wavefront(scene, quiet_options());
  for (size_t p = 0; p < r.count.size(); ++p)
    for (int c = 0; c < 3; ++c) ASSERT_FLOAT_EQ(r.sum[p * 3 + c] / float(r.count[p]), 0.25f) << "pixel " << p;
}

bool same_bits(const aw::RenderResult& a, const aw::RenderResult& b) {
  return a.sum.size() == b.sum.size() && std::memcmp(a.sum.data(), b.sum.data(), a.sum.size() * 4) == 0 &&
         a.count == b.count;
}

// Same seed and device: bit-identical, whatever the pool and batch sizes (the film's
// summation order is fixed by the job order, see host/render/wavefront.cpp).
TEST(Determinism, SameSeedBitIdenticalAcrossPoolSizes) {
  aw::Scene scene = aw::load_scene(src("scenes/cornell.json"), {"render.width=96", "render.height=96", "render.spp=8"});
  aw::RenderOptions a = quiet_options();
  aw::RenderResult r1 = aw::render_wavefront(scene, a);
  aw::RenderResult r2 = aw::render_wavefront(scene, a);
  EXPECT_TRUE(same_bits(r1, r2));
  aw::RenderOptions b = quiet_options();
  b.pool_size = 1000;  // not a multiple of anything in particular; padded to the work-group
  b.max_batch = 7777;  // batches that start mid-image
  aw::RenderResult r3 = aw::render_wavefront(scene, b);
  EXPECT_TRUE(same_bits(r1, r3));
  // The batch ring (wavefront.cpp, run_jobs) with batches far smaller than the pool, one path
  // per work-item: both halves of the ring are busy most of the time, and the free slots that
  // regenerate leaves stay queued for the next batch (kernels.cl takes the FREE queue's last
  // entries); every job lands in the film once.
  aw::RenderOptions c = quiet_options();
  c.lanes = false;
  c.pool_size = 1024;
  c.max_batch = 100;
  aw::RenderResult r4 = aw::render_wavefront(scene, c);
  EXPECT_EQ(r4.stats.samples, 96u * 96u * 8u);
  EXPECT_TRUE(same_bits(r1, r4));
}

// Dense launches (a queue consumed in slot order by one work-item per pool slot, see
// host/render/wavefront.cpp) and queue launches process the same paths: bit-identical films
// whether every stage that can runs dense, none does, or the default threshold decides. The
// every-lobe scene with a cutout material covers all queues, pass-through included, and a
// small pool leaves some queues nearly empty and others full.
TEST(Determinism, DenseAndQueueLaunchesBitIdentical) {
  struct Case {
    const char* scene;
    std::vector<std::string> defs;
  };
  const Case cases[] = {
      {"scenes/cornell.json", {"render.width=64", "render.height=64", "render.spp=4"}},
      {"scenes/materials.json",
       {"render.width=64", "render.height=32", "render.spp=4", "materials.leaf.cutout_opacity=0.3"}},
  };
  for (const Case& c : cases) {
    aw::Scene scene = aw::load_scene(src(c.scene), c.defs);
    aw::RenderOptions dflt = quiet_options();
    dflt.pool_size = 2048;
    aw::RenderOptions dense = dflt, queued = dflt;
    dense.dense_fraction = 0.0;
    queued.dense_fraction = 2.0;
    aw::RenderResult r_default = aw::render_wavefront(scene, dflt);
    aw::RenderResult r_dense = aw::render_wavefront(scene, dense);
    aw::RenderResult r_queued = aw::render_wavefront(scene, queued);
    EXPECT_GT(image_mean(r_default), 0.0) << c.scene;
    EXPECT_TRUE(same_bits(r_default, r_dense)) << c.scene;
    EXPECT_TRUE(same_bits(r_default, r_queued)) << c.scene;
  }
}

TEST(Determinism, DifferentSeedsDiffer) {
  aw::Scene s1 = aw::load_scene(src("scenes/cornell.json"), {"render.width=64", "render.height=64", "render.spp=4"});
  aw::Scene s2 = aw::load_scene(src("scenes/cornell.json"),
                                {"render.width=64", "render.height=64", "render.spp=4", "render.seed=7"});
  aw::RenderResult r1 = aw::render_wavefront(s1, quiet_options());
  aw::RenderResult r2 = aw::render_wavefront(s2, quiet_options());
  EXPECT_FALSE(same_bits(r1, r2));
  // ...but they estimate the same image.
  EXPECT_NEAR(image_mean(r1) / image_mean(r2), 1.0, 0.03);
}

// Also through the CLI and the EXR file: the written file is bit-identical.
TEST(Determinism, ExrFilesBitIdentical) {
  std::string bin = ARCHWAVE_BINARY;
  std::string dir = testing::TempDir() + "/det_" + std::to_string(getpid());
  std::system(("mkdir -p " + dir).c_str());
  auto run = [&](const std::string& out, const std::string& extra) {
    std::string cmd = bin + " " + src("scenes/cornell.json") + " --width 48 --height 48 --spp 4 -q -o " + out + " " +
                      extra + " 2>/dev/null";
    return std::system(cmd.c_str());
  };
  ASSERT_EQ(run(dir + "/a.exr", ""), 0);
  ASSERT_EQ(run(dir + "/b.exr", ""), 0);
  ASSERT_EQ(run(dir + "/c.exr", "--seed 3"), 0);
  aw::Image a = aw::read_exr(dir + "/a.exr"), b = aw::read_exr(dir + "/b.exr"), c = aw::read_exr(dir + "/c.exr");
  EXPECT_EQ(a.rgb, b.rgb);
  EXPECT_NE(a.rgb, c.rgb);
  EXPECT_EQ(a.int_attrs["spp"], 4);
  EXPECT_EQ(a.int_attrs["seed"], 0);
  EXPECT_EQ(c.int_attrs["seed"], 3);
}

}  // namespace
