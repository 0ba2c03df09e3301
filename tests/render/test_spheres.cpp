// Analytic spheres (issue 14): a "sphere" object is one primitive in the flattened BVH (and an
// Embree user geometry in the scalar path) unless "segments", a non-similarity transform or
// light sampling ask for the tessellation. The image matches the finely tessellated sphere's,
// the wavefront matches the scalar path per pixel, and the loader decides as documented.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "host/render/render.h"
#include "host/render/scene_pack.h"
#include "host/scene/scene.h"
#include "tests/render/render_test_util.h"

namespace {

aw::RenderOptions quiet() { return aw_test::quiet_options(); }

// Three spheres (Lambert with a checker, glossy anisotropic GGX, glass) on a floor under a
// quad light; `segments` empty for analytic spheres, else each sphere's tessellation.
std::string spheres_scene(const std::string& segments) {
  const std::string seg = segments.empty() ? "" : R"(, "segments": )" + segments;
  return aw_test::write_temp_scene("spheres", R"({
    "render": { "width": 96, "height": 64, "spp": 16, "max_depth": 6 },
    "camera": { "position": [0, 1.2, 5], "look_at": [0, 0.5, 0], "fov": 35 },
    "environment": { "type": "constant", "color": [0.1, 0.1, 0.12] },
    "lights": [ { "type": "quad", "corner": [-1, 3, -1], "edge_u": [2, 0, 0], "edge_v": [0, 0, 2], "intensity": 8 } ],
    "textures": { "checks": { "type": "checker", "scale": [16, 8], "color1": [0.8, 0.7, 0.6], "color2": [0.2, 0.3, 0.5] } },
    "materials": {
      "floor": { "diffuse": { "color": 0.5 }, "reflection": { "weight": 0 } },
      "clay": { "diffuse": { "color": { "texture": "checks" } }, "reflection": { "weight": 0 } },
      "brushed": { "diffuse": { "color": 0.1 }, "metal": true, "reflection": { "weight": 1, "glossiness": 0.7 },
                   "anisotropy": { "amount": 0.7, "orientation": "tangent" } },
      "glass": { "diffuse": { "weight": 0 }, "reflection": { "weight": 1 }, "refraction": { "weight": 1, "ior": 1.5 } }
    },
    "objects": [
      { "shape": "quad", "corner": [-4, 0, 4], "edge_u": [8, 0, 0], "edge_v": [0, 0, -8], "material": "floor" },
      { "shape": "sphere", "center": [-1.2, 0.5, 0], "radius": 0.5, "material": "clay" )" + seg + R"( },
      { "shape": "sphere", "center": [0, 0.5, -0.3], "radius": 0.5, "material": "brushed",
        "transform": { "rotate": [20, 30, 0] } )" + seg + R"( },
      { "shape": "sphere", "center": [1.2, 0.5, 0], "radius": 0.5, "material": "glass" )" + seg + R"( }
    ]
  })");
}

double mean(const aw::RenderResult& r) { return aw_test::image_mean(r); }

// The same scene with analytic spheres and with spheres of 256 x 128 segments (65,000
// triangles each: the facets depart from the sphere by 7e-5 of its radius, about 1/700 of a
// pixel here), the same random numbers: the images agree except where the facets move an edge
// or a refracted ray. Measured with 1024 x 512 segments: means equal to 6 digits, every pixel
// within 5%; the tolerance is 2e-3 on the means and 90% of the pixels.
TEST(Spheres, AnalyticMatchesFinelyTessellated) {
  aw::Scene a = aw::load_scene(spheres_scene(""));
  aw::Scene t = aw::load_scene(spheres_scene("[256, 128]"));
  ASSERT_EQ(a.spheres.size(), 3u);
  ASSERT_EQ(t.spheres.size(), 0u);
  aw::RenderResult ra = aw::render_wavefront(a, quiet()), rt = aw::render_wavefront(t, quiet());
  aw::ImageDiff d = aw::compare_images(ra.image(a), rt.image(t), 0.05, 1e-3);
  std::printf("analytic %.6f, tessellated %.6f, %.2f%% of pixels within 5%%\n", mean(ra), mean(rt),
              d.frac_pixels_within * 100);
  EXPECT_NEAR(mean(ra) / mean(rt), 1.0, 2e-3);
  EXPECT_GE(d.frac_pixels_within, 0.9);
  EXPECT_EQ(ra.stats.bad_samples, 0u);
  EXPECT_EQ(ra.stats.spheres, 3u);
  EXPECT_EQ(ra.stats.triangles, 2u);
}

TEST(Spheres, KernelMatchesScalar) {
  // Glass, GGX and Lambert spheres (the textured scene's bumped sphere: Texture.*).
  aw_test::expect_kernel_matches_scalar("scenes/bench/race_spheres.json",
                                        {"render.width=64", "render.height=40", "render.spp=8"});
}

// The loader keeps a sphere analytic under a similarity, with its frame and radius carried
// through the transform, and tessellates it for "segments", a non-uniform scale, a mirroring
// transform or light sampling.
TEST(Spheres, LoaderKeepsSimilaritiesAnalytic) {
  const std::string path = aw_test::write_temp_scene("sphere_load", R"({
    "materials": { "m": {}, "hot": { "incandescent": { "color": [1, 1, 1] } } },
    "objects": [
      { "shape": "sphere", "center": [1, 0, 0], "radius": 0.5, "material": "m",
        "transform": { "translate": [0, 2, 0], "rotate": [0, 90, 0], "scale": 2 } },
      { "shape": "sphere", "material": "m", "segments": [8, 4] },
      { "shape": "sphere", "material": "m", "transform": { "scale": [1, 2, 1] } },
      { "shape": "sphere", "material": "m", "transform": { "scale": [-1, 1, 1] } },
      { "shape": "sphere", "material": "hot", "light_sampling": true }
    ]
  })");
  aw::Scene s = aw::load_scene(path);
  ASSERT_EQ(s.spheres.size(), 1u);
  ASSERT_EQ(s.meshes.size(), 4u);
  const aw::SphereDesc& sd = s.spheres[0];
  // scale 2, then rotate 90 degrees about Y ((1, 0, 0) -> (0, 0, -1)), then translate.
  EXPECT_NEAR(sd.center.x, 0.0f, 1e-6);
  EXPECT_NEAR(sd.center.y, 2.0f, 1e-6);
  EXPECT_NEAR(sd.center.z, -2.0f, 1e-6);
  EXPECT_FLOAT_EQ(sd.radius, 1.0f);
  EXPECT_NEAR(sd.axis_x.z, -1.0f, 1e-6);
  EXPECT_NEAR(sd.axis_y.y, 1.0f, 1e-6);
  EXPECT_EQ(s.meshes[0].indices.size(), 8u * 6u);  // 8 x 4 segments
  // The packed scene: one vertex and one marked TriangleInfo after the triangles.
  aw::PackedScene p = aw::pack_scene(s, nullptr);
  ASSERT_EQ(p.soup.spheres.size(), 1u);
  EXPECT_EQ(p.tri_info.size(), p.soup.indices.size() + 1);
  EXPECT_EQ(p.tri_info.back().v[1], uint32_t(AW_SPHERE_MARK));
  EXPECT_TRUE(p.features.on[aw::FeatureSet::SPHERE]);
  // A build without the sphere test refuses the scene rather than render spheres as triangles.
  aw::RenderOptions o = quiet();
  o.force_off = {"SPHERE"};
  EXPECT_THROW(aw::render_wavefront(s, o), std::exception);
}

}  // namespace
