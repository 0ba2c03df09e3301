// anisotropy.orientation rendered: "tangent" (mesh tangents interpolated per vertex) and "uv"
// (each triangle's dP/du) agree where the two frames are the same (a flat UV-mapped quad)
// and differ where they are not (a coarse sphere: smooth against faceted frames). Every image
// is rendered by both renderers, which must agree.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "host/render/render.h"
#include "host/scene/scene.h"
#include "tests/render/render_test_util.h"

namespace {

// A glossy, strongly anisotropic metal lit by a point light (a delta light: the highlight is
// found by light sampling alone, so it is nearly noise-free at a few samples per pixel).
std::string material(const char* orientation, float amount) {
  char b[512];
  std::snprintf(b, sizeof b, R"({ "diffuse": { "color": 0.05 },
      "reflection": { "weight": 1, "glossiness": 0.55, "color": [1, 0.8, 0.6],
                      "fresnel": { "use_ior": false, "facing": 0.9, "perpendicular": 1 } },
      "anisotropy": { "amount": %g, "rotation": 0.1, "orientation": "%s" } })",
                double(amount), orientation);
  return b;
}

std::string write_scene(const std::string& mat, const std::string& object, const std::string& camera) {
  std::string json = R"({
  "render": { "width": 40, "height": 40, "spp": 8, "seed": 11, "max_depth": 3 },
  "camera": )" + camera + R"(,
  "environment": { "type": "constant", "color": [0.05, 0.05, 0.05], "intensity": 1 },
  "lights": [ { "type": "point", "position": [0.5, 3, 2], "intensity": 20 } ],
  "materials": { "m": )" + mat + R"( },
  "objects": [ )" + object + R"( ]
})";
  return aw_test::write_temp_scene("aniso_frame", json);
}

struct Rendered {
  aw::Scene scene;
  aw::RenderResult wave, scalar;
};

// Renders with both renderers and checks that they agree (the repository's kernel-vs-scalar
// criterion: 99% of pixels within 1e-3, means within 1e-3) and that nothing was discarded.
Rendered render_both(const std::string& path, const std::string& what) {
  Rendered r{aw::load_scene(path), {}, {}};
  aw::RenderOptions o;
  r.wave = aw::render_wavefront(r.scene, o);
  r.scalar = aw::render_scalar(r.scene, o);
  aw::ImageDiff d = aw::compare_images(r.wave.image(r.scene), r.scalar.image(r.scene), 1e-3, 1e-4);
  std::printf("%s: kernel vs scalar %.2f%% of pixels within 1e-3, means %.6f vs %.6f\n", what.c_str(),
              d.frac_pixels_within * 100, d.mean_a, d.mean_b);
  EXPECT_GE(d.frac_pixels_within, 0.99) << what;
  EXPECT_LE(d.rel_mean_diff, 1e-3) << what;
  EXPECT_EQ(r.wave.stats.bad_samples, 0u) << what;
  EXPECT_EQ(r.scalar.stats.bad_samples, 0u) << what;
  return r;
}

// Mean absolute per-channel difference relative to the mean of `a`.
double rel_mean_abs_diff(const aw::RenderResult& a, const aw::RenderResult& b) {
  double diff = 0.0, sum = 0.0;
  for (size_t i = 0; i < a.sum.size(); ++i) {
    const size_t p = i / 3;
    const double va = a.sum[i] / a.count[p], vb = b.sum[i] / b.count[p];
    diff += std::fabs(va - vb);
    sum += std::fabs(va);
  }
  return sum > 0.0 ? diff / sum : 0.0;
}

const char* kTopCamera = R"({ "position": [0, 3, 2.5], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 50 })";

// A quad whose u edge is neither axis-aligned nor orthogonal to its v edge: its analytic
// tangent, normalize(edge_u), is the same direction as every triangle's dP/du.
const char* kQuad =
    R"({ "shape": "quad", "corner": [-1.2, 0, 0.8], "edge_u": [2, 0, -0.6], "edge_v": [0.4, 0, -1.8], "material": "m" })";

