// OBJ with Wavefront MTL materials (host/scene/obj_materials.h): faces grouped by usemtl, the
// MTL -> Architectural material mapping of docs/obj-mtl.md rule by rule, texture options,
// missing and malformed files, and that load_obj still reads and refuses files as before.
// Every file is written by the test itself, so each case shows exactly what it feeds the
// importer.
#include <gtest/gtest.h>

#include "tests/scene/scene_test_util.h"
#include <png.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "host/scene/loader_parts.h"
#include "host/scene/obj_materials.h"

namespace {

using aw::Brdf;
using aw::MaterialDesc;
using aw::TextureDesc;
using aw::TextureRef;
using aw::scene_detail::DMesh;
using aw::scene_detail::load_obj;
using aw::scene_detail::load_obj_with_materials;
using aw::scene_detail::ObjImport;

std::string temp_dir() { return aw_test::scratch_dir("objmtl"); }

std::string write_file(const std::string& name, const std::string& bytes) {
  return aw_test::write_scratch_file(temp_dir(), name, bytes);
}

// A 2 x 2 8-bit PNG written with libpng; `channels` 3 (RGB) or 4 (RGBA), rows top first.
void write_png(const std::string& name, int channels, const std::vector<uint8_t>& pixels) {
  const std::string path = temp_dir() + name;
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  FILE* f = std::fopen(path.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    std::fclose(f);
    FAIL() << "libpng failed";
  }
  png_init_io(png, f);
  png_set_IHDR(png, info, 2, 2, 8, channels == 4 ? PNG_COLOR_TYPE_RGBA : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  png_write_row(png, const_cast<png_bytep>(pixels.data()));
  png_write_row(png, const_cast<png_bytep>(pixels.data() + 2 * channels));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(f);
}

void write_rgb_png(const std::string& name) {
  write_png(name, 3, {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255});
}
void write_rgba_png(const std::string& name) {
  write_png(name, 4, {255, 0, 0, 255, 0, 255, 0, 0, 0, 0, 255, 128, 255, 255, 255, 255});
}

// One quad (two triangles) with normals and UVs, using material `mtl` from `lib`.
std::string quad_obj(const std::string& lib, const std::string& mtl) {
  return "mtllib " + lib + "\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
         "usemtl " + mtl + "\nf 1/1/1 2/2/1 3/3/1 4/4/1\n";
}

struct Loaded {
  bool ok = false;
  ObjImport import;
  std::string error;
  std::vector<std::string> warnings;
};

// Writes `name`.obj and `name`.mtl (the OBJ a quad with material "m") and loads the OBJ.
Loaded load_material(const std::string& name, const std::string& mtl) {
  write_file(name + ".mtl", mtl);
  Loaded r;
  r.ok = load_obj_with_materials(write_file(name + ".obj", quad_obj(name + ".mtl", "m")), &r.import, &r.error,
                                 &r.warnings);
  return r;
}

Loaded load(const std::string& obj_path) {
  Loaded r;
  r.ok = load_obj_with_materials(obj_path, &r.import, &r.error, &r.warnings);
  return r;
}

bool has_warning(const std::vector<std::string>& warnings, const std::string& part) {
  for (const std::string& w : warnings) {
    if (w.find(part) != std::string::npos) return true;
  }
  return false;
}

std::string all(const std::vector<std::string>& warnings) {
  std::string s;
  for (const std::string& w : warnings) s += w + "\n";
  return s;
}

const TextureRef* binding(const Loaded& r, size_t material, const std::string& key) {
  const auto& b = r.import.bindings.at(material);
  auto it = b.find(key);
  return it == b.end() ? nullptr : &it->second;
}

// ---- geometry -----------------------------------------------------------------------------------

TEST(ObjMtl, PrimitivesFollowUsemtlInOrderOfFirstUse) {
  write_file("split.mtl", "newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\n");
  const std::string obj = write_file("split.obj",
                                     "mtllib split.mtl\n"
                                     "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 2 2\n"
                                     "f 1 2 3\n"          // before any usemtl: material -1
                                     "usemtl blue\nf 1 3 4\n"
                                     "usemtl red\nf 2 3 5\n"
                                     "usemtl blue\nf 3 4 5\n");
  const Loaded r = load(obj);
  ASSERT_TRUE(r.ok) << r.error;
  ASSERT_EQ(r.import.material_names, (std::vector<std::string>{"red", "blue"}));
  ASSERT_EQ(r.import.materials.size(), 2u);
  ASSERT_EQ(r.import.bindings.size(), 2u);
  EXPECT_EQ(r.import.materials[0].diffuse.color, glm::vec3(1, 0, 0));
  EXPECT_EQ(r.import.materials[1].diffuse.color, glm::vec3(0, 0, 1));

  ASSERT_EQ(r.import.primitives.size(), 3u);
  const auto& none = r.import.primitives[0];
  const auto& blue = r.import.primitives[1];
  const auto& red = r.import.primitives[2];
  EXPECT_EQ(none.material, -1);
  EXPECT_EQ(blue.material, 1);
  EXPECT_EQ(red.material, 0);
  EXPECT_EQ(none.name, "faces without a material");
  EXPECT_EQ(blue.name, "material 'blue'");
  EXPECT_EQ(none.mesh.indices.size(), 1u);
  EXPECT_EQ(blue.mesh.indices.size(), 2u);
  EXPECT_EQ(red.mesh.indices.size(), 1u);
  // De-indexed per primitive, vertices in order of first use within it.
  const std::vector<glm::dvec3> blue_positions = {{0, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 2, 2}};
  EXPECT_EQ(blue.mesh.positions, blue_positions);
  EXPECT_EQ(blue.mesh.indices, (std::vector<glm::uvec3>{{0, 1, 2}, {1, 2, 3}}));
  const std::vector<glm::dvec3> red_positions = {{1, 0, 0}, {1, 1, 0}, {2, 2, 2}};
  EXPECT_EQ(red.mesh.positions, red_positions);
  EXPECT_TRUE(none.mesh.normals.empty());
  EXPECT_TRUE(none.mesh.uvs.empty());
}

TEST(ObjMtl, WithoutUsemtlOnePrimitiveEqualToLoadObj) {
  const std::string obj = write_file("plain.obj",
                                     "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                     "vn 0 0 1\nf 1/1/1 2/2/1 3/3/1 4/4/1\nf 4/4/1 3/3/1 2/2/1\n");
  const Loaded r = load(obj);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_TRUE(r.import.materials.empty());
  ASSERT_EQ(r.import.primitives.size(), 1u);
  EXPECT_EQ(r.import.primitives[0].material, -1);

  DMesh mesh;
  std::string error;
  std::vector<std::string> warnings;
  ASSERT_TRUE(load_obj(obj, &mesh, &error, &warnings)) << error;
  const DMesh& p = r.import.primitives[0].mesh;
  EXPECT_EQ(p.positions, mesh.positions);
  EXPECT_EQ(p.normals, mesh.normals);
  EXPECT_EQ(p.uvs, mesh.uvs);
  EXPECT_EQ(p.indices, mesh.indices);
  EXPECT_EQ(p.indices.size(), 3u);
}

TEST(ObjMtl, UnknownUsemtlTakesMaterialMinusOne) {
  write_file("unknown.mtl", "newmtl a\nKd 1 1 1\n");
  const Loaded r = load(write_file("unknown.obj", quad_obj("unknown.mtl", "nosuch")));
  ASSERT_TRUE(r.ok) << r.error;
  ASSERT_EQ(r.import.primitives.size(), 1u);
  EXPECT_EQ(r.import.primitives[0].material, -1);
  EXPECT_TRUE(has_warning(r.warnings, "nosuch")) << all(r.warnings);
}

TEST(ObjMtl, EachPrimitiveKeepsTheAttributesAllItsCornersHave) {
  // The textured part has UVs, the other none: load_obj drops the UVs of the whole file, a
  // primitive keeps its own.
  write_file("attrs.mtl", "newmtl tex\nnewmtl plain\n");
  const std::string obj = write_file("attrs.obj",
                                     "mtllib attrs.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
                                     "usemtl tex\nf 1/1 2/2 3/3\nusemtl plain\nf 1 3 2\n");
  const Loaded r = load(obj);
  ASSERT_TRUE(r.ok) << r.error;
  ASSERT_EQ(r.import.primitives.size(), 2u);
  EXPECT_EQ(r.import.primitives[0].mesh.uvs, (std::vector<glm::dvec2>{{0, 0}, {1, 0}, {1, 1}}));
  EXPECT_TRUE(r.import.primitives[1].mesh.uvs.empty());
  DMesh mesh;
  std::string error;
  std::vector<std::string> warnings;
  ASSERT_TRUE(load_obj(obj, &mesh, &error, &warnings));
  EXPECT_TRUE(mesh.uvs.empty());
}

TEST(ObjMtl, EveryLibraryOfAnMtllibLineIsRead) {
  // tinyobjloader alone stops at the first file it can read.
  write_file("lib_a.mtl", "newmtl a\nKd 1 0 0\n");
  write_file("lib_b.mtl", "newmtl b\nKd 0 1 0\n");
  const Loaded r = load(write_file("two_libs.obj",
                                   "mtllib lib_a.mtl lib_b.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\n"
                                   "usemtl b\nf 1 2 3\nusemtl a\nf 1 3 2\n"));
  ASSERT_TRUE(r.ok) << r.error;
  ASSERT_EQ(r.import.material_names, (std::vector<std::string>{"a", "b"}));
  ASSERT_EQ(r.import.primitives.size(), 2u);
  EXPECT_EQ(r.import.primitives[0].material, 1);
  EXPECT_EQ(r.import.primitives[1].material, 0);
}

TEST(ObjMtl, DuplicateMaterialKeepsTheFirstDefinition) {
  const Loaded r = load_material("dup", "newmtl m\nKd 1 0 0\nnewmtl m\nKd 0 1 0\n");
  ASSERT_TRUE(r.ok) << r.error;
  ASSERT_EQ(r.import.materials.size(), 1u);
  EXPECT_EQ(r.import.materials[0].diffuse.color, glm::vec3(1, 0, 0));
  EXPECT_TRUE(has_warning(r.warnings, "defined again")) << all(r.warnings);
}

// ---- missing and malformed files --------------------------------------------------------------

TEST(ObjMtl, MissingMtlIsAWarningAndFacesHaveNoMaterial) {
  const Loaded r = load(write_file("nomtl.obj", quad_obj("does_not_exist.mtl", "m")));
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_TRUE(r.import.materials.empty());
  ASSERT_EQ(r.import.primitives.size(), 1u);
  EXPECT_EQ(r.import.primitives[0].material, -1);
  EXPECT_EQ(r.import.primitives[0].mesh.indices.size(), 2u);
  EXPECT_TRUE(has_warning(r.warnings, "material library \"does_not_exist.mtl\" does not exist")) << all(r.warnings);
}

TEST(ObjMtl, MalformedMtlIsAnErrorNamingTheFileTheLineAndTheProblem) {
  struct Case {
    std::string mtl, expected;
  };
  const Case cases[] = {
      {"newmtl m\nKd 1 abc 0\n", "line 2: 'Kd' value \"abc\" is not a finite decimal number"},
      {"newmtl m\nKd 1 1\n", "line 2: 'Kd' takes 1 or 3 numbers (r [g b]), got 2 values"},
      {"newmtl m\nNs nan\n", "line 2: 'Ns' value \"nan\" is not a finite decimal number"},
      {"newmtl m\nNi 1 2\n", "line 2: 'Ni' takes one number, got 2 values"},
      {"newmtl m\nd 1e999\n", "line 2: 'd' value \"1e999\" is out of the range of float"},
      {"newmtl m\nillum 12\n", "line 2: 'illum' takes an illumination model, an integer from 0 to 10; got \"12\""},
      {"Kd 1 1 1\nnewmtl m\n", "line 1: 'Kd' comes before any newmtl"},
      {"newmtl\n", "line 1: 'newmtl' names no material"},
      {"newmtl m\nmap_Kd -s 2\n", "line 2: 'map_Kd' names no file"},
      {"newmtl m\nmap_Kd -s x.png\n", "line 2: 'map_Kd' option -s needs 1 to 3 numbers, got \"x.png\""},
      {"newmtl m\nmap_Kd -clamp yes x.png\n", "line 2: 'map_Kd' option -clamp takes on or off, got \"yes\""},
      {"newmtl m\nbump -frobnicate 1 x.png\n", "line 2: 'bump' has an unknown option \"-frobnicate\""},
      {"newmtl m\nmap_Kd -s 0 1 x.png\n", "line 2: 'map_Kd' option -s must not scale by 0"},
      {"newmtl m\nbump -imfchan q x.png\n", "line 2: 'bump' option -imfchan takes one of r, g, b, m, l, z, got \"q\""},
  };
  int i = 0;
  for (const Case& c : cases) {
    const std::string name = "bad" + std::to_string(i++);
    const Loaded r = load_material(name, c.mtl);
    EXPECT_FALSE(r.ok) << c.mtl;
    EXPECT_EQ(r.error, "material library \"" + name + ".mtl\", " + c.expected) << c.mtl;
    EXPECT_TRUE(r.import.primitives.empty());
  }
}

TEST(ObjMtl, MissingMapFileIsAnErrorNamingIt) {
  const Loaded r = load_material("nomap", "newmtl m\nmap_Kd textures/missing.png\n");
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("material 'm' (nomap.mtl): line 2: map_Kd \"textures/missing.png\": cannot open the file"),
            std::string::npos)
      << r.error;
}

TEST(ObjMtl, ObjErrorsComeFirstAndReadAsLoadObjs) {
  // A malformed MTL does not hide the OBJ's own error, and the OBJ's messages are load_obj's.
  write_file("errs.mtl", "newmtl m\nKd x\n");
  const std::vector<std::string> objs = {
      "mtllib errs.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nusemtl m\nf 1 2 7\n",    // index out of range
      "mtllib errs.mtl\nv 0 0 0\nv 1 nan 0\nv 1 1 0\nusemtl m\nf 1 2 3\n",  // not a number
      "mtllib errs.mtl\nv 0 0 0\nv 1 1e999 0\nv 1 1 0\nf 1 2 3\n",          // out of float
      "mtllib errs.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvn 0 0 1\nf 1//1 2//1 3//4\n",
  };
  int i = 0;
  for (const std::string& text : objs) {
    const std::string path = write_file("errs" + std::to_string(i++) + ".obj", text);
    DMesh mesh;
    std::string expected;
    std::vector<std::string> warnings;
    ASSERT_FALSE(load_obj(path, &mesh, &expected, &warnings)) << text;
    const Loaded r = load(path);
    EXPECT_FALSE(r.ok);
    EXPECT_EQ(r.error, expected) << text;
  }
  const Loaded missing = load(temp_dir() + "no_such.obj");
  EXPECT_FALSE(missing.ok);
  EXPECT_EQ(missing.error, "no such file");
  // A good OBJ with that MTL: the MTL's error.
  const Loaded r = load(write_file("errs_good.obj", quad_obj("errs.mtl", "m")));
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.error, "material library \"errs.mtl\", line 2: 'Kd' value \"x\" is not a finite decimal number");
}

// ---- the mapping, rule by rule (docs/obj-mtl.md) ------------------------------------------------

TEST(ObjMtlMapping, KdIsTheDiffuseColourAndOneValueIsGrey) {
  const Loaded r = load_material("kd", "newmtl m\nKd 0.25\n");
  ASSERT_TRUE(r.ok) << r.error;
  const MaterialDesc& m = r.import.materials[0];
  EXPECT_EQ(m.diffuse.color, glm::vec3(0.25f));
  EXPECT_EQ(m.diffuse.weight, 1.0f);
  EXPECT_EQ(m.diffuse.roughness, 0.0f);
  EXPECT_TRUE(r.import.bindings[0].empty());
  // No Ks: no reflection.
  EXPECT_EQ(m.reflection.weight, 0.0f);
  EXPECT_EQ(m.cutout_opacity, 1.0f);
  EXPECT_EQ(m.refraction.weight, 0.0f);
}

TEST(ObjMtlMapping, AByteOrderMarkIsNotAStatement) {
  const Loaded r = load_material("bom", "\xEF\xBB\xBFnewmtl m\nKd 0.5 0.25 0\n");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.import.material_names, std::vector<std::string>{"m"});
  EXPECT_EQ(r.import.materials[0].diffuse.color, glm::vec3(0.5f, 0.25f, 0.0f));
  EXPECT_TRUE(r.warnings.empty()) << all(r.warnings);
}

