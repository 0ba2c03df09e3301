// Lights at infinity against closed forms (docs/scene-format.md, `lights` sun and `environment`):
// as in test_lights.cpp, a white Lambertian floor (albedo 1) at y = 0 is seen through a very
// narrow camera aimed at the origin P, whose radiance is E / pi with E the irradiance there.
//
//   sun, irradiance E, direction at angle t from the zenith, angular radius a <= 90 - t:
//     E_P = E cos t (the disc, of radiance E / (pi sin^2 a), is wholly above the horizon, and
//     its projected solid angle is pi sin^2 a cos t: PBR 3rd ed. Sec. 5.5.1)
//   constant environment L:                      E_P = pi L
//   lat-long map, texel (i, j) of radiance L_ij, nearest lookup, horizon on a row border:
//     E_P = sum over upper texels of L_ij * (2 pi / w) * (sin^2 theta_1 - sin^2 theta_0) / 2,
//     the integral of cos(theta) over the texel (theta from +Y).
//
// The sun and the map are sampled by next-event estimation and by BSDF sampling, weighted by
// MIS; the constant environment by BSDF sampling alone. Both renderers, 1% (the images have
// 65k samples; the narrow view's footprint changes E by < 0.01%).
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "host/film/image_io.h"
#include "host/render/render.h"
#include "host/render/scene_pack.h"
#include "host/scene/scene.h"
#include "host/scene/sky.h"
#include "tests/render/render_test_util.h"

namespace {

const double kPi = 3.14159265358979323846;

std::string floor_scene(const std::string& lights, const std::string& environment,
                        const std::string& render_extra = R"("max_depth": 1)") {
  std::string json = R"({
  "render": { "width": 16, "height": 16, "spp": 256, "seed": 5, )" + render_extra + R"( },
  "camera": { "position": [0, 0.3, 3], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 0.2 },
  "environment": )" + environment + R"(,
  "lights": [ )" + lights + R"( ],
  "materials": { "white": { "diffuse": { "color": [1, 1, 1] }, "reflection": { "weight": 0 } } },
  "objects": [ { "shape": "quad", "corner": [-50, 0, 50], "edge_u": [100, 0, 0], "edge_v": [0, 0, -100],
                 "material": "white" } ]
})";
  return aw_test::write_temp_scene("infinite_light_scene", json);
}

double mean_green(const aw::RenderResult& r) {
  double s = 0.0;
  for (size_t p = 0; p < r.count.size(); ++p) s += r.sum[p * 3 + 1] / r.count[p];
  return s / double(r.count.size());
}

void expect_radiance(const std::string& scene_path, double expected, const char* what) {
  aw::Scene scene = aw::load_scene(scene_path);
  aw::RenderOptions o;
  aw::RenderResult rw = aw::render_wavefront(scene, o);
  aw::RenderResult rs = aw::render_scalar(scene, o);
  double w = mean_green(rw), s = mean_green(rs);
  std::printf("%-44s expected %.6f  wavefront %.6f  scalar %.6f\n", what, expected, w, s);
  EXPECT_NEAR(w / expected, 1.0, 0.01) << what << " (wavefront)";
  EXPECT_NEAR(s / expected, 1.0, 0.01) << what << " (scalar)";
  EXPECT_EQ(rw.stats.bad_samples, 0u) << what;
  EXPECT_EQ(rs.stats.bad_samples, 0u) << what;
}

const char* kBlack = R"({ "type": "constant", "color": [0, 0, 0] })";

TEST(InfiniteLights, HardSunStraightDown) {
  expect_radiance(floor_scene(R"({ "type": "sun", "direction": [0, -1, 0], "angle": 0, "intensity": 3 })", kBlack),
                  3.0 / kPi, "hard sun, zenith");
}

TEST(InfiniteLights, SunTiltedHardAndSoft) {
  // direction (sin t, -cos t, 0): t = 40 degrees from the zenith.
  const double t = 40.0 * kPi / 180.0;
  char dir[96];
  std::snprintf(dir, sizeof dir, "[%.9f, %.9f, 0]", std::sin(t), -std::cos(t));
  const std::string d = dir;
  expect_radiance(floor_scene(R"({ "type": "sun", "direction": )" + d + R"(, "angle": 0, "intensity": 2 })", kBlack),
                  2.0 * std::cos(t) / kPi, "hard sun, 40 deg");
  expect_radiance(floor_scene(R"({ "type": "sun", "direction": )" + d + R"(, "angle": 0.53, "intensity": 2 })", kBlack),
                  2.0 * std::cos(t) / kPi, "sun 0.53 deg, 40 deg");
  expect_radiance(floor_scene(R"({ "type": "sun", "direction": )" + d + R"(, "angle": 20, "intensity": 2 })", kBlack),
                  2.0 * std::cos(t) / kPi, "sun 20 deg wide, 40 deg (MIS matters)");
}

