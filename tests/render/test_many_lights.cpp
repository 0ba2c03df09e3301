// Many lights and mesh lights against closed forms (docs/architecture.md, "Many lights"): as in
// test_lights.cpp a narrow camera looks at the point P = 0 of a white Lambert floor, whose
// radiance is E / pi.
//
//   a grid of sphere lights, radiance L, radius r, centre at distance d and height h above P,
//   each wholly above the horizon:  E = sum  pi L (r/d)^2 (h/d)   (pi L sin^2(alpha) cos(theta))
//   a light-sampled incandescent quad (objects[].light_sampling): Lambert's polygon formula
//   a light-sampled incandescent sphere object (tessellated): the sphere light's formula, to
//   the tessellation's 0.1%
//
// Light selection by the tree (render.light_selection "tree", and "auto" from 16 lights on)
// and by power alone must both give E: the tree changes the noise, not the answer; so must
// BSDF sampling alone (light_sampling false), which the MIS weights make consistent with it.
// 1%, both renderers; the many-lights gallery scene kernel = scalar per pixel.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "host/film/image_io.h"
#include "host/render/render.h"
#include "host/render/scene_pack.h"
#include "host/scene/scene.h"
#include "tests/render/render_test_util.h"

namespace {

const double kPi = 3.14159265358979323846;

std::string floor_with(const std::string& lights, const std::string& objects, const std::string& render) {
  std::string json = R"({
  "render": { "width": 16, "height": 16, "spp": 256, "seed": 4, "max_depth": 1)" + render + R"( },
  "camera": { "position": [0, 0.3, 3], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 0.2 },
  "lights": [ )" + lights + R"( ],
  "materials": { "white": { "diffuse": { "color": [1, 1, 1] }, "reflection": { "weight": 0 } },
                 "lamp": { "diffuse": { "weight": 0 }, "reflection": { "weight": 0 },
                           "incandescent": { "color": [1, 1, 1], "scale": 3 } } },
  "objects": [ { "shape": "quad", "corner": [-50, 0, 50], "edge_u": [100, 0, 0], "edge_v": [0, 0, -100],
                 "material": "white" } )" + objects + R"( ]
})";
  return aw_test::write_temp_scene("many_lights", json);
}

double mean_green(const aw::RenderResult& r) {
  double s = 0.0;
  for (size_t p = 0; p < r.count.size(); ++p) s += r.sum[p * 3 + 1] / r.count[p];
  return s / double(r.count.size());
}

void expect_radiance(const std::string& path, const std::vector<std::string>& overrides, double expected,
                     const std::string& what) {
  aw::Scene scene = aw::load_scene(path, overrides);
  aw::RenderOptions o;
  aw::RenderResult rw = aw::render_wavefront(scene, o);
  aw::RenderResult rs = aw::render_scalar(scene, o);
  const double w = mean_green(rw), s = mean_green(rs);
  std::printf("%-52s expected %.6f  wavefront %.6f  scalar %.6f\n", what.c_str(), expected, w, s);
  EXPECT_NEAR(w / expected, 1.0, 0.01) << what << " (wavefront)";
  EXPECT_NEAR(s / expected, 1.0, 0.01) << what << " (scalar)";
  EXPECT_EQ(rw.stats.bad_samples, 0u) << what;
}

TEST(ManyLights, GridOfSphereLightsWithTreeAndWithPower) {
  // 8 x 8 spheres of radius 0.05 at height 1, 0.4 apart, and radiance 2.
  std::string lights;
  double e = 0.0;
  const double r = 0.05, h = 1.0, L = 2.0;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j) {
      const double x = -1.4 + 0.4 * i, z = -1.4 + 0.4 * j;
      char buf[160];
      std::snprintf(buf, sizeof buf, R"(%s{ "type": "sphere", "center": [%g, %g, %g], "radius": %g, "intensity": %g })",
                    lights.empty() ? "" : ", ", x, h, z, r, L);
      lights += buf;
      const double d2 = x * x + h * h + z * z, d = std::sqrt(d2);
      e += kPi * L * (r * r / d2) * (h / d);
    }
  const std::string path = floor_with(lights, "", "");
  aw::PackedScene auto_pack = aw::pack_scene(aw::load_scene(path), nullptr);
  EXPECT_TRUE(auto_pack.features.on[aw::FeatureSet::LIGHT_TREE]) << "64 lights: the tree by default";
  EXPECT_EQ(auto_pack.light_tree.size(), 127u);
  expect_radiance(path, {}, e / kPi, "64 spheres, light tree (auto)");
  expect_radiance(path, {"render.light_selection=power"}, e / kPi, "64 spheres, by power");
}

