// Bad scenes: each fixture must fail with the expected position and message. Positions were
// worked out by hand from the fixture text (1-based line:column of the key, or of the
// enclosing object for a missing key, or of the offending token for syntax errors).
#include <gtest/gtest.h>

#include "tests/scene/scene_test_util.h"

using aw_test::data_path;
using aw_test::load_error;

namespace {

struct BadCase {
  const char* file;
  const char* line_col;  // "LINE:COL"
  const char* fragment;  // must appear after the position
};

void PrintTo(const BadCase& c, std::ostream* os) { *os << c.file; }

class BadScene : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadScene, FailsWithPositionAndMessage) {
  const BadCase& c = GetParam();
  const std::string path = data_path(c.file);
  const std::string message = load_error(path);
  const std::string prefix = path + ":" + c.line_col + ": ";
  EXPECT_EQ(message.rfind(prefix, 0), 0u) << "expected prefix " << prefix << "\n got: " << message;
  EXPECT_NE(message.find(c.fragment), std::string::npos)
      << "expected fragment: " << c.fragment << "\n got: " << message;
}

const BadCase kBadCases[] = {
    // Syntax: the trailing comma is accepted, the '}' after it is not.
    {"bad_json.json", "5:3", "syntax error while parsing object key - unexpected '}'"},
    {"bad_type.json", "4:23", "materials.glass.refraction.ior: expected a number, got \"glass\""},
    {"bad_unknown_top_key.json", "3:3", "lighting: unknown key \"lighting\""},
    {"bad_unknown_material_key.json", "5:34",
     "materials.glass.refraction.fog.distanse: unknown key \"distanse\" (did you mean "
     "\"distance\"?)"},
    {"bad_missing_mesh.json", "5:7", "objects[0].file: cannot load mesh"},
    {"bad_unknown_material_name.json", "5:7",
     "objects[0].material: objects[0] (sphere) uses unknown material \"flor\""},
    {"bad_no_materials.json", "2:34",
     "unknown material \"floor\" (the scene defines no materials)"},
    {"bad_zero_width.json", "3:5", "render.width: must be between 1 and 65536, got 0"},
    {"bad_negative_spp.json", "2:28", "render.spp: must be >= 1, got -4"},
    {"bad_enum_brdf.json", "3:32",
     "materials.shiny.reflection.brdf: unknown value \"phong\"; expected one of: beckmann, ggx, "
     "ashikhmin_shirley, ashikhmin_shirley_legacy"},
    {"bad_texture_ref.json", "4:53",
     "materials.bronze.anisotropy.rotation.texture: no texture named \"pounded\" in the textures section"},
    {"bad_textures_section.json", "3:36",
     "textures.checks.scale: texture \"checks\": scale must be finite and non-zero, got [8,0]"},
    {"bad_sun.json", "4:47", "lights[1].angle: must be in [0, 180], got 200"},
    {"bad_matrix_length.json", "6:9",
     "objects[0].transform.matrix: expected 16 numbers (a row-major 4x4 matrix), got 12"},
    // A missing key has no position of its own: the enclosing object's opening brace.
    {"bad_missing_shape.json", "5:5", "objects[1]: missing required key \"shape\""},
    {"bad_env_map.json", "1:33", "environment.file: cannot read the environment map: cannot read EXR \""},
    {"bad_fov.json", "3:5", "camera.fov: must be in (0, 180), got 180"},
    {"bad_singular_transform.json", "5:7", "objects[0].transform: the transform is singular"},
    {"bad_seed.json", "2:15", "render.seed: must be a non-negative integer below 2^32"},
    {"bad_sphere_radius.json", "5:7", "objects[0].radius: must be > 0, got 0"},
    {"bad_light_key.json", "3:24", "lights[0].radius: unknown key \"radius\""},
    {"bad_empty_mesh.json", "4:41", "has no triangles"},
    {"bad_duplicate_key.json", "4:5", "render.spp: duplicate key \"spp\""},
    // Columns count characters, not bytes: "é" is two bytes in UTF-8.
    {"bad_utf8_column.json", "2:25", "unknown key \"diffus\" (did you mean \"diffuse\"?)"},
    // The key's start is found even when it contains escaped quotes and backslashes.
    {"bad_escaped_key.json", "2:28", "unknown key \"we\"ird\\\""},
    // OBJ values that are not finite decimal numbers: refused with the OBJ line (tinyobjloader
    // alone would read "nan" or "0,5" as 0, and overflow to infinity).
    {"bad_inf_mesh.json", "4:24", "inf_coord.obj\": line 2: 'v' value \"1e999\" is out of the range of float"},
    {"bad_nan_mesh.json", "4:24", "nan_coord.obj\": line 4: 'v' value \"nan\" is not a finite decimal number"},
    {"bad_word_uv_mesh.json", "4:24", "word_uv.obj\": line 7: 'vt' value \"1,5\" is not a finite decimal number"},
    {"bad_material_colour_type.json", "3:38",
     "materials.m.diffuse.color[1]: expected a number, got \"red\""},
    // Meshes carry two UV sets: another one would silently orient anisotropy by set 0.
    {"bad_uv_set.json", "4:38",
     "materials.brushed.anisotropy.uv_set: material \"brushed\": anisotropy.uv_set = 2: no such UV set"},
};

INSTANTIATE_TEST_SUITE_P(Fixtures, BadScene, ::testing::ValuesIn(kBadCases));

TEST(SceneErrors, SpecExampleMessageIsExact) {
  const std::string path = data_path("bad_type.json");
  EXPECT_EQ(load_error(path),
            path + ":4:23: materials.glass.refraction.ior: expected a number, got \"glass\"");
}

TEST(SceneErrors, MissingMeshNamesTheResolvedPath) {
  const std::string message = load_error(data_path("bad_missing_mesh.json"));
  // Resolved against the scene file's directory, not the working directory.
  EXPECT_NE(message.find("\"" + data_path("meshes/missing.obj") + "\""), std::string::npos)
      << message;
}

TEST(SceneErrors, MissingSceneFileNamesIt) {
  const std::string path = data_path("does_not_exist.json");
  const std::string message = load_error(path);
  EXPECT_EQ(message.rfind(path + ": cannot open scene file", 0), 0u) << message;
}

TEST(SceneErrors, OnlySceneErrorEscapes) {
  // A directory where the scene should be; must still be a SceneError, not a crash or a
  // std::filesystem / iostream exception.
  EXPECT_THROW(aw::load_scene(data_path("meshes")), aw::SceneError);
  EXPECT_THROW(aw::load_scene(data_path("meshes/quad_full.obj")), aw::SceneError);
}

}  // namespace
