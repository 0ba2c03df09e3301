// AOVs (issue 15, docs/production.md#aovs): the layers' names, first-hit data of known value
// (the albedo of a Lambert plane, its normal, its depth and position, the material's index),
// light groups that sum to the beauty to float precision (also with clamping, lobe splitting
// and ambient occlusion), the wavefront against the scalar path, and parts that merge with
// their AOVs bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

#include "host/render/film_state.h"
#include "host/render/render.h"
#include "host/scene/scene.h"
#include "kernels/integrator/aov.h"
#include "tests/render/render_test_util.h"

namespace {

const char* kAll = "render.aovs=\"albedo,normal,depth,position,material_id,light_groups\"";

// A Lambert plane z = 0 facing a camera 3 units away on +z, under a grey sky.
std::string plane_scene() {
  return aw_test::write_temp_scene("aov_plane", R"({
  "render": { "width": 9, "height": 9, "spp": 16, "max_depth": 3 },
  "camera": { "position": [0, 0, 3], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 20 },
  "environment": { "type": "constant", "color": [0.5, 0.5, 0.5], "intensity": 1 },
  "materials": {
    "unused": { "diffuse": { "color": [1, 0, 0] } },
    "paint": { "diffuse": { "color": [0.5, 0.25, 0.125] }, "reflection": { "weight": 0 } }
  },
  "objects": [ { "shape": "quad", "corner": [-20, -20, 0], "edge_u": [40, 0, 0], "edge_v": [0, 40, 0],
                 "material": "paint" } ]
})");
}

// The image's AOV channel `name` at pixel p (exposure applies to the light groups only).
float channel(const aw::Image& img, const std::string& name, size_t p) {
  for (const aw::ImageChannel& c : img.channels)
    if (c.name == name) return c.f.at(p);
  ADD_FAILURE() << "no channel " << name;
  return NAN;
}

TEST(Aovs, LayersAreNamedAsCompositorsExpect) {
  const aw::Scene s = aw::load_scene(plane_scene(), {kAll});
  const aw::Image img = aw::render_wavefront(s, aw_test::quiet_options()).image(s);
  std::vector<std::string> names;
  for (const aw::ImageChannel& c : img.channels) names.push_back(c.name);
  const std::vector<std::string> expected = {
      "albedo.R",     "albedo.G",     "albedo.B",       "normal.X",       "normal.Y",       "normal.Z",       "depth.Z",
      "position.X",   "position.Y",   "position.Z",     "material_id.id", "emission.R",     "emission.G",     "emission.B",
      "ao.R",         "ao.G",         "ao.B",           "diffuse.R",      "diffuse.G",      "diffuse.B",      "translucency.R",
      "translucency.G", "translucency.B", "reflection.R", "reflection.G", "reflection.B", "refraction.R", "refraction.G",
      "refraction.B"};
  EXPECT_EQ(names, expected);
  // Without AOVs: no layers, and the kernels are built without them (the Cornell box's
  // kernels, which the other render tests build too).
  const aw::Scene plain = aw::load_scene(aw_test::source_path("scenes/cornell.json"), {"render.width=8", "render.height=8", "render.spp=1"});
  const aw::RenderResult r = aw::render_wavefront(plain, aw_test::quiet_options());
  EXPECT_TRUE(r.image(plain).channels.empty());
  EXPECT_EQ(r.stats.kernel_features.find("aov"), std::string::npos) << r.stats.kernel_features;
}

