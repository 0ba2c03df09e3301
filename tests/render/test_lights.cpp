// Light units and sampling against closed forms (docs/scene-format.md, `lights`: "units are
// part of the contract"). A white Lambertian floor (albedo 1) at y = 0 is seen through a very
// narrow camera aimed at the origin, so every pixel sees (almost exactly) the point P = 0. Its
// radiance is E / pi where E is the irradiance at P, and E has a closed form for each light:
//
//   point, intensity I at height h:            E = I / h^2
//   sphere, radiance L, radius r, centre at h: E = pi L (r / h)^2     (pi L sin^2 of the half-angle)
//   disk facing down, radius r at height h:    E = pi L r^2 / (h^2 + r^2)
//   polygon (quad), radiance L:                E = L/2 sum_i theta_i (n . u_i)
//     (Lambert's formula: theta_i is the angle the edge (v_i, v_i+1) subtends at P and u_i the
//      unit normal of the plane through P and that edge; Arvo 1995, "Applications of
//      Irradiance Tensors...", Sec. 3.)
//
// Area lights are estimated by light sampling and BSDF sampling combined with MIS, so these
// tests also check that the two MIS weights sum to one, also at the depth limit and with
// gi off. Tolerance 1%: the images have 40k+ samples and the narrow view's footprint changes
// E by < 0.01%.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include <glm/glm.hpp>

#include "host/render/render.h"
#include "host/scene/scene.h"
#include "tests/render/render_test_util.h"

namespace {

const double kPi = 3.14159265358979323846;

std::string scene_with(const std::string& light_json, const std::string& render_extra = R"("max_depth": 1)") {
  std::string json = R"({
  "render": { "width": 16, "height": 16, "spp": 256, "seed": 3, )" + render_extra + R"( },
  "camera": { "position": [0, 0.3, 3], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 0.2 },
  "lights": [ )" + light_json + R"( ],
  "materials": { "white": { "diffuse": { "color": [1, 1, 1] }, "reflection": { "weight": 0 } } },
  "objects": [ { "shape": "quad", "corner": [-50, 0, 50], "edge_u": [100, 0, 0], "edge_v": [0, 0, -100],
                 "material": "white" } ]
})";
  return aw_test::write_temp_scene("light_scene", json);
}

double mean_radiance(const aw::RenderResult& r) {
  double s = 0.0;
  for (size_t p = 0; p < r.count.size(); ++p) s += r.sum[p * 3 + 1] / r.count[p];  // green channel
  return s / double(r.count.size());
}

void expect_radiance(const std::string& scene_path, double expected, const char* what) {
  aw::Scene scene = aw::load_scene(scene_path);
  aw::RenderOptions o;
  double w = mean_radiance(aw::render_wavefront(scene, o));
  double s = mean_radiance(aw::render_scalar(scene, o));
  std::printf("%-40s expected %.6f  wavefront %.6f  scalar %.6f\n", what, expected, w, s);
  EXPECT_NEAR(w / expected, 1.0, 0.01) << what << " (wavefront)";
  EXPECT_NEAR(s / expected, 1.0, 0.01) << what << " (scalar)";
}

TEST(Lights, PointLightInverseSquare) {
  // I = 2 W/sr at h = 1.5: E = 2 / 2.25, L = E / pi.
  expect_radiance(scene_with(R"({ "type": "point", "position": [0, 1.5, 0], "intensity": 2 })"),
                  2.0 / 2.25 / kPi, "point");
}

TEST(Lights, SphereLight) {
  double L = 3.0, r = 0.5, h = 2.0;
  expect_radiance(scene_with(R"({ "type": "sphere", "center": [0, 2, 0], "radius": 0.5, "intensity": 3 })"),
                  kPi * L * (r / h) * (r / h) / kPi, "sphere");
}

TEST(Lights, DiskLightFacingDown) {
  double L = 2.0, r = 1.0, h = 0.8;
  expect_radiance(
      scene_with(R"({ "type": "disk", "center": [0, 0.8, 0], "normal": [0, -1, 0], "radius": 1, "intensity": 2 })"),
      kPi * L * r * r / (h * h + r * r) / kPi, "disk (large and close: MIS matters)");
}

TEST(Lights, QuadLightOffCentre) {
  // A 1 x 0.5 rectangle at height 0.7, off to one side; emits downwards (edge_u x edge_v = -y).
  std::vector<glm::dvec3> v = {{0.2, 0.7, -0.3}, {1.2, 0.7, -0.3}, {1.2, 0.7, 0.2}, {0.2, 0.7, 0.2}};
  double L = 4.0;
  expect_radiance(scene_with(R"({ "type": "quad", "corner": [0.2, 0.7, -0.3], "edge_u": [1, 0, 0],
                                  "edge_v": [0, 0, 0.5], "intensity": 4 })"),
                  aw_test::polygon_irradiance(v, L) / kPi, "quad (off centre)");
}

TEST(Lights, OneSidedQuadFacingAwayGivesNothingTwoSidedGivesAll) {
  std::vector<glm::dvec3> v = {{-0.5, 0.7, -0.5}, {0.5, 0.7, -0.5}, {0.5, 0.7, 0.5}, {-0.5, 0.7, 0.5}};
  // edge_v x edge_u order reversed: emits upwards, away from the floor.
  std::string away = R"({ "type": "quad", "corner": [-0.5, 0.7, -0.5], "edge_u": [0, 0, 1], "edge_v": [1, 0, 0],
                          "intensity": 4 )";
  aw::Scene s = aw::load_scene(scene_with(away + "}"));
  aw::RenderOptions o;
  EXPECT_EQ(mean_radiance(aw::render_wavefront(s, o)), 0.0);
  expect_radiance(scene_with(away + R"(, "two_sided": true })"), aw_test::polygon_irradiance(v, 4.0) / kPi,
                  "quad two-sided, facing away");
}

// MIS completeness at the limits: gi off, and max_depth 1 with gi on, must both give the
// full direct light (the BSDF-sampling half of MIS is traced to find the light).
TEST(Lights, MisCompleteWithGiOffAndAtDepthLimit) {
  double L = 2.0, r = 1.0, h = 0.8;
  std::string disk =
      R"({ "type": "disk", "center": [0, 0.8, 0], "normal": [0, -1, 0], "radius": 1, "intensity": 2 })";
  expect_radiance(scene_with(disk, R"("max_depth": 1, "gi": false)"), L * r * r / (h * h + r * r), "disk, gi off");
  expect_radiance(scene_with(disk, R"("max_depth": 3)"), L * r * r / (h * h + r * r),
                  "disk, max_depth 3 (no other surface)");
}

TEST(Lights, InvisibleLightIsNotSeenByCameraButStillLights) {
  // The camera looks at the floor through the sphere light; invisible, it must not block.
  std::string json = R"({ "type": "sphere", "center": [0, 0.15, 1.5], "radius": 0.1, "intensity": 5,
                           "visible": false })";
  aw::Scene s = aw::load_scene(scene_with(json));
  aw::RenderOptions o;
  double w = mean_radiance(aw::render_wavefront(s, o));
  // Visible, the same light fills the view with its radiance 5.
  aw::Scene sv = aw::load_scene(scene_with(R"({ "type": "sphere", "center": [0, 0.15, 1.5], "radius": 0.1,
                                                "intensity": 5 })"));
  double v = mean_radiance(aw::render_wavefront(sv, o));
  EXPECT_NEAR(v, 5.0, 1e-4);
  EXPECT_LT(w, 0.5);
  EXPECT_GT(w, 0.0);
}

}  // namespace
