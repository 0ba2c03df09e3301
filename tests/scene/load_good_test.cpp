// A complete, valid scene: every section, explicit values and defaults.
#include <gtest/gtest.h>

#include "tests/scene/scene_test_util.h"

using aw_test::data_path;

namespace {

void expect_vec3(const glm::vec3& v, float x, float y, float z) {
  EXPECT_FLOAT_EQ(v.x, x);
  EXPECT_FLOAT_EQ(v.y, y);
  EXPECT_FLOAT_EQ(v.z, z);
}

class GoodFullScene : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = new aw::Scene(aw::load_scene(data_path("good_full.json")));
  }
  static void TearDownTestSuite() {
    delete scene_;
    scene_ = nullptr;
  }
  static aw::Scene* scene_;
};
aw::Scene* GoodFullScene::scene_ = nullptr;

TEST_F(GoodFullScene, RenderSettings) {
  const aw::RenderSettings& r = scene_->render;
  EXPECT_EQ(r.width, 320);
  EXPECT_EQ(r.height, 200);
  EXPECT_EQ(r.spp, 32);
  EXPECT_EQ(r.seed, 4294967295u);
  EXPECT_EQ(r.max_depth, 6);
  EXPECT_EQ(r.reflection_depth, 4);
  EXPECT_EQ(r.refraction_depth, 5);
  EXPECT_FALSE(r.gi);
  EXPECT_FLOAT_EQ(r.cutoff, 0.01f);
  EXPECT_FALSE(r.lobe_splitting);
  EXPECT_FLOAT_EQ(r.clamp, 10.0f);
  EXPECT_EQ(scene_->path, data_path("good_full.json"));
  EXPECT_TRUE(scene_->warnings.empty());
}

TEST_F(GoodFullScene, CameraAndExposure) {
  const aw::CameraDesc& c = scene_->camera;
  expect_vec3(c.position, 1, 2, 5);
  expect_vec3(c.look_at, 0, 0.5f, 0);
  expect_vec3(c.up, 0, 1, 0);
  EXPECT_FLOAT_EQ(c.fov, 35.5f);
  EXPECT_EQ(c.exposure.mode, aw::ExposureDesc::Mode::Photographic);
  EXPECT_FLOAT_EQ(c.exposure.iso, 200);
  EXPECT_FLOAT_EQ(c.exposure.shutter, 50);
  EXPECT_FLOAT_EQ(c.exposure.f_number, 8);
  expect_vec3(c.exposure.whitepoint, 1, 0.9f, 0.8f);
  EXPECT_FLOAT_EQ(c.exposure.vignetting, 0.5f);
  // (1/50) * 200 / (8^2 * 100)
  EXPECT_FLOAT_EQ(aw::exposure_scale(c.exposure), 0.000625f);
}

TEST_F(GoodFullScene, Environment) {
  EXPECT_EQ(scene_->environment.type, aw::EnvironmentDesc::Type::Constant);
  expect_vec3(scene_->environment.color, 0.1f, 0.2f, 0.3f);
  EXPECT_FLOAT_EQ(scene_->environment.intensity, 2);
}

TEST_F(GoodFullScene, Lights) {
  const auto& l = scene_->lights;
  ASSERT_EQ(l.size(), 4u);
  EXPECT_EQ(l[0].type, aw::LightDesc::Type::Point);
  expect_vec3(l[0].position, 0, 3, 0);
  expect_vec3(l[0].color, 1, 0.2f, 0.2f);
  EXPECT_FLOAT_EQ(l[0].intensity, 20);

  EXPECT_EQ(l[1].type, aw::LightDesc::Type::Quad);
  expect_vec3(l[1].corner, -0.5f, 2.99f, -0.5f);
  expect_vec3(l[1].edge_u, 1, 0, 0);
  expect_vec3(l[1].edge_v, 0, 0, 1);
  EXPECT_TRUE(l[1].two_sided);
  EXPECT_FALSE(l[1].visible);

  EXPECT_EQ(l[2].type, aw::LightDesc::Type::Disk);
  expect_vec3(l[2].center, 0, 3, 0);
  expect_vec3(l[2].normal, 0, -1, 0);  // normalised from [0, -2, 0]
  EXPECT_FLOAT_EQ(l[2].radius, 0.5f);
  expect_vec3(l[2].color, 0.5f, 0.5f, 0.5f);  // a single number is grey
  EXPECT_FALSE(l[2].two_sided);
  EXPECT_TRUE(l[2].visible);

  EXPECT_EQ(l[3].type, aw::LightDesc::Type::Sphere);
  expect_vec3(l[3].center, 2, 3, 0);
  EXPECT_FLOAT_EQ(l[3].radius, 0.25f);
  EXPECT_FLOAT_EQ(l[3].intensity, 5);
}