TEST(ManyLights, TreeWithFewLightsAndASun) {
  // The tree beside a light at infinity (chosen between by power), forced on for three lights.
  const std::string lights = R"({ "type": "point", "position": [0, 1, 0], "intensity": 1 },
    { "type": "point", "position": [1, 1, 0], "intensity": 2 },
    { "type": "sphere", "center": [0, 1, 1], "radius": 0.1, "intensity": 4 },
    { "type": "sun", "direction": [0, -1, 0], "angle": 1, "intensity": 0.5 })";
  const double e = 1.0 / 1.0 + 2.0 * (1.0 / 2.0) * (1.0 / std::sqrt(2.0)) + kPi * 4.0 * (0.01 / 2.0) / std::sqrt(2.0) + 0.5;
  const std::string path = floor_with(lights, "", "");
  expect_radiance(path, {"render.light_selection=tree"}, e / kPi, "3 lights in a tree, and a sun");
  expect_radiance(path, {}, e / kPi, "3 lights and a sun by power");
}

TEST(ManyLights, LightSampledMeshQuadMatchesLambertsFormula) {
  const std::string quad = R"(, { "shape": "quad", "corner": [0.2, 0.7, -0.3], "edge_u": [1, 0, 0], "edge_v": [0, 0, 0.5],
                                  "material": "lamp", "light_sampling": true })";
  const std::vector<glm::dvec3> v = {{0.2, 0.7, -0.3}, {1.2, 0.7, -0.3}, {1.2, 0.7, 0.2}, {0.2, 0.7, 0.2}};
  const double expected = aw_test::polygon_irradiance(v, 3.0) / kPi;
  const std::string path = floor_with("", quad, "");
  aw::PackedScene p = aw::pack_scene(aw::load_scene(path), nullptr);
  EXPECT_EQ(p.lights.size(), 2u);  // its two triangles
  EXPECT_TRUE(p.features.on[aw::FeatureSet::LIGHT_MESH]);
  expect_radiance(path, {}, expected, "incandescent quad, light-sampled");
  expect_radiance(path, {"render.light_selection=tree"}, expected, "incandescent quad, light-sampled, tree");
  expect_radiance(path, {"objects[1].light_sampling=false"}, expected, "incandescent quad, BSDF sampling only");
}

TEST(ManyLights, LightSampledSphereObjectMatchesTheSphereLight) {
  const std::string sphere = R"(, { "shape": "sphere", "center": [0.3, 1.2, 0.2], "radius": 0.3, "material": "lamp",
                                    "light_sampling": true })";
  const double d2 = 0.09 + 1.44 + 0.04, d = std::sqrt(d2);
  const double expected = kPi * 3.0 * (0.09 / d2) * (1.2 / d) / kPi;
  const std::string path = floor_with("", sphere, "");
  aw::PackedScene p = aw::pack_scene(aw::load_scene(path), nullptr);
  EXPECT_GT(p.lights.size(), 1000u);
  EXPECT_FALSE(p.light_tree.empty());
  expect_radiance(path, {}, expected, "incandescent sphere object, light-sampled (tree)");
}

TEST(ManyLights, LightSamplingNeedsAnIncandescentMaterial) {
  const std::string bad = R"(, { "shape": "quad", "corner": [0, 1, 0], "material": "white", "light_sampling": true })";
  try {
    aw::load_scene(floor_with("", bad, ""));
    ADD_FAILURE() << "accepted";
  } catch (const aw::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("objects[1].light_sampling: "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("incandescent"), std::string::npos) << e.what();
  }
}

TEST(ManyLights, GallerySceneKernelMatchesScalar) {
  aw_test::expect_kernel_matches_scalar("scenes/docs/many_lights.json", {"render.width=48", "render.height=36", "render.spp=8"});
}

}  // namespace