TEST(AnisotropyFrame, TangentAndUvAgreeOnAFlatUvMappedQuad) {
  Rendered tangent = render_both(write_scene(material("tangent", -0.9f), kQuad, kTopCamera), "quad, tangent");
  Rendered uv = render_both(write_scene(material("uv", -0.9f), kQuad, kTopCamera), "quad, uv");
  Rendered iso = render_both(write_scene(material("tangent", 0.0f), kQuad, kTopCamera), "quad, isotropic");
  // The two frames differ only by rounding, so the images agree pixel by pixel (the random
  // numbers are the same; a rounding-level change of a direction moves a value by far less
  // than 1e-3).
  for (auto which : {&Rendered::wave, &Rendered::scalar}) {
    aw::ImageDiff d = aw::compare_images((tangent.*which).image(tangent.scene), (uv.*which).image(uv.scene), 1e-3, 1e-4);
    std::printf("quad: tangent vs uv %.2f%% of pixels within 1e-3, max |diff| %.2e\n", d.frac_pixels_within * 100,
                d.max_abs_diff);
    EXPECT_GE(d.frac_pixels_within, 0.99);
    EXPECT_LE(d.rel_mean_diff, 1e-4);
  }
  // ... and the agreement is not vacuous: the anisotropy visibly changes the highlight.
  const double aniso_effect = rel_mean_abs_diff(tangent.wave, iso.wave);
  std::printf("quad: anisotropic vs isotropic, mean |diff| / mean = %.4f\n", aniso_effect);
  EXPECT_GT(aniso_effect, 0.05);
}

TEST(AnisotropyFrame, TangentAndUvDifferOnACoarseSphere) {
  // 12 x 6 segments: each triangle's dP/du (the "uv" frame) is a chord, up to 15 degrees off
  // the smooth analytic tangent the "tangent" frame interpolates, and it jumps from one
  // triangle to the next, so the stretched highlight is broken up into facets.
  const char* sphere = R"({ "shape": "sphere", "center": [0, 0, 0], "radius": 1, "segments": [12, 6], "material": "m" })";
  const char* camera = R"({ "position": [0, 1.5, 3.5], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 40 })";
  Rendered tangent = render_both(write_scene(material("tangent", -0.9f), sphere, camera), "sphere, tangent");
  Rendered uv = render_both(write_scene(material("uv", -0.9f), sphere, camera), "sphere, uv");
  for (auto which : {&Rendered::wave, &Rendered::scalar}) {
    const double d = rel_mean_abs_diff(tangent.*which, uv.*which);
    std::printf("sphere: tangent vs uv, mean |diff| / mean = %.4f\n", d);
    EXPECT_GT(d, 0.02);
  }
}

TEST(AnisotropyFrame, MeshesWithoutUvsOrWithGeneratedTangentsRenderCleanly) {
  // OBJ meshes carry no tangents: they are generated at pack time. two_tris_plain.obj has no
  // UVs and no normals (the generator falls back to the normal's basis); quad_full.obj has
  // both. No sample may be NaN (render_both checks bad_samples) and both renderers agree.
  const std::string meshes = std::string(ARCHWAVE_TEST_DATA) + "/scene/data/meshes/";
  for (const char* orientation : {"tangent", "uv"}) {
    for (const char* file : {"two_tris_plain.obj", "quad_full.obj"}) {
      const std::string transform = std::string(file) == "quad_full.obj"
                                        ? R"(, "transform": { "rotate": [-90, 0, 0], "translate": [-0.5, 0, 0.5] })"
                                        : R"(, "transform": { "translate": [-1, 0, -1] })";
      const std::string object = R"({ "shape": "mesh", "file": ")" + meshes + file + R"(", "material": "m")" + transform + "}";
      render_both(write_scene(material(orientation, 0.8f), object, kTopCamera), std::string(file) + ", " + orientation);
    }
  }
}

}  // namespace
