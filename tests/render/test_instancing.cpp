// Instancing (issue 14): meshes placed several times are stored once and traversed through a
// two-level BVH (kernels/bvh/traverse.h; Embree's instances in the scalar path). The image
// matches the flattened equivalent (render.instancing false), the wavefront matches the scalar
// path per pixel, the loader shares and places as documented (docs/scene-format.md#instancing),
// and memory grows with placements by bytes, not triangles.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "host/bvh/flat_bvh.h"
#include "host/render/render.h"
#include "host/render/scene_pack.h"
#include "host/scene/scene.h"
#include "tests/render/render_test_util.h"

namespace {

aw::RenderOptions quiet() { return aw_test::quiet_options(); }

double mean(const aw::RenderResult& r) { return aw_test::image_mean(r); }

const std::vector<std::string> kSmall = {"render.width=96", "render.height=54", "render.spp=8"};

// scenes/instancing.json (cups and knots placed with rotations, non-uniform scales, mirrors, a
// material override and two mesh objects that share) against the same scene with every
// placement flattened into a mesh of its own, the same random numbers. The two differ only in
// float rounding of the vertices (object space carried by the instance's float transform vs
// the file's doubles carried at load), so paths agree except where that last bit moves an edge
// or a refracted ray. Measured: 99.6% of pixels within 5% and the means within 2e-4; the
// tolerances are 97% and 2e-3.
TEST(Instancing, SameImageAsFlattened) {
  std::vector<std::string> flat_ovr = kSmall;
  flat_ovr.push_back("render.instancing=false");
  aw::Scene a = aw::load_scene(aw_test::source_path("scenes/instancing.json"), kSmall);
  aw::Scene f = aw::load_scene(aw_test::source_path("scenes/instancing.json"), flat_ovr);
  ASSERT_EQ(a.instances.size(), 8u);
  ASSERT_EQ(a.prototypes.size(), 4u);  // meshes.cup, with glass, meshes.knot, the two mesh objects' cup
  ASSERT_EQ(f.instances.size(), 0u);
  ASSERT_EQ(f.meshes.size(), 9u);  // the floor and the eight placements
  EXPECT_EQ(a.rendered_triangle_count(), f.triangle_count());
  aw::RenderResult ra = aw::render_wavefront(a, quiet()), rf = aw::render_wavefront(f, quiet());
  aw::ImageDiff d = aw::compare_images(ra.image(a), rf.image(f), 0.05, 1e-3);
  std::printf("instanced %.6f, flattened %.6f, %.2f%% of pixels within 5%%\n", mean(ra), mean(rf),
              d.frac_pixels_within * 100);
  EXPECT_NEAR(mean(ra) / mean(rf), 1.0, 2e-3);
  EXPECT_GE(d.frac_pixels_within, 0.97);
  EXPECT_EQ(ra.stats.bad_samples, 0u);
  EXPECT_EQ(ra.stats.instances, 8u);
  EXPECT_EQ(ra.stats.instanced_triangles, f.triangle_count());
  EXPECT_LT(ra.stats.scene_bytes, rf.stats.scene_bytes);
}

TEST(Instancing, KernelMatchesScalar) { aw_test::expect_kernel_matches_scalar("scenes/instancing.json", kSmall); }

// A build without the instance branch refuses an instanced scene rather than render it without
// its instances.
TEST(Instancing, BuildWithoutInstancesRefusesTheScene) {
  aw::Scene s = aw::load_scene(aw_test::source_path("scenes/instancing.json"), kSmall);
  aw::RenderOptions o = quiet();
  o.force_off = {"INSTANCE"};
  EXPECT_THROW(aw::render_wavefront(s, o), std::exception);
}

std::string cup_path() { return aw_test::source_path("scenes/meshes/cup.obj"); }

// The loader: "meshes" entries placed by "instance" objects (the entry's transform first, then
// the instance's), one prototype per (mesh, material), mesh objects that differ only in their
// transform shared, light-sampled ones and single ones not, and render.instancing false.
TEST(Instancing, LoaderSharesAndPlaces) {
  const std::string cup = cup_path();
  const std::string path = aw_test::write_temp_scene("instancing_load", R"({
    "materials": { "m": {}, "g": {}, "hot": { "incandescent": { "color": [1, 1, 1] } } },
    "meshes": {
      "cup": { "file": ")" + cup + R"(", "material": "m", "transform": { "scale": 2 } },
      "unused": { "file": ")" + cup + R"(" }
    },
    "objects": [
      { "shape": "instance", "mesh": "cup", "transform": { "translate": [10, 0, 0] } },
      { "shape": "instance", "mesh": "cup" },
      { "shape": "instance", "mesh": "cup", "material": "g" },
      { "shape": "mesh", "file": ")" + cup + R"(", "material": "m", "transform": { "translate": [0, 5, 0] } },
      { "shape": "mesh", "file": ")" + cup + R"(", "material": "m" },
      { "shape": "mesh", "file": ")" + cup + R"(", "material": "g" },
      { "shape": "mesh", "file": ")" + cup + R"(", "material": "hot", "light_sampling": true },
      { "shape": "mesh", "file": ")" + cup + R"(", "material": "hot", "light_sampling": true }
    ]
  })");
  aw::Scene s = aw::load_scene(path);
  ASSERT_EQ(s.prototypes.size(), 3u);  // meshes.cup, meshes.cup with g, the two shared objects
  ASSERT_EQ(s.instances.size(), 5u);
  EXPECT_EQ(s.meshes.size(), 3u);  // the single "g" object and the two light-sampled ones
  EXPECT_EQ(s.prototypes[0].name, "meshes.cup");
  EXPECT_EQ(s.prototypes[1].name, "meshes.cup with material \"g\"");
  EXPECT_EQ(s.instances[0].name, "objects[0] (instance of meshes.cup)");
  EXPECT_EQ(s.instances[0].prototype, 0u);
  EXPECT_EQ(s.instances[1].prototype, 0u);
  EXPECT_EQ(s.instances[2].prototype, 1u);
  EXPECT_EQ(s.instances[3].prototype, 2u);
  EXPECT_EQ(s.instances[4].prototype, 2u);
  // The entry's scale 2, then the instance's translation.
  EXPECT_DOUBLE_EQ(s.instances[0].transform[0][0], 2.0);
  EXPECT_DOUBLE_EQ(s.instances[0].transform[3][0], 10.0);
  EXPECT_DOUBLE_EQ(s.instances[3].transform[3][1], 5.0);
  const size_t cup_tris = s.prototypes[0].triangle_count();
  EXPECT_EQ(cup_tris, 2496u);
  EXPECT_EQ(s.triangle_count(), 6 * cup_tris);  // three prototypes and three world meshes
  EXPECT_EQ(s.rendered_triangle_count(), 8 * cup_tris);
  bool warned = false;
  for (const std::string& w : s.warnings) warned |= w.find("\"unused\" is defined but no instance places it") != std::string::npos;
  EXPECT_TRUE(warned);
  // The packed soup: world triangles first, each prototype's after them, the instances' transforms.
  aw::PackedScene p = aw::pack_scene(s, nullptr);
  ASSERT_EQ(p.soup.prototypes.size(), 3u);
  EXPECT_EQ(p.soup.world_tris(), 3 * cup_tris);
  EXPECT_EQ(p.soup.prototypes[1].first_tri, 4 * cup_tris);
  ASSERT_EQ(p.soup.instances.size(), 5u);
  EXPECT_FLOAT_EQ(p.soup.instances[0].o2w[3], 10.0f);
  EXPECT_FLOAT_EQ(p.soup.instances[0].w2o[0], 0.5f);
  EXPECT_FLOAT_EQ(p.soup.instances[0].w2o[3], -5.0f);
  EXPECT_TRUE(p.features.on[aw::FeatureSet::INSTANCE]);