TEST(ObjMtlMapping, KdOutOfRangeIsClampedWithAWarning) {
  const Loaded r = load_material("kd_clamp", "newmtl m\nKd 1.5 0.5 -0.5\n");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.import.materials[0].diffuse.color, glm::vec3(1.0f, 0.5f, 0.0f));
  EXPECT_TRUE(has_warning(r.warnings, "material 'm' (kd_clamp.mtl): Kd [1.5, 0.5, -0.5] is outside [0, 1], clamped"))
      << all(r.warnings);
}

TEST(ObjMtlMapping, MapKdIsAnSrgbTextureTimesGreyKd) {
  write_rgb_png("tex/diffuse.png");
  const Loaded r = load_material("mapkd", "newmtl m\nKd 0.5 0.5 0.5\nmap_Kd tex/diffuse.png\n");
  ASSERT_TRUE(r.ok) << r.error;
  const TextureRef* ref = binding(r, 0, "diffuse.color");
  ASSERT_NE(ref, nullptr);
  EXPECT_EQ(ref->channel, -1);
  EXPECT_FLOAT_EQ(ref->multiplier, 0.5f);
  EXPECT_FLOAT_EQ(ref->offset, 0.0f);
  ASSERT_EQ(r.import.textures.size(), 1u);
  const TextureDesc& t = r.import.textures[ref->texture];
  EXPECT_EQ(t.name, "tex/diffuse.png");
  EXPECT_EQ(t.source, temp_dir() + "tex/diffuse.png");
  EXPECT_EQ(t.colorspace, TextureDesc::ColorSpace::Srgb);
  EXPECT_EQ(t.wrap, TextureDesc::Wrap::Repeat);
  EXPECT_EQ(t.width, 2);
  EXPECT_EQ(t.channels, 3);
  // Top left texel: sRGB red decoded to linear 1.
  EXPECT_FLOAT_EQ(t.texels[0], 1.0f);
  EXPECT_TRUE(r.warnings.empty()) << all(r.warnings);
}