// Known first-hit values on the plane: its diffuse colour as albedo (no other lobe), +z as its
// normal, z = 0, the distance along each pixel's rays, and the material's index (1: "paint"
// comes after "unused" in the file).
TEST(Aovs, FirstHitDataOfAKnownPlane) {
  const aw::Scene s = aw::load_scene(plane_scene(), {kAll});
  for (bool scalar : {false, true}) {
    SCOPED_TRACE(scalar ? "scalar" : "wavefront");
    const aw::RenderResult r = scalar ? aw::render_scalar(s, aw_test::quiet_options()) : aw::render_wavefront(s, aw_test::quiet_options());
    const aw::Image img = r.image(s);
    const double t = std::tan(10.0 * M_PI / 180.0);
    for (int y = 0; y < 9; ++y)
      for (int x = 0; x < 9; ++x) {
        const size_t p = size_t(y) * 9 + size_t(x);
        EXPECT_NEAR(channel(img, "albedo.R", p), 0.5, 1e-6);
        EXPECT_NEAR(channel(img, "albedo.G", p), 0.25, 1e-6);
        EXPECT_NEAR(channel(img, "albedo.B", p), 0.125, 1e-6);
        EXPECT_NEAR(channel(img, "normal.X", p), 0.0, 1e-6);
        EXPECT_NEAR(channel(img, "normal.Y", p), 0.0, 1e-6);
        EXPECT_NEAR(channel(img, "normal.Z", p), 1.0, 1e-6);
        EXPECT_NEAR(channel(img, "position.Z", p), 0.0, 1e-5);
        EXPECT_NEAR(channel(img, "material_id.id", p), 1.0, 1e-6);
        // The pixel centre's ray: the samples spread over the pixel, so the mean distance and
        // position are the centre's to within the pixel's extent (2 t / 9 of the view).
        const double u = (2.0 * (x + 0.5) / 9 - 1.0) * t, v = (1.0 - 2.0 * (y + 0.5) / 9) * t;
        EXPECT_NEAR(channel(img, "depth.Z", p), 3.0 * std::sqrt(1.0 + u * u + v * v), 3e-3);
        EXPECT_NEAR(channel(img, "position.X", p), 3.0 * u, 2e-2);
        EXPECT_NEAR(channel(img, "position.Y", p), 3.0 * v, 2e-2);
      }
  }
}

// Every light group's sum is the beauty, pixel by pixel, to float precision; each group that
// the scene lights is non-zero somewhere.
void expect_groups_sum_to_beauty(const std::string& scene, const std::vector<std::string>& extra, bool scalar,
                                 const std::vector<std::string>& lit) {
  std::vector<std::string> o = {"render.width=40", "render.height=30", "render.spp=8", kAll};  // extra may override spp
  o.insert(o.end(), extra.begin(), extra.end());
  const aw::Scene s = aw::load_scene(aw_test::source_path(scene), o);
  const aw::RenderResult r = scalar ? aw::render_scalar(s, aw_test::quiet_options()) : aw::render_wavefront(s, aw_test::quiet_options());
  const aw::Image img = r.image(s);
  const char* groups[] = {"emission", "ao", "diffuse", "translucency", "reflection", "refraction"};
  std::map<std::string, double> total;
  double worst = 0.0;
  for (size_t p = 0; p < size_t(img.width) * img.height; ++p)
    for (int c = 0; c < 3; ++c) {
      const std::string ch = std::string(1, "RGB"[c]);
      double sum = 0.0;
      for (const char* g : groups) {
        const double v = channel(img, std::string(g) + "." + ch, p);
        sum += v;
        total[g] += std::fabs(v);
      }
      const double beauty = img.rgb[p * 3 + c];
      worst = std::max(worst, std::fabs(sum - beauty) / std::max(1e-3, std::fabs(beauty)));
    }
  std::printf("%s: largest relative difference of the groups' sum from the beauty %.3g\n", scene.c_str(), worst);
  EXPECT_LT(worst, 1e-5);
  for (const std::string& g : lit) EXPECT_GT(total[g], 0.0) << g << " is empty";
}

TEST(Aovs, LightGroupsSumToTheBeauty) {
  // Each kernel build serves several cases (kernel builds dominate this test's time): the
  // materials scene at 2 spp splits its lobes (render.lobe_splitting, the default), so the
  // groups' sum is checked with splits averaged, on both renderers.
  expect_groups_sum_to_beauty("scenes/cornell.json", {}, false, {"emission", "diffuse"});
  expect_groups_sum_to_beauty("scenes/materials.json", {"render.spp=2"}, false, {"diffuse", "reflection", "refraction"});
  expect_groups_sum_to_beauty("scenes/materials.json", {"render.spp=2"}, true, {"diffuse", "reflection", "refraction"});
  // Clamping scales each group as it scales the beauty.
  expect_groups_sum_to_beauty("scenes/cornell.json", {"render.clamp=0.3"}, false, {"emission", "diffuse"});
}