  aw::Scene f = aw::load_scene(path, {"render.instancing=false"});
  EXPECT_TRUE(f.prototypes.empty());
  EXPECT_TRUE(f.instances.empty());
  EXPECT_EQ(f.meshes.size(), 8u);
  EXPECT_EQ(f.triangle_count(), 8 * cup_tris);
}

// A mirroring instance keeps its triangles facing out: its winding is reversed in world space,
// which the kernels undo (classify_hit_point's `mirrored`), as the loader does for a flattened
// mirrored mesh. A mesh without normals, so the winding alone decides the outside: the
// refractive cup mirrored and not gives the same image as its flattened equivalent.
// (scenes/instancing.json covers mirrors of meshes with normals.)
TEST(Instancing, MirroredWithoutNormals) {
  const std::string dir = testing::TempDir();
  const std::string obj = dir + "/instancing_tetra.obj";
  {
    std::FILE* fp = std::fopen(obj.c_str(), "w");
    ASSERT_TRUE(fp);
    std::fputs("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n", fp);
    std::fclose(fp);
  }
  const std::string scene = R"({
    "render": { "width": 48, "height": 32, "spp": 8, "max_depth": 8 },
    "camera": { "position": [0, 0.4, 4], "look_at": [0, 0.3, 0], "fov": 40 },
    "environment": { "type": "constant", "color": [0.8, 0.8, 0.8] },
    "materials": { "glass": { "diffuse": { "weight": 0 }, "reflection": { "weight": 1 },
                              "refraction": { "weight": 1, "ior": 1.5,
                                              "fog": { "enable": true, "distance": 0.3 } } } },
    "meshes": { "t": { "file": ")" + obj + R"(", "material": "glass" } },
    "objects": [
      { "shape": "instance", "mesh": "t", "transform": { "translate": [-0.8, 0, 0] } },
      { "shape": "instance", "mesh": "t", "transform": { "scale": [-1, 1, 1], "translate": [0.8, 0, 0] } }
    ]
  })";
  const std::string path = aw_test::write_temp_scene("instancing_mirror", scene);
  aw::Scene a = aw::load_scene(path), f = aw::load_scene(path, {"render.instancing=false"});
  ASSERT_EQ(a.instances.size(), 2u);
  // The scalar path: classify_hit_point is the kernels' own code, and the scalar path needs no
  // kernel build (the wavefront's instance handling is compared with it in KernelMatchesScalar).
  aw::RenderResult ra = aw::render_scalar(a, quiet()), rf = aw::render_scalar(f, quiet());
  aw::ImageDiff d = aw::compare_images(ra.image(a), rf.image(f), 1e-3, 1e-4);
  std::printf("instanced vs flattened: %.2f%% of pixels within 1e-3, means %.6f vs %.6f\n", d.frac_pixels_within * 100,
              d.mean_a, d.mean_b);
  EXPECT_GE(d.frac_pixels_within, 0.98);
  EXPECT_LE(d.rel_mean_diff, 1e-3);
}