TEST(ObjMtlMapping, ColouredKdMultipliesTheMapByItsLuminance) {
  write_rgb_png("diffuse_c.png");
  const Loaded r = load_material("mapkd_c", "newmtl m\nKd 1 0.5 0\nmap_Kd diffuse_c.png\n");
  ASSERT_TRUE(r.ok) << r.error;
  const TextureRef* ref = binding(r, 0, "diffuse.color");
  ASSERT_NE(ref, nullptr);
  EXPECT_FLOAT_EQ(ref->multiplier, float(0.2126 + 0.7152 * 0.5));
  EXPECT_TRUE(has_warning(r.warnings, "luminance")) << all(r.warnings);
}

TEST(ObjMtlMapping, MapKdWithoutKdOrWithBlackKdIsTheMapAlone) {
  write_rgb_png("diffuse_a.png");
  const Loaded absent = load_material("mapkd_absent", "newmtl m\nmap_Kd diffuse_a.png\n");
  ASSERT_TRUE(absent.ok) << absent.error;
  EXPECT_FLOAT_EQ(binding(absent, 0, "diffuse.color")->multiplier, 1.0f);
  EXPECT_TRUE(absent.warnings.empty()) << all(absent.warnings);
  const Loaded black = load_material("mapkd_black", "newmtl m\nKd 0 0 0\nmap_Kd diffuse_a.png\n");
  ASSERT_TRUE(black.ok) << black.error;
  EXPECT_FLOAT_EQ(binding(black, 0, "diffuse.color")->multiplier, 1.0f);
  EXPECT_TRUE(has_warning(black.warnings, "Kd is black; map_Kd is used as it is")) << all(black.warnings);
}