TEST(InfiniteLights, SunAsWideAsTheSkyAndMisCompleteWithGiOff) {
  // angle 180: the disc is the whole upper hemisphere, of radiance E / pi: E_P = E again.
  expect_radiance(floor_scene(R"({ "type": "sun", "direction": [0, -1, 0], "angle": 180, "intensity": 2 })", kBlack),
                  2.0 / kPi, "sun 180 deg (a hemisphere)");
  expect_radiance(floor_scene(R"({ "type": "sun", "direction": [0, -1, 0], "angle": 30, "intensity": 2 })", kBlack,
                              R"("max_depth": 1, "gi": false)"),
                  2.0 / kPi, "sun 30 deg, gi off");
}

TEST(InfiniteLights, ConstantEnvironment) {
  expect_radiance(floor_scene("", R"({ "type": "constant", "color": [0.5, 0.5, 0.5], "intensity": 2 })"), 1.0,
                  "constant environment 1");
}

// Writes a lat-long EXR whose texel (i, j) has radiance value(i, j) (grey).
template <class F>
std::string write_map(const std::string& name, int w, int h, F value) {
  aw::Image img;
  img.width = w;
  img.height = h;
  img.rgb.resize(size_t(w) * h * 3);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i)
      for (int c = 0; c < 3; ++c) img.rgb[3 * (size_t(j) * w + i) + c] = float(value(i, j));
  std::string path = testing::TempDir() + "/" + name + "_" + std::to_string(getpid()) + ".exr";
  aw::write_exr(path, img);
  return path;
}

// E at an upward point from a nearest-lookup map (rows aligned so the horizon is a border).
template <class F>
double map_irradiance(int w, int h, F value) {
  double e = 0.0;
  for (int j = 0; j < h / 2; ++j) {
    const double s0 = std::sin(kPi * j / h), s1 = std::sin(kPi * (j + 1) / h);
    for (int i = 0; i < w; ++i) e += value(i, j) * (2.0 * kPi / w) * (s1 * s1 - s0 * s0) / 2.0;
  }
  return e;
}

TEST(InfiniteLights, MapUpperHalfOneGivesAlbedo) {
  auto half = [](int, int j) { return j < 4 ? 1.0 : 0.0; };
  const std::string map = write_map("half_map", 16, 8, half);
  expect_radiance(floor_scene("", R"({ "type": "map", "file": ")" + map + R"(", "rotation": 30 })"), 1.0,
                  "map: upper half 1");
}

TEST(InfiniteLights, StructuredMapWithAHotTexelMatchesItsIntegral) {
  auto value = [](int i, int j) {
    if (i == 5 && j == 1) return 200.0;  // a small bright source: importance sampling finds it
    return 0.05 + 0.1 * ((i * 7 + j * 3) % 5) + (j >= 8 ? 3.0 : 0.0);  // the ground is bright, and hidden
  };
  const std::string map = write_map("hot_map", 24, 16, value);
  const double expected = map_irradiance(24, 16, value) / kPi;
  expect_radiance(floor_scene("", R"({ "type": "map", "file": ")" + map + R"(", "intensity": 1 })"), expected,
                  "map with a hot texel");
  expect_radiance(floor_scene("", R"({ "type": "map", "file": ")" + map + R"(" })", R"("max_depth": 1, "gi": false)"),
                  expected, "map with a hot texel, gi off");
}

TEST(InfiniteLights, SunAndMapTogether) {
  auto value = [](int i, int j) { return 0.2 + 0.05 * ((i + 2 * j) % 3); };
  const std::string map = write_map("sun_map", 16, 8, value);
  expect_radiance(floor_scene(R"({ "type": "sun", "direction": [0, -1, 0], "angle": 2, "intensity": 3 })",
                              R"({ "type": "map", "file": ")" + map + R"(" })"),
                  (3.0 + map_irradiance(16, 8, value)) / kPi, "sun and map");
}