// The same first-hit AOVs per pixel from the wavefront and the scalar path; merged sample-range
// parts carry the AOVs' exact sums bit for bit.
TEST(Aovs, KernelMatchesScalarAndPartsMergeBitForBit) {
  const aw::Scene s = aw::load_scene(aw_test::source_path("scenes/cornell.json"),
                                     {"render.width=32", "render.height=24", "render.spp=6", kAll});
  const aw::RenderResult w = aw::render_wavefront(s, aw_test::quiet_options());
  const aw::RenderResult c = aw::render_scalar(s, aw_test::quiet_options());
  const aw::Image iw = w.image(s), ic = c.image(s);
  size_t close = 0, total = 0;
  for (size_t k = 0; k < iw.channels.size(); ++k)
    for (size_t p = 0; p < iw.channels[k].f.size(); ++p) {
      const double a = iw.channels[k].f[p], b = ic.channels[k].f[p];
      close += std::fabs(a - b) <= 1e-4 * std::max({1.0, std::fabs(a), std::fabs(b)});
      ++total;
    }
  std::printf("%.3f%% of AOV values agree within 1e-4\n", 100.0 * close / total);
  EXPECT_GE(double(close) / total, 0.99);

  std::vector<aw::FilmState> parts;
  for (auto [a, b] : std::vector<std::pair<uint32_t, uint32_t>>{{0, 2}, {2, 3}, {3, 6}}) {
    aw::RenderOptions o = aw_test::quiet_options();
    o.sample_start = a;
    o.sample_end = b;
    parts.push_back(aw::film_state(aw::render_wavefront(s, o), s));
  }
  std::string report;
  std::vector<std::string> warnings;
  bool resumable = false;
  const aw::FilmState m = aw::merge_films(parts, {"a", "b", "c"}, &report, &warnings, &resumable);
  EXPECT_TRUE(m.aov_acc == w.aov_acc) << "the merged AOV sums differ";
  EXPECT_EQ(m.acc, w.acc);
  // Through the EXR's film state and back.
  const std::string path = testing::TempDir() + "/aov_state_" + std::to_string(getpid()) + ".exr";
  aw::write_exr(path, aw::film_image(m, true));
  const aw::FilmState back = aw::read_film_state(path);
  EXPECT_EQ(back.aov_mask, w.aov_mask);
  EXPECT_TRUE(back.aov_acc == w.aov_acc);
  // A resumed film continues its AOVs too: the first part, resumed to all six samples.
  const aw::RenderResult first = aw::film_to_result(parts[0]);
  aw::RenderOptions more = aw_test::quiet_options();
  more.resume = &first;
  const aw::RenderResult resumed = aw::render_wavefront(s, more);
  EXPECT_TRUE(resumed.aov_acc == w.aov_acc) << "the resumed AOV sums differ";
  // Parts with other AOVs do not merge.
  const aw::Scene fewer = aw::load_scene(aw_test::source_path("scenes/cornell.json"),
                                         {"render.width=32", "render.height=24", "render.spp=6", "render.aovs=\"albedo\""});
  aw::RenderOptions o = aw_test::quiet_options();
  o.sample_start = 3;
  parts = {parts[0], aw::film_state(aw::render_wavefront(fewer, o), fewer)};
  EXPECT_THROW(aw::merge_films(parts, {"a", "b"}, &report, &warnings, &resumable), aw::SceneError);
}

// Signed exact sums: normals and positions of either sign come back as added.
TEST(Aovs, SignedSumsAreExact) {
  uint64_t w[2] = {0, 0};
  film_add_signed(w, -1.5f);
  EXPECT_EQ(aw::film_word_value_signed(w), -1.5);
  film_add_signed(w, 0.25f);
  EXPECT_EQ(aw::film_word_value_signed(w), -1.25);
  film_add_signed(w, 3.0f);
  EXPECT_EQ(aw::film_word_value_signed(w), 1.75);
  film_add_signed(w, -1.75f);
  EXPECT_EQ(w[0], 0u);
  EXPECT_EQ(w[1], 0u);
}

TEST(Aovs, UnknownNamesAreRefusedNamingThem) {
  try {
    aw::load_scene(plane_scene(), {"render.aovs=\"albedo,shadow\""});
    ADD_FAILURE() << "loaded";
  } catch (const aw::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("\"shadow\" is not an AOV"), std::string::npos) << e.what();
  }
  EXPECT_THROW(aw::load_scene(plane_scene(), {"render.aovs=[\"depth\", 3]"}), aw::SceneError);
  EXPECT_EQ(aw::load_scene(plane_scene(), {"render.aovs=[\"depth\", \"ao\"]"}).render.aovs,
            (1u << AW_AOV_DEPTH) | (1u << AW_AOV_AO));
}

}  // namespace