TEST(ObjMtlMapping, KsAndNsAreAPhongHighlightOnAshikhminShirley) {
  const Loaded r = load_material("ks", "newmtl m\nKs 0.8 0.4 0.2\nNs 100\nillum 2\n");
  ASSERT_TRUE(r.ok) << r.error;
  const MaterialDesc& m = r.import.materials[0];
  EXPECT_FLOAT_EQ(m.reflection.weight, 0.8f);
  EXPECT_FLOAT_EQ(m.reflection.color.x, 1.0f);
  EXPECT_FLOAT_EQ(m.reflection.color.y, 0.5f);
  EXPECT_FLOAT_EQ(m.reflection.color.z, 0.25f);
  EXPECT_EQ(m.reflection.brdf, Brdf::AshikhminShirley);
  // g = 1 - (2 / (n + 2))^(1/4); the Ashikhmin-Shirley exponent 2 / alpha^2 - 2 with
  // alpha = (1 - g)^2 gives n back.
  const double g = 1.0 - std::pow(2.0 / 102.0, 0.25);
  EXPECT_FLOAT_EQ(m.reflection.glossiness, float(g));
  const double alpha = (1.0 - double(m.reflection.glossiness)) * (1.0 - double(m.reflection.glossiness));
  EXPECT_NEAR(2.0 / (alpha * alpha) - 2.0, 100.0, 1e-3);
  // The dielectric Fresnel of the IOR (no Ni: 1.5), locked to refraction.ior.
  EXPECT_TRUE(m.reflection.fresnel.use_ior);
  EXPECT_TRUE(m.reflection.fresnel.lock_to_refraction_ior);
  EXPECT_FLOAT_EQ(m.refraction.ior, 1.5f);
  EXPECT_FALSE(m.metal);
}

