// Kernel specialisation (DESIGN.md principle 4): the program built for a scene's features
// renders the same image as the generic one, and a feature it lacks is never silently ignored.
#include <gtest/gtest.h>

#include <cstring>
#include <stdexcept>
#include <string>

#include "host/render/features.h"
#include "host/render/render.h"
#include "host/render/scene_pack.h"
#include "host/scene/scene.h"

namespace {

std::string src(const std::string& rel) { return std::string(ARCHWAVE_SOURCE_DIR) + "/" + rel; }

TEST(Specialisation, FeaturesDerivedFromTheScene) {
  aw::Scene cornell = aw::load_scene(src("scenes/cornell.json"));
  aw::FeatureSet f = aw::derive_features(aw::pack_scene(cornell, nullptr));
  EXPECT_EQ(f.describe(), "light_point light_quad");  // Lambert only: no material feature
  aw::Scene mats = aw::load_scene(src("scenes/materials.json"));
  aw::FeatureSet g = aw::derive_features(aw::pack_scene(mats, nullptr));
  for (int id : {aw::FeatureSet::REFLECTION, aw::FeatureSet::REFRACTION, aw::FeatureSet::TRANSLUCENCY,
                 aw::FeatureSet::ROUGH_DIFFUSE, aw::FeatureSet::ANISOTROPY, aw::FeatureSet::FOG,
                 aw::FeatureSet::INCANDESCENCE, aw::FeatureSet::LIGHT_QUAD, aw::FeatureSet::LIGHT_POINT})
    EXPECT_TRUE(g.on[id]) << aw::FeatureSet::name(id);
  EXPECT_FALSE(g.on[aw::FeatureSet::CUTOUT]);
  EXPECT_FALSE(g.on[aw::FeatureSet::LIGHT_SPHERE]);
}

// Same seed, same device: the specialised and the generic program compute the same floats
// (no fast math; the removed code paths contributed exact zeros), so the films are
// bit-identical — on a scene with few features and on one with many.
TEST(Specialisation, SameImageAsGenericKernels) {
  for (const char* scene_file : {"scenes/cornell.json", "scenes/materials.json"}) {
    aw::Scene s = aw::load_scene(src(scene_file), {"render.width=96", "render.height=64", "render.spp=4"});
    aw::RenderOptions spec, gen;
    gen.generic_kernels = true;
    aw::RenderResult a = aw::render_wavefront(s, spec), b = aw::render_wavefront(s, gen);
    EXPECT_NE(a.stats.kernel_features, b.stats.kernel_features);
    ASSERT_EQ(a.sum.size(), b.sum.size());
    size_t differ = 0;
    for (size_t i = 0; i < a.sum.size(); ++i) differ += a.sum[i] != b.sum[i];
    EXPECT_EQ(differ, 0u) << scene_file << ": " << differ << " of " << a.sum.size() << " values differ";
  }
}

// A build that lacks a feature the scene uses must refuse to produce an image.
TEST(Specialisation, MissingFeatureIsNeverSilentlyIgnored) {
  aw::Scene s = aw::load_scene(src("scenes/materials.json"), {"render.width=32", "render.height=16", "render.spp=2"});
  for (const char* feature : {"REFLECTION", "REFRACTION", "TRANSLUCENCY"}) {
    aw::RenderOptions o;
    o.force_off = {feature};
    try {
      aw::render_wavefront(s, o);
      ADD_FAILURE() << "rendering without " << feature << " should fail";
    } catch (const std::logic_error& e) {
      EXPECT_NE(std::string(e.what()).find("lack"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
