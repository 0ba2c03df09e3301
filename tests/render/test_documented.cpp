// The material's documented behaviours (docs/material.md), rendered. Each scene is built so that
// the right answer is exact: a constant environment seen through or reflected by one object.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "host/render/render.h"
#include "host/scene/scene.h"
#include "tests/render/render_test_util.h"

namespace {

std::string write_scene(const std::string& materials, const std::string& objects, const std::string& extra = "") {
  std::string json = R"({
  "render": { "width": 32, "height": 32, "spp": 16, "seed": 2, "max_depth": 8 },
  "camera": { "position": [0, 0, 4], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 30 },
  "environment": { "type": "constant", "color": [0.2, 0.4, 0.8], "intensity": 1 },
  "materials": {)" + materials + R"(},
  "objects": [)" + objects + R"(])" + extra + R"(
})";
  return aw_test::write_temp_scene("documented", json);
}

struct Rendered {
  aw::RenderResult wave, scalar;
};

Rendered render_both(const std::string& path) {
  aw::Scene s = aw::load_scene(path);
  aw::RenderOptions o;
  return {aw::render_wavefront(s, o), aw::render_scalar(s, o)};
}

float px(const aw::RenderResult& r, int x, int y, int c) {
  size_t p = size_t(y) * r.width + x;
  return r.sum[p * 3 + c] / float(r.count[p]);
}

const float kEnv[3] = {0.2f, 0.4f, 0.8f};

// docs/material.md §1: refraction.glossiness has "no effect when IOR = 1", and refraction weight 1
// with IOR 1 makes an object invisible except for its Fresnel — which is 0 at IOR 1. So a
// sphere of it in front of a constant environment leaves exactly the environment.
TEST(Documented, RefractionWithIorOneIsInvisible) {
  for (const char* gloss : {"1", "0.3"}) {
    std::string mat = std::string(R"("ghost": { "refraction": { "weight": 1, "ior": 1, "glossiness": )") + gloss +
                      R"( }, "diffuse": { "color": [1, 0, 0] } })";
    Rendered r = render_both(write_scene(mat, R"({ "shape": "sphere", "center": [0, 0, 0], "radius": 1, "material": "ghost" })"));
    for (const aw::RenderResult* res : {&r.wave, &r.scalar})
      for (int y = 0; y < res->height; ++y)
        for (int x = 0; x < res->width; ++x)
          for (int c = 0; c < 3; ++c) ASSERT_NEAR(px(*res, x, y, c), kEnv[c], 1e-5) << "glossiness " << gloss << " at " << x << "," << y;
  }
}

// A perfect mirror (weight 1, colour 1, reflectivity 1: the curve with facing = perpendicular
// = 1) takes all the energy (docs/material.md §2, "mirror wins"): the diffuse colour cannot matter.
// Rendered with a white and with a black diffuse colour, the images are bit-identical, and
// (away from the silhouette, where interpolated normals may send a reflection below the
// surface) every pixel is the environment it reflects.
TEST(Documented, PerfectMirrorRendersNoDiffuse) {
  auto mirror = [](const char* diffuse) {
    return std::string(R"("mirror": { "diffuse": { "color": )") + diffuse + R"( },
      "reflection": { "weight": 1, "color": [1, 1, 1], "glossiness": 1,
                      "fresnel": { "use_ior": false, "facing": 1, "perpendicular": 1 } } })";
  };
  const char* sphere = R"({ "shape": "sphere", "center": [0, 0, 0], "radius": 1, "material": "mirror" })";
  Rendered white = render_both(write_scene(mirror("[1, 1, 1]"), sphere));
  Rendered black = render_both(write_scene(mirror("[0, 0, 0]"), sphere));
  EXPECT_EQ(white.wave.sum, black.wave.sum);
  EXPECT_EQ(white.scalar.sum, black.scalar.sum);
  int exact = 0;
  for (int y = 0; y < white.wave.height; ++y)
    for (int x = 0; x < white.wave.width; ++x) exact += std::fabs(px(white.wave, x, y, 2) - kEnv[2]) < 1e-5f;
  EXPECT_GT(exact, 32 * 32 * 95 / 100);
}