TEST(ObjMtlMapping, NsZeroIsTheBroadestLobe) {
  const Loaded r = load_material("ns0", "newmtl m\nKs 1 1 1\nNs 0\n");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_FLOAT_EQ(r.import.materials[0].reflection.glossiness, 0.0f);
  EXPECT_FLOAT_EQ(r.import.materials[0].reflection.weight, 1.0f);
  EXPECT_EQ(r.import.materials[0].reflection.color, glm::vec3(1.0f));
}

TEST(ObjMtlMapping, Illum1HasNoHighlight) {
  const Loaded r = load_material("illum1", "newmtl m\nKd 1 1 1\nKs 1 1 1\nillum 1\n");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.import.materials[0].reflection.weight, 0.0f);
  EXPECT_TRUE(has_warning(r.warnings, "illum 1 has no specular term")) << all(r.warnings);
}

TEST(ObjMtlMapping, MapKsIsTheReflectionColour) {
  write_rgb_png("spec.png");
  const Loaded r = load_material("mapks", "newmtl m\nKs 0.5 0.5 0.5\nmap_Ks spec.png\n");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_FLOAT_EQ(r.import.materials[0].reflection.weight, 0.5f);
  const TextureRef* ref = binding(r, 0, "reflection.color");
  ASSERT_NE(ref, nullptr);
  EXPECT_FLOAT_EQ(ref->multiplier, 1.0f);
  EXPECT_EQ(r.import.textures[ref->texture].colorspace, TextureDesc::ColorSpace::Srgb);
}

TEST(ObjMtlMapping, Illum3IsAMirrorWithTheDefaultFresnel) {
  const Loaded r = load_material("illum3", "newmtl m\nKs 0.9 0.9 0.9\nNs 10\nNi 1.8\nillum 3\n");
  ASSERT_TRUE(r.ok) << r.error;
  const MaterialDesc& m = r.import.materials[0];
  EXPECT_FLOAT_EQ(m.reflection.glossiness, 1.0f);
  EXPECT_FLOAT_EQ(m.reflection.weight, 0.9f);
  EXPECT_TRUE(m.reflection.fresnel.use_ior);
  EXPECT_TRUE(m.reflection.fresnel.lock_to_refraction_ior);
  EXPECT_FLOAT_EQ(m.refraction.ior, 1.8f);
  EXPECT_EQ(m.refraction.weight, 0.0f);
}

TEST(ObjMtlMapping, NiOfOneGivesTheReflectionItsOwnIor) {
  const Loaded r = load_material("ni1", "newmtl m\nKs 0.5 0.5 0.5\nNi 1.0\n");
  ASSERT_TRUE(r.ok) << r.error;
  const MaterialDesc& m = r.import.materials[0];
  EXPECT_FLOAT_EQ(m.refraction.ior, 1.0f);
  EXPECT_FALSE(m.reflection.fresnel.lock_to_refraction_ior);
  EXPECT_FLOAT_EQ(m.reflection.fresnel.ior, 1.5f);
  EXPECT_TRUE(has_warning(r.warnings, "uses IOR 1.5")) << all(r.warnings);
  const Loaded low = load_material("ni_low", "newmtl m\nNi 0.5\n");
  ASSERT_TRUE(low.ok) << low.error;
  EXPECT_FLOAT_EQ(low.import.materials[0].refraction.ior, 1.5f);
  EXPECT_TRUE(has_warning(low.warnings, "Ni 0.5 is below 1; 1.5 is used")) << all(low.warnings);
}