TEST_F(GoodFullScene, MaterialNamesInFileOrder) {
  // File order, not alphabetical ("plain" < "floor" would sort differently).
  const std::vector<std::string> expected = {"floor", "bronze", "glass", "plain"};
  EXPECT_EQ(scene_->material_names, expected);
  EXPECT_EQ(scene_->materials.size(), 4u);
}

TEST_F(GoodFullScene, ExplicitMaterialValues) {
  const aw::MaterialDesc& floor = scene_->materials[0];
  expect_vec3(floor.diffuse.color, 0.8f, 0.7f, 0.6f);

  const aw::MaterialDesc& bronze = scene_->materials[1];
  EXPECT_FLOAT_EQ(bronze.diffuse.roughness, 0.25f);
  EXPECT_TRUE(bronze.metal);
  EXPECT_FLOAT_EQ(bronze.reflection.weight, 1);
  EXPECT_FLOAT_EQ(bronze.reflection.glossiness, 0.6f);
  EXPECT_EQ(bronze.reflection.brdf, aw::Brdf::Beckmann);
  EXPECT_FALSE(bronze.reflection.fresnel.use_ior);
  EXPECT_EQ(bronze.reflection.fresnel.medium, aw::FresnelMedium::Conductor);
  EXPECT_FLOAT_EQ(bronze.reflection.fresnel.k, 3.5f);
  EXPECT_FLOAT_EQ(bronze.reflection.fresnel.facing, 0.5f);
  EXPECT_FLOAT_EQ(bronze.reflection.fresnel.perpendicular, 0.9f);
  EXPECT_FLOAT_EQ(bronze.reflection.fresnel.curve, 3);
  EXPECT_FLOAT_EQ(bronze.anisotropy.amount, -0.8f);
  EXPECT_FLOAT_EQ(bronze.anisotropy.rotation, 0.25f);
  EXPECT_EQ(bronze.anisotropy.orientation, aw::AnisoOrientation::Uv);
  EXPECT_EQ(bronze.anisotropy.uv_set, 0);

  const aw::MaterialDesc& glass = scene_->materials[2];
  EXPECT_FLOAT_EQ(glass.diffuse.weight, 0);
  EXPECT_FLOAT_EQ(glass.reflection2.weight, 0.3f);
  expect_vec3(glass.reflection2.color, 0.5f, 0.5f, 0.5f);
  EXPECT_EQ(glass.reflection2.brdf, aw::Brdf::AshikhminShirleyLegacy);
  EXPECT_EQ(glass.reflection2.samples, 4);
  EXPECT_FLOAT_EQ(glass.refraction.weight, 1);
  EXPECT_FLOAT_EQ(glass.refraction.ior, 1.5f);
  EXPECT_TRUE(glass.refraction.thin_walled);
  EXPECT_TRUE(glass.refraction.fog.enable);
  EXPECT_FLOAT_EQ(glass.refraction.fog.distance, 1);
  EXPECT_TRUE(glass.refraction.fog.use_end_color);
  expect_vec3(glass.refraction.fog.end_color, 0.53f, 0.1f, 0.1f);
  EXPECT_TRUE(glass.ao.enable);
  EXPECT_EQ(glass.ao.combine, aw::AoCombine::Multiply);
  EXPECT_EQ(glass.ao.samples, 32);
  expect_vec3(glass.ao.shadow_color, 0.1f, 0.1f, 0.1f);
  EXPECT_FLOAT_EQ(glass.ao.max_distance, 2.5f);
  EXPECT_TRUE(glass.optimizations.trace_depth_override);
  EXPECT_EQ(glass.optimizations.reflection_depth, 2);
  EXPECT_EQ(glass.optimizations.refraction_depth, 5);  // default kept next to a set sibling
  EXPECT_TRUE(glass.optimizations.reflection_cutoff.enable);
  EXPECT_FLOAT_EQ(glass.optimizations.reflection_cutoff.threshold, 0.05f);
  EXPECT_FALSE(glass.optimizations.refraction_cutoff.enable);
  EXPECT_FLOAT_EQ(glass.optimizations.refraction_cutoff.threshold, 0.02f);
  EXPECT_FLOAT_EQ(glass.cutout_opacity, 0.75f);
  expect_vec3(glass.incandescent.color, 2, 1, 0.5f);  // emission may exceed 1
  EXPECT_FLOAT_EQ(glass.incandescent.scale, 3);
  EXPECT_TRUE(glass.propagate_alpha);
  EXPECT_FLOAT_EQ(glass.bump.scale, 0.5f);
  EXPECT_TRUE(glass.bump.add_to_material_bump);
  EXPECT_TRUE(glass.bump.input.empty());
}

