// -D overrides: applied to the JSON before validation, reported as "command line -D ...".
#include <gtest/gtest.h>

#include "host/render/scene_pack.h"
#include "tests/scene/scene_test_util.h"

using aw_test::data_path;
using aw_test::load_error;

namespace {

const std::string kSmall = data_path("good_small.json");

TEST(Overrides, ReplaceAScalar) {
  EXPECT_EQ(aw::load_scene(kSmall).render.spp, 4);
  EXPECT_EQ(aw::load_scene(kSmall, {"render.spp=16"}).render.spp, 16);
}

TEST(Overrides, NestedColour) {
  const aw::Scene s = aw::load_scene(kSmall, {"materials.floor.diffuse.color=[1,0,0]"});
  EXPECT_EQ(s.materials[0].diffuse.color, glm::vec3(1, 0, 0));
}

TEST(Overrides, CreateNewKeysAndSections) {
  // Neither "camera" nor "reflection" exists in the file; both are created and validated.
  const aw::Scene s =
      aw::load_scene(kSmall, {"camera.fov=30", "materials.floor.reflection.glossiness=0.25",
                              "environment.type=constant", "render.gi=false"});
  EXPECT_FLOAT_EQ(s.camera.fov, 30.0f);
  EXPECT_FLOAT_EQ(s.materials[0].reflection.glossiness, 0.25f);
  EXPECT_FALSE(s.render.gi);
}

// render.rr_depth (an archwave extension, the benchmark's "Russian roulette off" knob) is
// validated like any key and reaches the kernels' parameters.
TEST(Overrides, RussianRouletteDepthReachesTheKernels) {
  const aw::Scene s = aw::load_scene(kSmall, {"render.rr_depth=1000"});
  EXPECT_EQ(s.render.rr_depth, 1000);
  std::vector<std::string> warnings;
  EXPECT_EQ(aw::pack_scene(s, &warnings).params.rr_depth, 1000u);
  EXPECT_NE(load_error(kSmall, {"render.rr_depth=-1"}).find("render.rr_depth"), std::string::npos);
}

TEST(Overrides, CreatedKeysAreValidatedLikeFileKeys) {
  EXPECT_EQ(load_error(kSmall, {"materials.floor.reflection.glosiness=0.25"}),
            "command line -D materials.floor.reflection.glosiness=0.25: "
            "materials.floor.reflection.glosiness: unknown key \"glosiness\" (did you mean "
            "\"glossiness\"?)");
  EXPECT_EQ(load_error(kSmall, {"camera.fov=200"}),
            "command line -D camera.fov=200: camera.fov: must be in (0, 180), got 200");
}

TEST(Overrides, BadTypeReportsTheCommandLine) {
  // "abc" is not JSON, so it becomes the string "abc"; spp then rejects it.
  EXPECT_EQ(load_error(kSmall, {"render.spp=abc"}),
            "command line -D render.spp=abc: render.spp: expected an integer, got \"abc\"");
  EXPECT_EQ(load_error(kSmall, {"render.spp=-1"}),
            "command line -D render.spp=-1: render.spp: must be >= 1, got -1");
}

TEST(Overrides, ArrayIndices) {
  const aw::Scene s = aw::load_scene(kSmall, {"objects[0].radius=2"});
  ASSERT_EQ(s.spheres.size(), 1u);  // an analytic sphere
  EXPECT_FLOAT_EQ(s.spheres[0].radius, 2.0f);
  // Index == size appends a new element.
  const aw::Scene t = aw::load_scene(kSmall, {R"(objects[1]={"shape":"box","material":"floor"})"});
  ASSERT_EQ(t.meshes.size(), 1u);
  EXPECT_EQ(t.meshes[0].name, "objects[1] (box)");
  const std::string gap = load_error(kSmall, {"objects[5].radius=1"});
  EXPECT_NE(gap.find("index out of range"), std::string::npos) << gap;
}

TEST(Overrides, ErrorsInsideAnOverriddenSubtreeNameTheOverride) {
  EXPECT_EQ(load_error(kSmall, {R"(camera={"fov": 30, "position": [0, 1]})"}),
            "command line -D camera={\"fov\": 30, \"position\": [0, 1]}: camera.position: "
            "expected an array of 3 numbers, got [0,1]");
}

TEST(Overrides, ErrorsElsewhereStillNameTheFile) {
  const std::string path = data_path("bad_negative_spp.json");
  EXPECT_EQ(load_error(path, {"render.width=32"}).rfind(path + ":2:28: render.spp:", 0), 0u);
  // ...and overriding the bad value fixes the scene.
  EXPECT_EQ(aw::load_scene(path, {"render.spp=2"}).render.spp, 2);
}

TEST(Overrides, MalformedEntries) {
  EXPECT_EQ(load_error(kSmall, {"render.spp"}),
            "command line -D render.spp: expected KEY=VALUE (e.g. render.spp=16)");
  EXPECT_NE(load_error(kSmall, {"=3"}).find("malformed key"), std::string::npos);
  EXPECT_NE(load_error(kSmall, {"render..spp=3"}).find("malformed key"), std::string::npos);
  EXPECT_NE(load_error(kSmall, {"objects[x].radius=3"}).find("malformed key"), std::string::npos);
  const std::string not_object = load_error(kSmall, {"render.spp.x=1"});
  EXPECT_EQ(not_object.rfind("command line -D render.spp.x=1: render.spp is not an object", 0), 0u)
      << not_object;
}

TEST(Overrides, MeshFileErrorsNameTheOverrideAndTheResolvedPath) {
  const std::string message = load_error(data_path("good_obj.json"),
                                         {"objects[1].file=meshes"});  // a directory, not a file
  EXPECT_EQ(message.rfind("command line -D objects[1].file=meshes: objects[1].file: ", 0), 0u)
      << message;
  EXPECT_NE(message.find(data_path("meshes")), std::string::npos) << message;
}

TEST(Overrides, ClampWarningsFromOverridesNameTheCommandLine) {
  const aw::Scene s = aw::load_scene(kSmall, {"materials.floor.diffuse.weight=2"});
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_EQ(s.warnings[0].rfind("command line -D materials.floor.diffuse.weight=2: warning: ", 0),
            0u)
      << s.warnings[0];
  EXPECT_FLOAT_EQ(s.materials[0].diffuse.weight, 1.0f);
}

TEST(Overrides, LaterOverrideOfAParentWins) {
  // The second entry replaces the whole render object, including the first entry's spp.
  const std::string message = load_error(kSmall, {"render.spp=8", R"(render={"spp": 0})"});
  EXPECT_EQ(message.rfind("command line -D render={\"spp\": 0}: render.spp: must be >= 1", 0), 0u)
      << message;
}

}  // namespace