// Memory: a placement costs its InstanceGpu (112 B) and its share of the top-level tree, not
// its mesh's triangles (2,496 here, about 250 KB flattened). Measured on the packed scene and
// the flattened BVH, the arrays the device holds.
size_t scene_bytes(const aw::Scene& s) {
  aw::PackedScene p = aw::pack_scene(s, nullptr);
  aw::EmbreeDevice dev;
  aw::FlatBvh bvh = aw::build_flat_bvh(dev, p.soup);
  return aw::packed_arrays_bytes(p) + bvh.nodes.size() * sizeof(BvhNode) + bvh.leaf_tris.size() * sizeof(LeafTriangle) +
         bvh.instances.size() * sizeof(InstanceGpu);
}

std::string grid_scene(int n) {
  std::string objects;
  for (int i = 0; i < n; ++i) {
    objects += std::string(i ? "," : "") + R"({ "shape": "instance", "mesh": "cup", "transform": { "translate": [)" +
               std::to_string(i % 40) + ", 0, " + std::to_string(i / 40) + "] } }";
  }
  return aw_test::write_temp_scene("instancing_grid", R"({
    "materials": { "m": {} },
    "meshes": { "cup": { "file": ")" + cup_path() + R"(", "material": "m" } },
    "objects": [ )" + objects + "]}");
}

