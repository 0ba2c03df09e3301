// Ambient occlusion (docs/material.md §4, kernels/integrator/ambient_occlusion.h) against closed
// forms. As in test_lights.cpp a very narrow camera looks at the point P = 0 of a floor (the
// "ao" material, diffuse rho = 0.6, no reflection), so every pixel shades (almost exactly) P:
//
//   nothing above P, add:                      L = rho * ambient_color (exactly, per sample)
//   inside a closed box, unlimited reach:      L = rho * shadow_color
//   a ceiling patch at height h straight above, spread 0 (every AO ray goes straight up):
//     v = (h / max_distance)^falloff (1 when h >= max_distance), AO = lerp(shadow, ambient, v)
//   multiply: the direct light of a sun, E cos t rho / pi, times AO.
// gi is off or max_depth 1 where the next surface would add its own AO. Both renderers.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "host/film/image_io.h"
#include "host/render/render.h"
#include "host/render/scene_pack.h"
#include "host/scene/scene.h"
#include "tests/render/render_test_util.h"

namespace {

const double kPi = 3.14159265358979323846;
const double kRho = 0.6;

// `ao` is the material's ao object; `extra` more objects; `lights` the lights array's content.
std::string ao_scene(const std::string& ao, const std::string& extra = "", const std::string& lights = "",
                     const std::string& render = R"("max_depth": 1)", const std::string& material_extra = "") {
  std::string json = R"({
  "render": { "width": 8, "height": 8, "spp": 64, "seed": 9, )" + render + R"( },
  "camera": { "position": [0, 0.3, 3], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 0.2,
              "exposure": { "mode": "stops", "stops": 2 } },
  "lights": [ )" + lights + R"( ],
  "materials": {
    "ao": { "diffuse": { "color": [0.6, 0.6, 0.6] }, "reflection": { "weight": 0 }, "ao": )" + ao + material_extra + R"( },
    "plain": { "diffuse": { "color": [0.5, 0.5, 0.5] }, "reflection": { "weight": 0 } }
  },
  "objects": [ { "shape": "quad", "corner": [-20, 0, 20], "edge_u": [40, 0, 0], "edge_v": [0, 0, -40],
                 "material": "ao" } )" + extra + R"( ]
})";
  return aw_test::write_temp_scene("ao_scene", json);
}

// A ceiling patch 0.2 x 0.2 centred above P at height h, facing down.
std::string patch_at(double h) {
  char buf[200];
  std::snprintf(buf, sizeof buf,
                R"(, { "shape": "quad", "corner": [-0.1, %g, -0.1], "edge_u": [0.2, 0, 0], "edge_v": [0, 0, 0.2],
                      "material": "plain" })",
                h);
  return buf;
}

double mean_green(const aw::RenderResult& r) {
  double s = 0.0;
  for (size_t p = 0; p < r.count.size(); ++p) s += r.sum[p * 3 + 1] / r.count[p];
  return s / double(r.count.size());
}

void expect_radiance(const std::string& scene_path, double expected, const char* what, double tol = 1e-4) {
  aw::Scene scene = aw::load_scene(scene_path);
  aw::RenderOptions o;
  aw::RenderResult rw = aw::render_wavefront(scene, o);
  aw::RenderResult rs = aw::render_scalar(scene, o);
  const double w = mean_green(rw), s = mean_green(rs);
  std::printf("%-48s expected %.6f  wavefront %.6f  scalar %.6f\n", what, expected, w, s);
  EXPECT_NEAR(w, expected, tol * std::max(1.0, expected)) << what << " (wavefront)";
  EXPECT_NEAR(s, expected, tol * std::max(1.0, expected)) << what << " (scalar)";
  EXPECT_EQ(rw.stats.bad_samples, 0u) << what;
}

TEST(AmbientOcclusion, OpenPlaneGivesAlbedoTimesAmbientInAddMode) {
  expect_radiance(ao_scene(R"({ "enable": true, "ambient_color": [0.7, 0.7, 0.7] })"), kRho * 0.7, "open plane, add");
}

TEST(AmbientOcclusion, ClosedBoxGivesShadowColourAndInvertNormalSwaps) {
  // A closed box around P (its floor is the ao floor): every AO ray meets a wall.
  const std::string box = R"(, { "shape": "box", "min": [-1, -0.5, -1], "max": [1, 1, 1], "material": "plain" })";
  // The camera sits inside the box too: move it there with a steeper, still narrow view.
  std::string inside = ao_scene(R"({ "enable": true, "max_distance": 0, "shadow_color": [0.3, 0.3, 0.3] })", box, "",
                                R"("max_depth": 1, "gi": false)");
  aw::Scene s = aw::load_scene(inside, {"camera.position=[0,0.5,0.5]"});
  aw::RenderOptions o;
  EXPECT_NEAR(mean_green(aw::render_wavefront(s, o)), kRho * 0.3, 1e-5) << "closed box";
  EXPECT_NEAR(mean_green(aw::render_scalar(s, o)), kRho * 0.3, 1e-5) << "closed box (scalar)";
  // Inverted, the rays leave through the floor into the empty space below the box... which
  // the box's own bottom closes: a floor above a lower floor is occluded only when inverted.
  const std::string below = R"(, { "shape": "quad", "corner": [-20, -1, 20], "edge_u": [40, 0, 0], "edge_v": [0, 0, -40],
                                  "material": "plain" })";
  expect_radiance(ao_scene(R"({ "enable": true, "max_distance": 0, "shadow_color": [0.3, 0.3, 0.3] })", below),
                  kRho * 1.0, "floor over a floor, normal AO: ambient");
  expect_radiance(ao_scene(R"({ "enable": true, "max_distance": 0, "shadow_color": [0.3, 0.3, 0.3], "invert_normal": true })",
                           below),
                  kRho * 0.3, "floor over a floor, inverted: shadow");
}