// Equal facing and perpendicular reflectivity gives view-independent reflection: a black
// mirror-glossy sphere with facing = perpendicular = 0.5 shows 0.5 x the environment at every
// pixel it covers, centre and rim alike.
TEST(Documented, EqualFacingAndPerpendicularIsViewIndependent) {
  std::string mat = R"("half": { "diffuse": { "color": [0, 0, 0] },
      "reflection": { "weight": 1, "glossiness": 1, "fresnel": { "use_ior": false, "facing": 0.5, "perpendicular": 0.5 } } })";
  Rendered r = render_both(write_scene(mat, R"({ "shape": "sphere", "center": [0, 0, 0], "radius": 1, "material": "half" })"));
  int on_sphere = 0;
  for (const aw::RenderResult* res : {&r.wave, &r.scalar})
    for (int y = 0; y < res->height; ++y)
      for (int x = 0; x < res->width; ++x) {
        float v = px(*res, x, y, 2);
        // Either background (env) or sphere (0.5 env); pixels on the silhouette mix both, and
        // also samples that graze the tessellated rim, where an interpolated normal can send
        // the reflection below the surface (the path then ends: 0; see PerfectMirrorRendersNoDiffuse).
        // So a mixed pixel lies in [0, env] and must touch the background (or the frame's edge,
        // which the sphere reaches: beyond it lies background too).
        auto is_bg = [&](int xx, int yy) {
          return xx >= 0 && yy >= 0 && xx < res->width && yy < res->height &&
                 std::fabs(px(*res, xx, yy, 2) - kEnv[2]) < 1e-5f;
        };
        bool bg = is_bg(x, y), sph = std::fabs(v - 0.5f * kEnv[2]) < 1e-5f;
        if (sph) ++on_sphere;
        if (!bg && !sph) {
          ASSERT_GE(v, 0.0f);
          ASSERT_LT(v, kEnv[2] + 1e-5f);
          bool touches = false;
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              int xx = x + dx, yy = y + dy;
              bool outside = xx < 0 || yy < 0 || xx >= res->width || yy >= res->height;
              touches = touches || outside || is_bg(xx, yy);
            }
          ASSERT_TRUE(touches) << "a mixed pixel away from the silhouette at " << x << "," << y << ": " << v;
        }
      }
  EXPECT_GT(on_sphere, 2 * 200) << "most of the sphere's pixels are exactly 0.5 env";
}

// Fog with end colour C at distance D transmits C^(d/D) over a path length d inside. A slab
// of IOR 1 (no bending, no Fresnel) 1 unit thick with D = 2 and C = (0.25, 0.5, 1) must
// transmit (0.5, 0.7071, 1).
TEST(Documented, FogEndColourTransmitsPowerOfDistance) {
  std::string mat = R"("fog": { "diffuse": { "weight": 0 }, "reflection": { "weight": 0 },
      "refraction": { "weight": 1, "ior": 1,
                      "fog": { "enable": true, "distance": 2, "use_end_color": true, "end_color": [0.25, 0.5, 1] } } })";
  Rendered r = render_both(write_scene(mat, R"({ "shape": "box", "min": [-3, -3, -0.5], "max": [3, 3, 0.5], "material": "fog" })"));
  // The centre pixel's ray crosses the slab along z: d = 1 (the view is narrow: 15 degrees
  // off axis at most, so d <= 1.035; the centre pixels are within 0.5 degrees).
  const float expect[3] = {kEnv[0] * 0.5f, kEnv[1] * std::sqrt(0.5f), kEnv[2] * 1.0f};
  for (const aw::RenderResult* res : {&r.wave, &r.scalar})
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(px(*res, 16, 16, c) / expect[c], 1.0, 2e-3) << "channel " << c;
}