// The values below are docs/material.md §1's defaults, written out rather than compared with a
// default-constructed MaterialDesc, so a drifting default in the struct is caught too.
TEST_F(GoodFullScene, ArchitecturalDefaultsOfAnEmptyMaterial) {
  const aw::MaterialDesc& m = scene_->materials[3];  // "plain": {}
  expect_vec3(m.diffuse.color, 0.5f, 0.5f, 0.5f);
  EXPECT_FLOAT_EQ(m.diffuse.weight, 1.0f);
  EXPECT_FLOAT_EQ(m.diffuse.roughness, 0.0f);
  EXPECT_FALSE(m.translucency.enable);
  expect_vec3(m.translucency.color, 0.7f, 0.6f, 0.5f);
  EXPECT_FLOAT_EQ(m.translucency.weight, 0.5f);
  EXPECT_FLOAT_EQ(m.reflection.weight, 0.6f);
  EXPECT_FLOAT_EQ(m.reflection2.weight, 0.0f);
  expect_vec3(m.reflection.color, 1, 1, 1);
  EXPECT_EQ(m.reflection.brdf, aw::Brdf::Ggx);
  EXPECT_FLOAT_EQ(m.reflection.glossiness, 1.0f);
  EXPECT_EQ(m.reflection.samples, 8);
  EXPECT_TRUE(m.reflection.fresnel.use_ior);
  EXPECT_TRUE(m.reflection.fresnel.lock_to_refraction_ior);
  EXPECT_FLOAT_EQ(m.reflection.fresnel.ior, 1.5f);
  EXPECT_EQ(m.reflection.fresnel.medium, aw::FresnelMedium::Dielectric);
  EXPECT_FLOAT_EQ(m.reflection.fresnel.facing, 0.2f);
  EXPECT_FLOAT_EQ(m.reflection.fresnel.perpendicular, 1.0f);
  EXPECT_FLOAT_EQ(m.reflection.fresnel.curve, 5.0f);
  EXPECT_FALSE(m.metal);
  EXPECT_FLOAT_EQ(m.highlight_vs_reflection, 1.0f);
  EXPECT_EQ(m.anisotropy.orientation, aw::AnisoOrientation::Tangent);
  EXPECT_FLOAT_EQ(m.refraction.weight, 0.0f);
  EXPECT_FLOAT_EQ(m.refraction.ior, 1.4f);
  EXPECT_EQ(m.refraction.samples, 8);
  EXPECT_FALSE(m.refraction.caustics);
  EXPECT_TRUE(m.refraction.allow_global_volume);
  expect_vec3(m.refraction.fog.end_color, 0, 0, 0);
  EXPECT_EQ(m.ao.combine, aw::AoCombine::Add);
  EXPECT_EQ(m.ao.samples, 16);
  EXPECT_FLOAT_EQ(m.ao.max_distance, 10.0f);
  EXPECT_FLOAT_EQ(m.ao.spread, 0.8f);
  EXPECT_FLOAT_EQ(m.ao.falloff, 1.0f);
  expect_vec3(m.ao.shadow_color, 0.2f, 0.2f, 0.2f);
  expect_vec3(m.ao.ambient_color, 1, 1, 1);
  EXPECT_EQ(m.optimizations.reflection_depth, 5);
  EXPECT_EQ(m.optimizations.refraction_depth, 5);
  EXPECT_TRUE(m.optimizations.skip_weak_internal_reflections);
  EXPECT_FALSE(m.optimizations.reflection_cutoff.enable);
  EXPECT_FLOAT_EQ(m.optimizations.reflection_cutoff.threshold, 0.01f);
  EXPECT_FLOAT_EQ(m.cutout_opacity, 1.0f);
  expect_vec3(m.incandescent.color, 0, 0, 0);
  EXPECT_FLOAT_EQ(m.incandescent.scale, 1.0f);
  EXPECT_FALSE(m.propagate_alpha);
  EXPECT_TRUE(m.bump.input.empty());
  EXPECT_FLOAT_EQ(m.bump.scale, 1.0f);
}