TEST(AmbientOcclusion, DistanceAndFalloffShapeTheVisibility) {
  const std::string patch = patch_at(0.5);
  // spread 0: every AO ray straight up, into the patch at h = 0.5.
  auto ao = [](double dist, double falloff) {
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  R"({ "enable": true, "spread": 0, "max_distance": %g, "falloff": %g, "shadow_color": [0.2, 0.2, 0.2] })",
                  dist, falloff);
    return std::string(buf);
  };
  auto expected = [](double v) { return kRho * (0.2 + (1.0 - 0.2) * v); };
  expect_radiance(ao_scene(ao(2, 1), patch), expected(0.25), "h 0.5, reach 2, falloff 1");
  expect_radiance(ao_scene(ao(2, 2), patch), expected(0.0625), "h 0.5, reach 2, falloff 2 (towards occluded)");
  expect_radiance(ao_scene(ao(2, 0.5), patch), expected(0.5), "h 0.5, reach 2, falloff 0.5 (towards un-occluded)");
  expect_radiance(ao_scene(ao(0.4, 1), patch), expected(1.0), "h 0.5, reach 0.4: not reached");
  // spread 0 with the patch moved aside: un-occluded whatever surrounds P sideways.
  expect_radiance(ao_scene(ao(2, 1), R"(, { "shape": "box", "min": [0.05, 0, -1], "max": [0.5, 2, 1], "material": "plain" })"),
                  expected(1.0), "spread 0 beside a wall: un-occluded");
}

TEST(AmbientOcclusion, MultiplyScalesDirectLightAndIncandescence) {
  const std::string patch = patch_at(0.5);
  const double t = 45.0 * kPi / 180.0;
  const std::string sun = R"({ "type": "sun", "direction": [0.70710678, -0.70710678, 0], "angle": 0, "intensity": 2 })";
  const std::string ao = R"({ "enable": true, "combine": "multiply", "spread": 0, "max_distance": 2, "shadow_color": [0.2, 0.2, 0.2] )";
  const double ao_v = 0.2 + 0.8 * 0.25;
  expect_radiance(ao_scene(ao + "}", patch, sun), 2.0 * std::cos(t) * kRho / kPi * ao_v, "multiply: sun x AO");
  // Incandescence 0.5: darkened only with apply_to_incandescence.
  const std::string inc = R"(, "incandescent": { "color": [1, 1, 1], "scale": 0.5 })";
  expect_radiance(ao_scene(ao + "}", patch, "", R"("max_depth": 1)", inc), 0.5, "multiply leaves incandescence");
  expect_radiance(ao_scene(ao + R"(, "apply_to_incandescence": true })", patch, "", R"("max_depth": 1)", inc),
                  0.5 * ao_v, "multiply with apply_to_incandescence");
}

TEST(AmbientOcclusion, ExposureCompensationDividesByTheExposure) {
  // stops 2: k = 4. The ambient term is stored as rho * ambient / 4, and shows as rho * ambient.
  expect_radiance(ao_scene(R"({ "enable": true, "exposure_compensation": true })"), kRho / 4.0,
                  "add, exposure compensated (k = 4)");
}

TEST(AmbientOcclusion, OnlyScenesWithAoBuildIt) {
  aw::PackedScene with = aw::pack_scene(aw::load_scene(ao_scene(R"({ "enable": true })")), nullptr);
  EXPECT_TRUE(with.features.on[aw::FeatureSet::AO]);
  aw::PackedScene without = aw::pack_scene(aw::load_scene(ao_scene(R"({ "enable": false })")), nullptr);
  EXPECT_FALSE(without.features.on[aw::FeatureSet::AO]);
  // A build without AO meets an AO material: refused, never rendered without it.
  aw::RenderOptions o;
  o.force_off = {"AO"};
  EXPECT_THROW(aw::render_wavefront(aw::load_scene(ao_scene(R"({ "enable": true })")), o), std::exception);
}

}  // namespace

namespace {

// The gallery's AO scenes (rings under sun and sky; add without GI, multiply with GI; the
// first hit's 256 AO samples split over the pixel's samples), per pixel: wavefront against the
// scalar path, and the specialised build against the generic one.
void expect_ao_scene_matches(const std::string& name) {
  aw_test::expect_kernel_matches_scalar("scenes/docs/" + name + ".json",
                                        {"render.width=48", "render.height=36", "render.spp=8", "environment.resolution=128"});
}

TEST(AmbientOcclusion, AddSceneKernelMatchesScalar) { expect_ao_scene_matches("ao_2_add"); }
TEST(AmbientOcclusion, MultiplySceneKernelMatchesScalar) { expect_ao_scene_matches("ao_4_gi_multiply"); }

}  // namespace