TEST(Instancing, MemoryGrowsByBytesPerInstance) {
  const aw::Scene a = aw::load_scene(grid_scene(10)), b = aw::load_scene(grid_scene(1000));
  const size_t ba = scene_bytes(a), bb = scene_bytes(b);
  const double per_instance = double(bb - ba) / 990.0;
  const aw::Scene fa = aw::load_scene(grid_scene(10), {"render.instancing=false"});
  const aw::Scene fb = aw::load_scene(grid_scene(20), {"render.instancing=false"});
  const double per_flattened = double(scene_bytes(fb) - scene_bytes(fa)) / 10.0;
  std::printf("instanced: %zu B for 10 cups, %zu B for 1000: %.0f B per instance; flattened: %.0f B per cup\n", ba, bb,
              per_instance, per_flattened);
  EXPECT_LT(per_instance, 400.0);  // InstanceGpu 112 B + its leaf slot 48 B + its node share
  EXPECT_GT(per_flattened, 200000.0);
}

// Extremes (issue 16): placements scaled by 1e-6 and 1e6, flattened to a sliver (1e-6 along
// one axis), mirrored on every axis, far from the origin (1e6) and overlapping by the hundred at
// one spot, seen by camera, shadow and glossy rays: zero NaN/Inf samples discarded and a finite
// image on the wavefront (generic kernels, shared with the other extremes tests) and the
// scalar path.
TEST(Instancing, ExtremesRenderFinite) {
  std::string objects = R"({ "shape": "quad", "corner": [-5, 0, 5], "edge_u": [10, 0, 0], "edge_v": [0, 0, -10], "material": "m" })";
  const char* transforms[] = {
      R"({ "scale": 1e-6, "translate": [-1, 0.5, 0] })",
      R"({ "scale": 1e6, "translate": [0, 0, -3e6] })",
      R"({ "scale": [1, 1e-6, 1], "translate": [1, 0.5, 0] })",
      R"({ "scale": [-1, -1, -1], "translate": [0, 1, 0.5] })",
      R"({ "translate": [1e6, 0, 0] })",
      R"({ "rotate": [90, 0, 45], "scale": [1e-3, 1e3, 1], "translate": [0.5, 0.5, 1] })"};
  for (const char* t : transforms) objects += std::string(R"(, { "shape": "instance", "mesh": "cup", "transform": )") + t + " }";
  for (int i = 0; i < 100; ++i)
    objects += R"(, { "shape": "instance", "mesh": "cup", "material": "glass", "transform": { "rotate": [0, )" +
               std::to_string(i * 3.6) + R"(, 0], "translate": [-0.5, 0, 0.5] } })";
  const std::string path = aw_test::write_temp_scene("instancing_extremes", R"({
    "render": { "width": 32, "height": 24, "spp": 4, "max_depth": 6 },
    "camera": { "position": [0, 1.5, 3], "look_at": [0, 0.4, 0], "fov": 60 },
    "environment": { "type": "constant", "color": [0.4, 0.4, 0.5] },
    "lights": [ { "type": "sphere", "center": [0, 3, 1], "radius": 0.3, "intensity": 20 } ],
    "materials": { "m": { "reflection": { "weight": 0.5, "glossiness": 0.7 } },
                   "glass": { "diffuse": { "weight": 0 }, "refraction": { "weight": 1, "ior": 1.5 } } },
    "meshes": { "cup": { "file": ")" + cup_path() + R"(", "material": "m" } },
    "objects": [ )" + objects + "]}");
  aw::Scene s = aw::load_scene(path);
  ASSERT_EQ(s.instances.size(), 106u);
  aw::RenderOptions g = quiet();
  g.generic_kernels = true;
  for (bool scalar : {false, true}) {
    aw::RenderResult r = scalar ? aw::render_scalar(s, quiet()) : aw::render_wavefront(s, g);
    EXPECT_EQ(r.stats.bad_samples, 0u) << (scalar ? "scalar" : "wavefront");
    for (float x : r.sum) ASSERT_TRUE(std::isfinite(x)) << (scalar ? "scalar" : "wavefront");
  }
}

}  // namespace
