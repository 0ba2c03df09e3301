// Kernel specialisation (docs/design.md, principle 4): the program built for a scene's features
// renders the same image as the generic one, and a feature it lacks is never silently ignored.
#include <gtest/gtest.h>

#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "host/render/features.h"
#include "host/render/render.h"
#include "host/render/scene_pack.h"
#include "host/scene/scene.h"

namespace {

std::string src(const std::string& rel) { return std::string(ARCHWAVE_SOURCE_DIR) + "/" + rel; }

TEST(Specialisation, FeaturesDerivedFromTheScene) {
  aw::Scene cornell = aw::load_scene(src("scenes/cornell.json"));
  aw::FeatureSet f = aw::pack_scene(cornell, nullptr).features;
  EXPECT_EQ(f.describe(), "light_point light_quad");  // Lambert only: no material feature
  aw::Scene mats = aw::load_scene(src("scenes/materials.json"));
  aw::FeatureSet g = aw::pack_scene(mats, nullptr).features;
  for (int id : {aw::FeatureSet::REFLECTION, aw::FeatureSet::REFRACTION, aw::FeatureSet::TRANSLUCENCY,
                 aw::FeatureSet::ROUGH_DIFFUSE, aw::FeatureSet::ANISOTROPY, aw::FeatureSet::FOG,
                 aw::FeatureSet::INCANDESCENCE, aw::FeatureSet::FRESNEL_CONDUCTOR, aw::FeatureSet::FRESNEL_CURVE,
                 aw::FeatureSet::THIN_WALLED, aw::FeatureSet::LIGHT_QUAD, aw::FeatureSet::LIGHT_POINT})
    EXPECT_TRUE(g.on[id]) << aw::FeatureSet::name(id);
  // The sampler: Sobol' (the default) is in every build, the others only where the scene asks.
  EXPECT_EQ(aw::pack_scene(aw::load_scene(src("scenes/cornell.json"), {"render.sampler=independent"}), nullptr)
                .features.describe(),
            "light_point light_quad sampler_independent");
  EXPECT_EQ(aw::pack_scene(aw::load_scene(src("scenes/cornell.json"), {"render.sampler=zsobol"}), nullptr)
                .features.describe(),
            "light_point light_quad sampler_zsobol");
  // Every reflection lobe there is GGX (the default): no other BRDF is built.
  for (int id : {aw::FeatureSet::CUTOUT, aw::FeatureSet::BRDF_BECKMANN, aw::FeatureSet::BRDF_AS,
                 aw::FeatureSet::LIGHT_SPHERE, aw::FeatureSet::LIGHT_DISK})
    EXPECT_FALSE(g.on[id]) << aw::FeatureSet::name(id);
}

// BRDFs and Fresnel modes count only where a reflection lobe carries energy (weight and
// colour); thin walls only on a material that reflects or transmits.
TEST(Specialisation, BrdfFresnelAndThinWallFeaturesFollowTheLobesThatUseThem) {
  auto features = [](std::vector<std::string> defs) {
    aw::Scene s = aw::load_scene(src("scenes/cornell.json"), defs);
    return aw::pack_scene(s, nullptr).features.describe();
  };
  const std::string lights = "light_point light_quad";
  EXPECT_EQ(features({"materials.white.reflection.weight=0.5", "materials.white.reflection.brdf=beckmann"}),
            "reflection brdf_beckmann " + lights);
  EXPECT_EQ(features({"materials.white.reflection.weight=0.5",
                      "materials.white.reflection.brdf=ashikhmin_shirley_legacy"}),
            "reflection brdf_as " + lights);
  EXPECT_EQ(features({"materials.white.reflection.weight=0.5", "materials.white.reflection.brdf=ashikhmin_shirley"}),
            "reflection brdf_as " + lights);
  EXPECT_EQ(features({"materials.white.reflection.weight=0.5", "materials.white.reflection.fresnel.use_ior=false"}),
            "reflection fresnel_curve " + lights);
  EXPECT_EQ(features({"materials.white.reflection.weight=0.5", "materials.white.reflection.fresnel.medium=conductor",
                      "materials.white.reflection.fresnel.k=3"}),
            "reflection fresnel_conductor " + lights);
  // No energy in the lobe: none of its BRDF or Fresnel is built.
  EXPECT_EQ(features({"materials.white.reflection.weight=0", "materials.white.reflection.brdf=beckmann",
                      "materials.white.reflection.fresnel.use_ior=false"}),
            lights);
  EXPECT_EQ(features({"materials.white.reflection.weight=0.5", "materials.white.reflection.color=[0,0,0]",
                      "materials.white.reflection.brdf=beckmann"}),
            lights);
  // A thin wall that neither reflects nor transmits is a diffuse surface.
  EXPECT_EQ(features({"materials.white.reflection.weight=0", "materials.white.refraction.thin_walled=true"}), lights);
  EXPECT_EQ(features({"materials.white.refraction.weight=0.5", "materials.white.refraction.thin_walled=true"}),
            "refraction thin_walled " + lights);
}

// Same seed, same device: the specialised and the generic program compute the same floats
// (no fast math; the removed code paths contributed exact zeros), so the films are
// bit-identical — on a scene with few features and on one with many.
TEST(Specialisation, SameImageAsGenericKernels) {
  struct Case {
    const char* file;
    std::vector<std::string> defs;
  };
  // materials.json with its GGX lobes turned into the other BRDFs, so that every BRDF and
  // Fresnel mode is compiled out of one specialised build or another and in the generic one.
  const std::vector<std::string> other_brdfs = {"materials.floor.reflection.brdf=beckmann",
                                                "materials.plastic.reflection.brdf=ashikhmin_shirley",
                                                "materials.leaf.reflection.brdf=ashikhmin_shirley_legacy"};
  // The Cornell box also with each sampler that is a feature (common/rng.h).
  const Case cases[] = {{"scenes/cornell.json", {}},
                        {"scenes/cornell.json", {"render.sampler=independent"}},
                        {"scenes/cornell.json", {"render.sampler=zsobol"}},
                        {"scenes/materials.json", {}},
                        {"scenes/materials.json", other_brdfs}};
  for (const Case& c : cases) {
    std::vector<std::string> defs = {"render.width=96", "render.height=64", "render.spp=4"};
    defs.insert(defs.end(), c.defs.begin(), c.defs.end());
    aw::Scene s = aw::load_scene(src(c.file), defs);
    aw::RenderOptions spec, gen;
    gen.generic_kernels = true;
    aw::RenderResult a = aw::render_wavefront(s, spec), b = aw::render_wavefront(s, gen);
    EXPECT_NE(a.stats.kernel_features, b.stats.kernel_features);
    ASSERT_EQ(a.sum.size(), b.sum.size());
    size_t differ = 0;
    for (size_t i = 0; i < a.sum.size(); ++i) differ += a.sum[i] != b.sum[i];
    EXPECT_EQ(differ, 0u) << c.file << " (" << a.stats.kernel_features << "): " << differ << " of " << a.sum.size()
                          << " values differ";
  }
}

// A build that lacks a feature the scene uses must refuse to produce an image: every material
// feature (checked at every hit in the kernels), every light type and sampler (checked by the host).
// Each case gives the Cornell box's white material one feature; most cases then build the
// same few programs (the scene's features minus the one turned off), so PoCL compiles three.
TEST(Specialisation, MissingFeatureIsNeverSilentlyIgnored) {
  const std::string refl = "materials.white.reflection.weight=0.5";
  const std::string refr = "materials.white.refraction.weight=0.5";
  struct Case {
    const char* feature;
    std::vector<std::string> defs;
  };
  const Case cases[] = {
      {"REFLECTION", {refl}},
      {"REFRACTION", {refr}},
      {"TRANSLUCENCY",
       {refr, "materials.white.translucency.enable=true", "materials.white.translucency.weight=1"}},
      {"ROUGH_DIFFUSE", {"materials.white.diffuse.roughness=0.5"}},
      {"ANISOTROPY", {refl, "materials.white.anisotropy.amount=0.5"}},
      {"FOG", {refr, "materials.white.refraction.fog.enable=true", "materials.white.refraction.fog.distance=1"}},
      {"CUTOUT", {"materials.white.cutout_opacity=0.2"}},
      {"INCANDESCENCE", {"materials.white.incandescent.color=[1,1,1]"}},
      {"BRDF_BECKMANN", {refl, "materials.white.reflection.brdf=beckmann"}},
      {"BRDF_AS", {refl, "materials.white.reflection.brdf=ashikhmin_shirley"}},
      {"FRESNEL_CONDUCTOR", {refl, "materials.white.reflection.fresnel.medium=conductor"}},
      {"FRESNEL_CURVE", {refl, "materials.white.reflection.fresnel.use_ior=false"}},
      {"THIN_WALLED", {refr, "materials.white.refraction.thin_walled=true"}},
      {"LIGHT_QUAD", {}},
      {"LIGHT_POINT", {}},
      {"SAMPLER_INDEPENDENT", {"render.sampler=independent"}},
      {"SAMPLER_ZSOBOL", {"render.sampler=zsobol"}},
      {"TEXTURE", {R"(textures.t={"type":"checker"})", R"(materials.white.diffuse.color={"texture":"t"})"}},
      {"BUMP", {R"(textures.t={"type":"noise"})", "materials.white.bump.input=t"}},
  };
  for (const Case& c : cases) {
    std::vector<std::string> defs = {"render.width=32", "render.height=32", "render.spp=2"};
    defs.insert(defs.end(), c.defs.begin(), c.defs.end());
    aw::Scene s = aw::load_scene(src("scenes/cornell.json"), defs);
    // The case really uses the feature: the specialised build for the scene has it.
    aw::FeatureSet need = aw::pack_scene(s, nullptr).features;
    bool used = false;
    for (int i = 0; i < aw::FeatureSet::COUNT; ++i) used |= need.on[i] && c.feature == std::string(aw::FeatureSet::name(i));
    EXPECT_TRUE(used) << c.feature << " is not used by its case: " << need.describe();
    aw::RenderOptions o;
    o.force_off = {c.feature};
    try {
      aw::render_wavefront(s, o);
      ADD_FAILURE() << "rendering without " << c.feature << " should fail";
    } catch (const std::logic_error& e) {
      EXPECT_NE(std::string(e.what()).find("lack"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