// Cutout opacity < 0.5: the surface is not there, for every kind of ray (docs/material.md §1). A
// cutout sheet between a light and the floor changes nothing: shadow rays step through it and
// BSDF-sampled rays that find the light through it are MIS-weighted from their true origin.
TEST(Documented, CutoutSurfaceIsNotThereForAnyRay) {
  auto scene = [](bool with_sheet) {
    std::string json = R"({
  "render": { "width": 24, "height": 16, "spp": 64, "seed": 4, "max_depth": 3 },
  "camera": { "position": [0, 0.4, 4], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 30 },
  "lights": [ { "type": "quad", "corner": [-1, 2, -1], "edge_u": [2, 0, 0], "edge_v": [0, 0, 2], "intensity": 3 } ],
  "materials": { "floor": { "diffuse": { "color": [0.8, 0.8, 0.8] }, "reflection": { "weight": 0 } },
                 "sheet": { "diffuse": { "color": [0.1, 0.1, 0.1] }, "reflection": { "weight": 0 }, "cutout_opacity": 0.3 } },
  "objects": [ { "shape": "quad", "corner": [-5, 0, 5], "edge_u": [10, 0, 0], "edge_v": [0, 0, -10], "material": "floor" })" +
                       std::string(with_sheet ? R"(,
               { "shape": "quad", "corner": [-3, 1, 3], "edge_u": [6, 0, 0], "edge_v": [0, 0, -6], "material": "sheet" })" : "") +
                       R"( ]
})";
    return aw_test::write_temp_scene("cutout", json);
  };
  Rendered open = render_both(scene(false)), sheet = render_both(scene(true));
  for (int which = 0; which < 2; ++which) {
    const aw::RenderResult& a = which ? open.scalar : open.wave;
    const aw::RenderResult& b = which ? sheet.scalar : sheet.wave;
    ASSERT_EQ(a.sum.size(), b.sum.size());
    double sa = 0.0, sb = 0.0;
    for (size_t i = 0; i < a.sum.size(); ++i) {
      sa += a.sum[i];
      sb += b.sum[i];
      ASSERT_NEAR(a.sum[i], b.sum[i], 1e-5f * std::max(1.0f, a.sum[i])) << (which ? "scalar" : "wavefront") << " at " << i;
    }
    EXPECT_GT(sa, 0.0);
  }
  aw::ImageDiff d = aw::compare_images(aw::Image{sheet.wave.width, sheet.wave.height, sheet.wave.sum, {}, {}},
                                       aw::Image{sheet.scalar.width, sheet.scalar.height, sheet.scalar.sum, {}, {}}, 1e-3, 1e-4);
  EXPECT_GE(d.frac_pixels_within, 0.99);
}

// Kernel vs scalar on a scene that uses every lobe (the material issue's equivalence test).
TEST(Documented, EveryLobeSceneKernelMatchesScalar) {
  aw::Scene s = aw::load_scene(std::string(ARCHWAVE_SOURCE_DIR) + "/scenes/materials.json",
                               {"render.width=128", "render.height=64", "render.spp=8"});
  aw::RenderOptions o;
  aw::RenderResult w = aw::render_wavefront(s, o), sc = aw::render_scalar(s, o);
  aw::ImageDiff d = aw::compare_images(w.image(s), sc.image(s), 1e-3, 1e-4);
  std::printf("every-lobe scene: %.3f%% of pixels within 1e-3, means %.6f vs %.6f\n", d.frac_pixels_within * 100,
              d.mean_a, d.mean_b);
  EXPECT_GE(d.frac_pixels_within, 0.99);
  EXPECT_LE(d.rel_mean_diff, 1e-3);
  EXPECT_EQ(w.stats.bad_samples, 0u);
}

}  // namespace