TEST_F(GoodFullScene, ObjectsAndMaterialIndices) {
  const auto& meshes = scene_->meshes;
  ASSERT_EQ(meshes.size(), 8u);
  EXPECT_EQ(meshes[0].name, "objects[0] (mesh meshes/quad_full.obj)");
  EXPECT_EQ(meshes[2].name, "objects[2] (sphere)");
  EXPECT_EQ(meshes[3].name, "objects[3] (quad)");
  EXPECT_EQ(meshes[4].name, "objects[4] (disk)");
  EXPECT_EQ(meshes[5].name, "objects[5] (box)");
  const uint32_t expected_material[8] = {2, 0, 1, 0, 3, 0, 3, 3};
  for (size_t i = 0; i < meshes.size(); ++i) {
    EXPECT_EQ(meshes[i].material, expected_material[i]) << meshes[i].name;
  }
  EXPECT_EQ(scene_->triangle_count(), 2u + 2u + 128u * 126u + 2u + 128u + 12u + 12u + 12u);
}

TEST_F(GoodFullScene, LoadingIsDeterministic) {
  const aw::Scene again = aw::load_scene(data_path("good_full.json"));
  ASSERT_EQ(again.meshes.size(), scene_->meshes.size());
  for (size_t i = 0; i < again.meshes.size(); ++i) {
    const aw::TriangleMesh& a = again.meshes[i];
    const aw::TriangleMesh& b = scene_->meshes[i];
    EXPECT_TRUE(a.positions == b.positions) << a.name;
    EXPECT_TRUE(a.normals == b.normals) << a.name;
    EXPECT_TRUE(a.uvs == b.uvs) << a.name;
    EXPECT_TRUE(a.indices == b.indices) << a.name;
  }
}

TEST(SceneDefaults, EmptyObjectGivesAllDefaults) {
  const aw::Scene s = aw::load_scene(data_path("good_empty.json"));
  EXPECT_EQ(s.render.width, 640);
  EXPECT_EQ(s.render.height, 480);
  EXPECT_EQ(s.render.spp, 64);
  EXPECT_EQ(s.render.seed, 0u);
  EXPECT_EQ(s.render.max_depth, 8);
  EXPECT_EQ(s.render.reflection_depth, 8);
  EXPECT_EQ(s.render.refraction_depth, 8);
  EXPECT_TRUE(s.render.gi);
  EXPECT_FLOAT_EQ(s.render.cutoff, 0.001f);
  EXPECT_TRUE(s.render.lobe_splitting);
  EXPECT_FLOAT_EQ(s.render.clamp, 0.0f);
  EXPECT_EQ(s.render.rr_depth, 4);
  expect_vec3(s.camera.position, 0, 1, 4);
  expect_vec3(s.camera.look_at, 0, 1, 0);
  expect_vec3(s.camera.up, 0, 1, 0);
  EXPECT_FLOAT_EQ(s.camera.fov, 40);
  EXPECT_EQ(s.camera.exposure.mode, aw::ExposureDesc::Mode::Stops);
  EXPECT_FLOAT_EQ(s.camera.exposure.stops, 0);
  EXPECT_FLOAT_EQ(aw::exposure_scale(s.camera.exposure), 1.0f);
  EXPECT_EQ(s.environment.type, aw::EnvironmentDesc::Type::Constant);
  expect_vec3(s.environment.color, 0, 0, 0);
  EXPECT_FLOAT_EQ(s.environment.intensity, 1);
  EXPECT_TRUE(s.lights.empty());
  EXPECT_TRUE(s.materials.empty());
  EXPECT_TRUE(s.material_names.empty());
  EXPECT_TRUE(s.meshes.empty());  // no objects: renders the environment only
  EXPECT_EQ(s.triangle_count(), 0u);
}