TEST(ObjMtlMapping, GlassIllumRefractsWhatDissolveLetsThrough) {
  const Loaded r = load_material("glass", "newmtl m\nKd 0.1 0.1 0.1\nKs 1 1 1\nd 0.2\nTf 0.9 1 0.8\nNi 1.33\nillum 7\n");
  ASSERT_TRUE(r.ok) << r.error;
  const MaterialDesc& m = r.import.materials[0];
  EXPECT_FLOAT_EQ(m.refraction.weight, 0.8f);
  EXPECT_EQ(m.refraction.color, glm::vec3(0.9f, 1.0f, 0.8f));
  EXPECT_FLOAT_EQ(m.refraction.ior, 1.33f);
  EXPECT_FLOAT_EQ(m.refraction.glossiness, 1.0f);
  EXPECT_FLOAT_EQ(m.reflection.glossiness, 1.0f);
  EXPECT_EQ(m.cutout_opacity, 1.0f);
  // Tr is 1 - d; d wins over Tr.
  const Loaded tr = load_material("glass_tr", "newmtl m\nTr 0.25\nillum 4\n");
  ASSERT_TRUE(tr.ok) << tr.error;
  EXPECT_FLOAT_EQ(tr.import.materials[0].refraction.weight, 0.25f);
  EXPECT_EQ(tr.import.materials[0].refraction.color, glm::vec3(1.0f));
  const Loaded both = load_material("glass_both", "newmtl m\nd 0.5\nTr 0.9\nillum 6\n");
  ASSERT_TRUE(both.ok) << both.error;
  EXPECT_FLOAT_EQ(both.import.materials[0].refraction.weight, 0.5f);
  EXPECT_TRUE(has_warning(both.warnings, "both d and Tr are given; d is used")) << all(both.warnings);
}

TEST(ObjMtlMapping, ConstantDissolveWithoutGlassIsACutout) {
  const Loaded low = load_material("d_low", "newmtl m\nd 0.3\nillum 2\n");
  ASSERT_TRUE(low.ok) << low.error;
  EXPECT_FLOAT_EQ(low.import.materials[0].cutout_opacity, 0.3f);
  EXPECT_EQ(low.import.materials[0].refraction.weight, 0.0f);
  EXPECT_TRUE(has_warning(low.warnings, "cut out entirely")) << all(low.warnings);
  const Loaded high = load_material("d_high", "newmtl m\nd 0.7\n");
  ASSERT_TRUE(high.ok) << high.error;
  EXPECT_FLOAT_EQ(high.import.materials[0].cutout_opacity, 0.7f);
  EXPECT_TRUE(has_warning(high.warnings, "opaque")) << all(high.warnings);
}

TEST(ObjMtlMapping, MapDIsACutoutOnTheAlphaOrTheLuminance) {
  write_rgba_png("leaf_rgba.png");
  write_rgb_png("leaf_rgb.png");
  const Loaded rgba = load_material("mapd_rgba", "newmtl m\nmap_d leaf_rgba.png\n");
  ASSERT_TRUE(rgba.ok) << rgba.error;
  const TextureRef* a = binding(rgba, 0, "cutout_opacity");
  ASSERT_NE(a, nullptr);
  EXPECT_EQ(a->channel, 3);
  EXPECT_FLOAT_EQ(a->multiplier, 1.0f);
  EXPECT_FLOAT_EQ(a->offset, 0.0f);
  EXPECT_EQ(rgba.import.textures[a->texture].colorspace, TextureDesc::ColorSpace::Linear);
  const Loaded rgb = load_material("mapd_rgb", "newmtl m\nd 0.8\nmap_d leaf_rgb.png\n");
  ASSERT_TRUE(rgb.ok) << rgb.error;
  const TextureRef* l = binding(rgb, 0, "cutout_opacity");
  ASSERT_NE(l, nullptr);
  EXPECT_EQ(l->channel, -1);
  EXPECT_FLOAT_EQ(l->multiplier, 0.8f);
  // -imfchan picks the channel.
  const Loaded chan = load_material("mapd_chan", "newmtl m\nmap_d -imfchan g leaf_rgba.png\n");
  ASSERT_TRUE(chan.ok) << chan.error;
  EXPECT_EQ(binding(chan, 0, "cutout_opacity")->channel, 1);
  // With a glass model the map drives the refraction instead: 1 - d * texel.
  const Loaded glass = load_material("mapd_glass", "newmtl m\nmap_d leaf_rgba.png\nillum 9\n");
  ASSERT_TRUE(glass.ok) << glass.error;
  EXPECT_EQ(binding(glass, 0, "cutout_opacity"), nullptr);
  const TextureRef* w = binding(glass, 0, "refraction.weight");
  ASSERT_NE(w, nullptr);
  EXPECT_EQ(w->channel, 3);
  EXPECT_FLOAT_EQ(w->multiplier, -1.0f);
  EXPECT_FLOAT_EQ(w->offset, 1.0f);
}

TEST(ObjMtlMapping, KeAndMapKeAreTheIncandescence) {
  const Loaded ke = load_material("ke", "newmtl m\nKe 2 1 0\n");
  ASSERT_TRUE(ke.ok) << ke.error;
  EXPECT_EQ(ke.import.materials[0].incandescent.color, glm::vec3(2, 1, 0));
  EXPECT_EQ(ke.import.materials[0].incandescent.scale, 1.0f);
  write_rgb_png("glow.png");
  const Loaded map = load_material("mapke", "newmtl m\nKe 3 3 3\nmap_Ke glow.png\n");
  ASSERT_TRUE(map.ok) << map.error;
  const TextureRef* ref = binding(map, 0, "incandescent.color");
  ASSERT_NE(ref, nullptr);
  EXPECT_FLOAT_EQ(ref->multiplier, 3.0f);
  EXPECT_EQ(map.import.textures[ref->texture].colorspace, TextureDesc::ColorSpace::Srgb);
}

