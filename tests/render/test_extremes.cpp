// docs/design.md, principle 7: glossiness 0 and 1, IOR exactly 1 (and near it), huge extinction,
// anisotropy ±1, grazing angles, degenerate triangles, zero-area lights: no NaN or Inf ever
// reaches the film, and no sample is discarded for being non-finite (the guard in
// path_result must not be what keeps the image clean). Both renderers.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <fstream>
#include <string>

#include "host/render/render.h"
#include "host/scene/scene.h"
#include "tests/render/render_test_util.h"

namespace {

// One scene per material: a sphere, a quad at grazing view, and an OBJ-free degenerate
// triangle fan (a disk of radius ~0 collapses to degenerate triangles), lit by every light
// type including a vanishingly small quad and a tiny, very bright sphere, plus lights of
// exactly zero area or radius (the loader drops those with a warning).
std::string scene_for(const std::string& material) {
  std::string json = R"({
  "render": { "width": 24, "height": 16, "spp": 8, "seed": 5, "max_depth": 12 },
  "camera": { "position": [0, 0.6, 4], "look_at": [0, 0.5, 0], "up": [0, 1, 0], "fov": 50 },
  "environment": { "type": "constant", "color": [0.5, 0.6, 0.7], "intensity": 1 },
  "lights": [
    { "type": "quad", "corner": [-1, 3, -1], "edge_u": [2, 0, 0], "edge_v": [0, 0, 2], "intensity": 5 },
    { "type": "quad", "corner": [1, 2, 0], "edge_u": [1e-9, 0, 0], "edge_v": [0, 0, 1e-9], "intensity": 5 },
    { "type": "disk", "center": [-2, 2, 1], "normal": [1, -1, 0], "radius": 0.3, "intensity": 5 },
    { "type": "sphere", "center": [2, 1, 1], "radius": 0.0001, "intensity": 1000 },
    { "type": "point", "position": [0, 2, 2], "intensity": 3 },
    { "type": "quad", "corner": [1, 2, 0], "edge_u": [0, 0, 0], "edge_v": [0, 0, 1], "intensity": 5 },
    { "type": "sphere", "center": [2, 1, 1], "radius": 0, "intensity": 1000 },
    { "type": "disk", "center": [-2, 2, 1], "radius": 0, "intensity": 5 }
  ],
  "materials": { "m": )" + material + R"( },
  "objects": [
    { "shape": "sphere", "center": [0, 0.5, 0], "radius": 0.5, "material": "m" },
    { "shape": "quad", "corner": [-3, 0, 3], "edge_u": [6, 0, 0], "edge_v": [0, 0, -6], "material": "m" },
    { "shape": "disk", "center": [1, 0.5, 0.5], "normal": [0, 0, 1], "radius": 1e-20, "material": "m" },
    { "shape": "box", "min": [-1.5, 0, -0.5], "max": [-1.0, 1e-7, 0.5], "material": "m" }
  ]
})";
  return aw_test::write_temp_scene("extreme", json);
}

const char* kMaterials[] = {
    // glossiness 0 and 1 for every BRDF, with anisotropy at both ends
    R"({ "reflection": { "weight": 1, "glossiness": 0, "brdf": "ggx" }, "anisotropy": { "amount": 1 } })",
    R"({ "reflection": { "weight": 1, "glossiness": 0, "brdf": "beckmann" }, "anisotropy": { "amount": -1 } })",
    R"({ "reflection": { "weight": 1, "glossiness": 0, "brdf": "ashikhmin_shirley" }, "anisotropy": { "amount": 1 } })",
    R"({ "reflection": { "weight": 1, "glossiness": 0, "brdf": "ashikhmin_shirley_legacy" }, "anisotropy": { "amount": -1 } })",
    R"({ "reflection": { "weight": 1, "glossiness": 1, "brdf": "ggx" }, "anisotropy": { "amount": 1, "rotation": 0.25 } })",
    R"({ "reflection": { "weight": 1, "glossiness": 0.999, "brdf": "beckmann" } })",
    R"({ "reflection": { "weight": 1, "glossiness": 0.999, "brdf": "ashikhmin_shirley" } })",
    // conductor with extreme k, curve with extreme exponent
    R"({ "metal": true, "reflection": { "weight": 1, "glossiness": 0.5,
         "fresnel": { "medium": "conductor", "lock_to_refraction_ior": false, "ior": 0.01, "k": 1000 } } })",
    R"({ "reflection": { "weight": 1, "glossiness": 0.5, "fresnel": { "use_ior": false, "facing": 0, "perpendicular": 1, "curve": 1000 } } })",
    // refraction: IOR exactly 1, just off 1, huge; glossiness 0 and 1; TIR-heavy
    R"({ "refraction": { "weight": 1, "ior": 1, "glossiness": 0 } })",
    R"({ "refraction": { "weight": 1, "ior": 1.0011, "glossiness": 1 } })",
    R"({ "refraction": { "weight": 1, "ior": 1.0011, "glossiness": 0 } })",
    R"({ "reflection": { "weight": 1 }, "refraction": { "weight": 1, "ior": 10, "glossiness": 0 } })",
    R"({ "reflection": { "weight": 0.2 }, "refraction": { "weight": 1, "ior": 1.5, "glossiness": 0.3 } })",
    // fog: huge extinction, tiny distance, end colour 0
    R"({ "refraction": { "weight": 1, "ior": 1.5, "fog": { "enable": true, "distance": 1e-6 } } })",
    R"({ "refraction": { "weight": 1, "ior": 1.5, "fog": { "enable": true, "distance": 1e-6, "use_end_color": true, "end_color": [0, 0.5, 1] } } })",
    // thin walls, translucency, rough diffuse at the ends
    R"({ "refraction": { "weight": 1, "ior": 1.5, "glossiness": 0, "thin_walled": true } })",
    R"({ "translucency": { "enable": true, "weight": 1 }, "refraction": { "weight": 1 } })",
    R"({ "diffuse": { "roughness": 1, "color": [1, 1, 1] }, "reflection": { "weight": 0 } })",
    // cutout and incandescence
    R"({ "cutout_opacity": 0.2, "incandescent": { "color": [1, 1, 1], "scale": 100 } })",
};

// The wavefront renders with the generic kernels: one program for the twenty materials instead
// of one per feature set (most of this test's time was PoCL compiling a dozen of them; the
// specialised builds render the same image as the generic one: Specialisation.*).
TEST(Extremes, NoNonFiniteSampleAtAnyParameterExtreme) {
  for (const char* m : kMaterials) {
    aw::Scene s = aw::load_scene(scene_for(m));
    aw::RenderOptions o;
    o.generic_kernels = true;
    for (bool scalar : {false, true}) {
      aw::RenderResult r = scalar ? aw::render_scalar(s, o) : aw::render_wavefront(s, o);
      EXPECT_EQ(r.stats.bad_samples, 0u) << (scalar ? "scalar: " : "wavefront: ") << m;
      bool finite = true;
      for (float v : r.sum) finite = finite && std::isfinite(v) && v >= 0.0f;
      EXPECT_TRUE(finite) << m;
    }
  }
}

}  // namespace