TEST(ExposureScale, StopsAndPhotographic) {
  aw::ExposureDesc e;
  e.stops = 2;
  EXPECT_FLOAT_EQ(aw::exposure_scale(e), 4.0f);
  e.stops = -1;
  EXPECT_FLOAT_EQ(aw::exposure_scale(e), 0.5f);
  e.mode = aw::ExposureDesc::Mode::Photographic;  // defaults: iso 100, 1/100 s, f/16
  EXPECT_FLOAT_EQ(aw::exposure_scale(e), 1.0f / 25600.0f);
  e.iso = 400;
  e.shutter = 25;
  e.f_number = 2;
  EXPECT_FLOAT_EQ(aw::exposure_scale(e), 0.04f * 400.0f / 400.0f);
}

TEST(SceneWarnings, OutOfRangeMaterialValuesAreClampedWithOneWarningEach) {
  const aw::Scene s = aw::load_scene(data_path("good_clamp.json"));
  ASSERT_EQ(s.materials.size(), 1u);
  const aw::MaterialDesc& m = s.materials[0];
  EXPECT_FLOAT_EQ(m.diffuse.weight, 1.0f);
  expect_vec3(m.diffuse.color, 1.0f, 0.5f, 0.0f);
  EXPECT_FLOAT_EQ(m.anisotropy.amount, 1.0f);
  EXPECT_EQ(m.reflection.samples, 1);
  EXPECT_FLOAT_EQ(m.reflection.glossiness, 0.5f);  // in range: untouched, no warning
  ASSERT_EQ(s.warnings.size(), 4u);  // weight, color (one for three components), amount, samples

  const std::string prefix = data_path("good_clamp.json");
  bool saw_weight = false;
  for (const std::string& w : s.warnings) {
    EXPECT_NE(w.find("material \"hot\""), std::string::npos) << w;
    if (w.find("diffuse.weight") != std::string::npos) {
      saw_weight = true;
      EXPECT_EQ(w.rfind(prefix + ":3:27: warning: materials.hot.diffuse.weight: ", 0), 0u) << w;
      EXPECT_NE(w.find("1.5"), std::string::npos) << w;
      EXPECT_NE(w.find("clamped to 1"), std::string::npos) << w;
    }
  }
  EXPECT_TRUE(saw_weight);
}

// Degenerate area lights (what exporters write for a lamp scaled to nothing) are dropped with
// a warning at their key, not refused; the proper light after them is kept.
TEST(SceneWarnings, DegenerateAreaLightsAreDroppedWithAWarning) {
  const aw::Scene s = aw::load_scene(data_path("good_degenerate_lights.json"));
  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_EQ(s.lights[0].type, aw::LightDesc::Type::Quad);
  EXPECT_FLOAT_EQ(s.lights[0].edge_v.z, 1.0f);
  ASSERT_EQ(s.warnings.size(), 3u);
  const std::string prefix = data_path("good_degenerate_lights.json");
  EXPECT_EQ(s.warnings[0].rfind(prefix + ":4:65: warning: lights[0].edge_v: quad light with zero area", 0), 0u)
      << s.warnings[0];
  EXPECT_EQ(s.warnings[1].rfind(prefix + ":5:46: warning: lights[1].radius: sphere light of radius 0", 0), 0u)
      << s.warnings[1];
  EXPECT_EQ(s.warnings[2].rfind(prefix + ":6:44: warning: lights[2].radius: disk light of radius 0", 0), 0u)
      << s.warnings[2];
  for (const std::string& w : s.warnings) EXPECT_NE(w.find("is dropped"), std::string::npos) << w;
}

TEST(SceneWarnings, NotYetImplementedRefractionFeaturesWarn) {
  const aw::Scene s = aw::load_scene(data_path("good_not_implemented.json"));
  ASSERT_EQ(s.warnings.size(), 2u);
  EXPECT_NE(s.warnings[0].find("refraction.caustics is not implemented yet"), std::string::npos)
      << s.warnings[0];
  EXPECT_NE(s.warnings[1].find("refraction.allow_global_volume is not implemented yet"),
            std::string::npos)
      << s.warnings[1];
  // The values are still parsed and kept.
  EXPECT_TRUE(s.materials[0].refraction.caustics);
  EXPECT_FALSE(s.materials[0].refraction.allow_global_volume);
}

}  // namespace