TEST(ObjMtlMapping, BumpIsALinearHeightScaledByBm) {
  write_rgb_png("height.png");
  const Loaded r = load_material("bump", "newmtl m\nbump -bm 2 height.png\nnorm height.png\n");
  ASSERT_TRUE(r.ok) << r.error;
  const TextureRef* ref = binding(r, 0, "bump.input");
  ASSERT_NE(ref, nullptr);
  EXPECT_EQ(ref->channel, -1);
  EXPECT_FLOAT_EQ(ref->multiplier, 1.0f);
  EXPECT_EQ(r.import.textures[ref->texture].colorspace, TextureDesc::ColorSpace::Linear);
  const MaterialDesc& m = r.import.materials[0];
  EXPECT_FLOAT_EQ(m.bump.scale, 0.02f);  // -bm 2 x 0.01 scene units
  EXPECT_EQ(m.bump.input, "height.png");
  EXPECT_TRUE(has_warning(r.warnings, "norm (a normal map) is not supported yet")) << all(r.warnings);
  // map_bump and no -bm: 1 unit.
  const Loaded plain = load_material("bump_plain", "newmtl m\nmap_bump height.png\n");
  ASSERT_TRUE(plain.ok) << plain.error;
  EXPECT_FLOAT_EQ(plain.import.materials[0].bump.scale, 0.01f);
  EXPECT_NE(binding(plain, 0, "bump.input"), nullptr);
}

TEST(ObjMtlMapping, ANormalMapWrittenAsBumpIsLeftOut) {
  // Blender writes tangent-space normal maps as map_Bump: mean colour near (0.5, 0.5, 1).
  write_png("normals.png", 3, {128, 128, 255, 120, 136, 250, 136, 120, 250, 128, 128, 255});
  const Loaded r = load_material("normal_bump", "newmtl m\nmap_Bump -bm 1 normals.png\n");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(binding(r, 0, "bump.input"), nullptr);
  EXPECT_TRUE(r.import.textures.empty());
  EXPECT_TRUE(r.import.materials[0].bump.input.empty());
  EXPECT_TRUE(has_warning(r.warnings, "looks like a tangent-space normal map")) << all(r.warnings);
  // The same file as a colour map stays.
  const Loaded kd = load_material("normal_kd", "newmtl m\nmap_Kd normals.png\nmap_Bump normals.png\n");
  ASSERT_TRUE(kd.ok) << kd.error;
  ASSERT_EQ(kd.import.textures.size(), 1u);
  EXPECT_EQ(binding(kd, 0, "diffuse.color")->texture, 0u);
}

TEST(ObjMtlMapping, PbrRoughnessAndMetal) {
  const Loaded r = load_material("pbr", "newmtl m\nKd 0.9 0.6 0.2\nPr 0.3\nPm 1\n");
  ASSERT_TRUE(r.ok) << r.error;
  const MaterialDesc& m = r.import.materials[0];
  EXPECT_TRUE(m.metal);
  EXPECT_FLOAT_EQ(m.reflection.glossiness, 0.7f);
  EXPECT_EQ(m.reflection.brdf, Brdf::Ggx);
  EXPECT_FLOAT_EQ(m.reflection.weight, 1.0f);
  EXPECT_EQ(m.reflection.color, glm::vec3(1.0f));
  EXPECT_FALSE(m.reflection.fresnel.use_ior);
  EXPECT_FLOAT_EQ(m.reflection.fresnel.facing, 1.0f);
  EXPECT_FLOAT_EQ(m.reflection.fresnel.perpendicular, 1.0f);
  EXPECT_EQ(m.diffuse.color, glm::vec3(0.9f, 0.6f, 0.2f));

  // A PBR dielectric without Ks: the specular layer at full weight; Pm 0.3 rounds to dielectric.
  write_rgb_png("rough.png");
  const Loaded d = load_material("pbr_d", "newmtl m\nPr 0.5\nPm 0.3\nmap_Pr rough.png\n");
  ASSERT_TRUE(d.ok) << d.error;
  const MaterialDesc& dm = d.import.materials[0];
  EXPECT_FALSE(dm.metal);
  EXPECT_FLOAT_EQ(dm.reflection.weight, 1.0f);
  EXPECT_FLOAT_EQ(dm.reflection.glossiness, 0.5f);
  EXPECT_TRUE(has_warning(d.warnings, "Pm 0.3 is taken as dielectric")) << all(d.warnings);
  const TextureRef* ref = binding(d, 0, "reflection.glossiness");
  ASSERT_NE(ref, nullptr);
  EXPECT_EQ(ref->channel, -1);
  EXPECT_FLOAT_EQ(ref->multiplier, -0.5f);
  EXPECT_FLOAT_EQ(ref->offset, 1.0f);
  EXPECT_EQ(d.import.textures[ref->texture].colorspace, TextureDesc::ColorSpace::Linear);
}

// ---- texture options -----------------------------------------------------------------------------