TEST(InfiniteLights, SkyAndSunMatchTheBakedSky) {
  // The sky is a baked map (host/scene/sky.h): its irradiance at P by the same closed form,
  // plus the sun's (whose colour the sky model sets; green is compared, so its transmittance's
  // green channel enters).
  const int w = 64, h = 32;
  const double zen = 35.0 * kPi / 180.0;
  char dir[96];
  std::snprintf(dir, sizeof dir, "[%.9f, %.9f, 0]", std::sin(zen), -std::cos(zen));
  aw::SkyModel sky = aw::make_preetham_sky(glm::vec3(-std::sin(zen), std::cos(zen), 0.0), 3.0f, glm::vec3(0.2f));
  std::vector<float> baked = aw::bake_sky_latlong(sky, w, h);
  auto green = [&](int i, int j) { return double(baked[3 * (size_t(j) * w + i) + 1]); };
  const double sun_green = aw::sun_transmittance_rgb(3.0f, float(zen)).y;
  const double scale = 1e-4;  // the sky's cd/m^2 brought near 1
  char env[160];
  std::snprintf(env, sizeof env, R"({ "type": "sky", "turbidity": 3, "resolution": %d, "intensity": %g })", w, scale);
  const std::string lights = std::string(R"({ "type": "sun", "angle": 0.53, "intensity": 1, "direction": )") + dir + "}";
  expect_radiance(floor_scene(lights, env), (scale * map_irradiance(w, h, green) + sun_green * std::cos(zen)) / kPi,
                  "sky and sun");
}

TEST(InfiniteLights, BadInputNamesTheKey) {
  auto fails_with = [](const std::string& lights, const std::string& env, const std::string& what) {
    try {
      aw::load_scene(floor_scene(lights, env));
      ADD_FAILURE() << "accepted: " << lights << " " << env;
    } catch (const aw::SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  fails_with(R"({ "type": "sun", "direction": [0, 0, 0] })", kBlack, "lights[0].direction");
  fails_with(R"({ "type": "sun", "angle": 181 })", kBlack, "lights[0].angle");
  fails_with(R"({ "type": "sun", "radius": 1 })", kBlack, "lights[0].radius");
  fails_with("", R"({ "type": "map" })", "file");
  fails_with("", R"({ "type": "map", "file": "/nonexistent/sky.exr" })", "/nonexistent/sky.exr");
  fails_with("", R"({ "type": "map", "file": "x.exr", "color": [1, 1, 1] })", "environment.color");
  fails_with("", R"({ "type": "sky" })", "sun");
  fails_with(R"({ "type": "sun" })", R"({ "type": "sky", "turbidity": 1 })", "environment.turbidity");
  // A file that is not an EXR.
  const std::string not_exr = aw_test::write_temp_scene("not_an_exr", "{}");
  fails_with("", R"({ "type": "map", "file": ")" + not_exr + R"(" })",
             not_exr.substr(not_exr.rfind('/') + 1) + "\": Cannot read image file");
}

}  // namespace

namespace {

TEST(InfiniteLights, SkySceneKernelMatchesScalar) {
  aw_test::expect_kernel_matches_scalar("scenes/docs/sky_fresnel_shallow.json",
                               {"render.width=64", "render.height=48", "render.spp=8", "environment.resolution=256"});
}

TEST(InfiniteLights, SunThroughWindowKernelMatchesScalar) {
  aw_test::expect_kernel_matches_scalar("scenes/docs/sun_window_interior.json",
                               {"render.width=64", "render.height=48", "render.spp=8", "environment.resolution=256"});
}

TEST(InfiniteLights, MapSceneSpecialisedBuildsOnlyWhatItUses) {
  auto value = [](int i, int j) { return 0.3 + 0.1 * ((i + j) % 2); };
  const std::string map = write_map("spec_map", 8, 4, value);
  aw::Scene scene = aw::load_scene(floor_scene(R"({ "type": "sun", "angle": 1 })", R"({ "type": "map", "file": ")" + map + R"(" })"));
  aw::PackedScene p = aw::pack_scene(scene, nullptr);
  EXPECT_EQ(p.features.describe(), "light_sun env_map");
  EXPECT_EQ(p.num_infinite, 2u);  // the map, then the sun
  EXPECT_EQ(p.lights[0].type, uint32_t(AW_LIGHT_ENV));
  EXPECT_EQ(p.lights[1].type, uint32_t(AW_LIGHT_SUN));
  // A build without the map's code refuses the scene rather than render it wrong.
  aw::RenderOptions o;
  o.force_off = {"ENV_MAP"};
  EXPECT_THROW(aw::render_wavefront(scene, o), std::exception);
}

}  // namespace

namespace {

// Issue 16's extremes for the lights at infinity and AO: a sun 0 and 180 degrees wide, grazing
// and straight up from below, an environment map of one pixel and one with a single hot pixel
// among black ones, AO reaching 0 (unlimited) and 1e9 with falloff 0 and huge, spread 0 and 1,
// with glossy, rough and refractive materials: no sample is discarded (the NaN guard must not
// be what keeps the image clean), both renderers.
TEST(InfiniteLights, ExtremesRenderFinite) {
  const std::string one_px = write_map("one_px", 1, 1, [](int, int) { return 3.0; });
  const std::string hot_px = write_map("hot_px", 64, 32, [](int i, int j) { return i == 40 && j == 3 ? 1e6 : 0.0; });
  const std::string suns[] = {
      R"({ "type": "sun", "direction": [0, -1, 0], "angle": 0, "intensity": 3 })",
      R"({ "type": "sun", "direction": [0.3, -1, 0.2], "angle": 180, "intensity": 3 })",
      R"({ "type": "sun", "direction": [1, -1e-7, 0], "angle": 0.53, "intensity": 3 })",
      R"({ "type": "sun", "direction": [0, 1, 0], "angle": 10, "intensity": 3 })"};
  const std::string envs[] = {R"({ "type": "map", "file": ")" + one_px + R"(" })",
                              R"({ "type": "map", "file": ")" + hot_px + R"(", "rotation": 1e6 })",
                              R"({ "type": "sky", "turbidity": 10, "resolution": 16 })"};
  const std::string aos[] = {
      R"("ao": { "enable": true, "max_distance": 0, "falloff": 0, "spread": 1, "samples": 64 })",
      R"("ao": { "enable": true, "combine": "multiply", "max_distance": 1e9, "falloff": 1e6, "spread": 0 })",
      R"("ao": { "enable": true, "max_distance": 1e-9, "invert_normal": true, "exposure_compensation": true })"};
  const std::string mats[] = {R"("reflection": { "weight": 1, "glossiness": 0.95 })",
                              R"("diffuse": { "roughness": 1 }, "reflection": { "weight": 0.5, "glossiness": 0 })",
                              R"("refraction": { "weight": 1, "ior": 1.5, "glossiness": 0.3 })"};
  int k = 0;
  for (const std::string& env : envs)
    for (size_t i = 0; i < 4; ++i, ++k) {
      const std::string json = R"({
  "render": { "width": 12, "height": 8, "spp": 8, "seed": 2, "max_depth": 6 },
  "camera": { "position": [0, 1, 3], "look_at": [0, 0.3, 0], "fov": 60 },
  "environment": )" + env + R"(, "lights": [ )" + suns[i] + R"( ],
  "materials": { "m": { )" + mats[k % 3] + ", " + aos[k % 3] + R"( } },
  "objects": [ { "shape": "sphere", "center": [0, 0.5, 0], "radius": 0.5, "material": "m" },
               { "shape": "quad", "corner": [-5, 0, 5], "edge_u": [10, 0, 0], "edge_v": [0, 0, -10], "material": "m" },
               { "shape": "box", "min": [-1.5, 0, -1], "max": [-1, 2, -0.5], "material": "m" } ]
})";
      aw::Scene scene = aw::load_scene(aw_test::write_temp_scene("extreme_inf", json));
      // The generic kernels: one build for the twelve scenes (specialised builds render the
      // same images: Specialisation.SameImageAsGenericKernels and the kernel tests above).
      aw::RenderOptions o;
      o.generic_kernels = true;
      aw::RenderResult w = aw::render_wavefront(scene, o), s = aw::render_scalar(scene, o);
      EXPECT_EQ(w.stats.bad_samples, 0u) << json;
      EXPECT_EQ(s.stats.bad_samples, 0u) << json;
      for (float v : w.sum) ASSERT_TRUE(std::isfinite(v)) << json;
    }
}

}  // namespace