TEST(ObjMtlTextures, ScaleOffsetAndClamp) {
  write_rgb_png("opts.png");
  const Loaded r = load_material("opts",
                                 "newmtl m\n"
                                 "map_Kd -s 2 3 1 -o 0.25 0.5 -clamp on opts.png\n"
                                 "map_Ks -s 4 opts.png\n"
                                 "Ks 1 1 1\n"
                                 "map_Ke opts.png\n");
  ASSERT_TRUE(r.ok) << r.error;
  ASSERT_EQ(r.import.textures.size(), 3u);
  const TextureDesc& kd = r.import.textures[binding(r, 0, "diffuse.color")->texture];
  EXPECT_EQ(kd.scale, glm::vec2(2, 3));
  EXPECT_EQ(kd.offset, glm::vec2(0.25f, 0.5f));
  EXPECT_EQ(kd.wrap, TextureDesc::Wrap::Clamp);
  EXPECT_EQ(kd.rotation, 0.0f);
  EXPECT_EQ(kd.name, "opts.png");
  // -s u alone: v keeps its default 1 (MTL spec: v and w are optional).
  const TextureDesc& ks = r.import.textures[binding(r, 0, "reflection.color")->texture];
  EXPECT_EQ(ks.scale, glm::vec2(4, 1));
  EXPECT_EQ(ks.wrap, TextureDesc::Wrap::Repeat);
  EXPECT_EQ(ks.name, "opts.png (2)");
  // No options: the third form, the same image decoded once more only per colour space.
  const TextureDesc& ke = r.import.textures[binding(r, 0, "incandescent.color")->texture];
  EXPECT_EQ(ke.scale, glm::vec2(1, 1));
  EXPECT_EQ(ke.texels, kd.texels);
  EXPECT_TRUE(r.warnings.empty()) << all(r.warnings);
}

TEST(ObjMtlTextures, SameMapTwiceIsOneTexture) {
  write_rgb_png("shared.png");
  write_file("shared.mtl", "newmtl a\nmap_Kd shared.png\nnewmtl b\nmap_Kd shared.png\n");
  const Loaded r = load(write_file("shared.obj",
                                   "mtllib shared.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
                                   "usemtl a\nf 1/1 2/2 3/3\nusemtl b\nf 1/1 3/3 2/2\n"));
  ASSERT_TRUE(r.ok) << r.error;
  ASSERT_EQ(r.import.textures.size(), 1u);
  EXPECT_EQ(binding(r, 0, "diffuse.color")->texture, 0u);
  EXPECT_EQ(binding(r, 1, "diffuse.color")->texture, 0u);
}

TEST(ObjMtlTextures, MmAndIgnoredOptions) {
  write_rgb_png("mm.png");
  const Loaded r = load_material("mm", "newmtl m\nKd 0.5\nmap_Kd -mm 0.1 0.8 -blendu off -boost 2 -t 0.1 mm.png\n");
  ASSERT_TRUE(r.ok) << r.error;
  const TextureRef* ref = binding(r, 0, "diffuse.color");
  ASSERT_NE(ref, nullptr);
  // 0.5 * (0.1 + 0.8 * texel)
  EXPECT_FLOAT_EQ(ref->multiplier, 0.4f);
  EXPECT_FLOAT_EQ(ref->offset, 0.05f);
  EXPECT_TRUE(has_warning(r.warnings, "map_Kd: option -blendu off is ignored")) << all(r.warnings);
  EXPECT_TRUE(has_warning(r.warnings, "map_Kd: option -boost is ignored")) << all(r.warnings);
  EXPECT_TRUE(has_warning(r.warnings, "map_Kd: option -t is ignored")) << all(r.warnings);
}

TEST(ObjMtlTextures, FileNamesMayHoldSpacesAndMapsAreRelativeToTheMtl) {
  write_rgb_png("sub/my texture.png");
  write_file("sub/spaces.mtl", "newmtl m\nmap_Kd -clamp off my texture.png\n");
  const Loaded r = load(write_file("spaces.obj", quad_obj("sub/spaces.mtl", "m")));
  ASSERT_TRUE(r.ok) << r.error;
  const TextureDesc& t = r.import.textures.at(binding(r, 0, "diffuse.color")->texture);
  EXPECT_EQ(t.name, "my texture.png");
  EXPECT_EQ(t.source, temp_dir() + "sub/my texture.png");
}

TEST(ObjMtlTextures, IgnoredStatementsWarnOncePerMaterial) {
  const Loaded r = load_material("ignored",
                                 "newmtl m\nKa 0.1 0.1 0.1\nmap_Ka amb.png\nrefl -type sphere env.png\n"
                                 "disp d.png\nmap_Ns ns.png\nsharpness 60\nPs 0.5\nPs 0.6\nfrobnicate 1\n");
  ASSERT_TRUE(r.ok) << r.error;  // ignored maps are not loaded, so missing files do not matter
  EXPECT_TRUE(has_warning(r.warnings, "refl is not supported (ignored)")) << all(r.warnings);
  EXPECT_TRUE(has_warning(r.warnings, "disp is not supported (ignored)")) << all(r.warnings);
  EXPECT_TRUE(has_warning(r.warnings, "map_Ns is not supported (ignored)")) << all(r.warnings);
  EXPECT_TRUE(has_warning(r.warnings, "unknown statement 'frobnicate' (ignored)")) << all(r.warnings);
  EXPECT_FALSE(has_warning(r.warnings, "Ka")) << all(r.warnings);
  size_t ps = 0;
  for (const std::string& w : r.warnings) ps += w.find("Ps is not supported") != std::string::npos;
  EXPECT_EQ(ps, 1u) << all(r.warnings);
}

}  // namespace
