// The glTF importer (host/scene/gltf_mesh.h): geometry, materials, textures and malformed files.
// Every glTF file here is written by the test itself (JSON with base64 data-URI buffers, or a
// .glb assembled byte by byte), so each case shows exactly what it feeds the importer.
#include <gtest/gtest.h>

#include "tests/scene/scene_test_util.h"
#include <png.h>
#include <unistd.h>

#include <cmath>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "host/scene/gltf_mesh.h"

namespace {

using aw::TextureDesc;
using aw::TextureRef;
using aw::scene_detail::GltfImport;
using aw::scene_detail::GltfPrimitive;
using aw::scene_detail::load_gltf;
using nlohmann::json;

constexpr int kByte = 5121, kShort = 5123, kInt = 5125, kFloat = 5126;
constexpr double kPi = 3.14159265358979323846;

using aw_test::base64;

std::string temp_dir() { return aw_test::scratch_dir("gltf"); }

std::string write_file(const std::string& name, const std::string& bytes) {
  return aw_test::write_scratch_file(temp_dir(), name, bytes);
}

// A 2 x 2 RGBA PNG (8 bits per channel), encoded with libpng in memory.
std::vector<uint8_t> png_2x2(const uint8_t rgba[16]) {
  std::vector<uint8_t> out;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return {};
  }
  png_set_write_fn(
      png, &out,
      [](png_structp p, png_bytep data, png_size_t n) {
        auto* o = static_cast<std::vector<uint8_t>*>(png_get_io_ptr(p));
        o->insert(o->end(), data, data + n);
      },
      nullptr);
  png_set_IHDR(png, info, 2, 2, 8, PNG_COLOR_TYPE_RGBA, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  png_write_row(png, const_cast<png_bytep>(rgba));
  png_write_row(png, const_cast<png_bytep>(rgba + 8));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return out;
}

// Row 0 (the top of the image): red, half-transparent mid green; row 1: transparent blue, white.
const uint8_t kPixels[16] = {255, 0, 0, 255, 0, 128, 0, 128, 0, 0, 255, 0, 255, 255, 255, 255};

double srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

// Builds a glTF document and its one binary buffer.
struct Gltf {
  json g = {{"asset", {{"version", "2.0"}}}};
  std::vector<uint8_t> bin;

  size_t append(const void* data, size_t bytes) {
    while (bin.size() % 4) bin.push_back(0);
    const size_t offset = bin.size();
    const auto* p = static_cast<const uint8_t*>(data);
    bin.insert(bin.end(), p, p + bytes);
    return offset;
  }
  int view(size_t offset, size_t length) {
    g["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", length}});
    return int(g["bufferViews"].size()) - 1;
  }
  int accessor(const void* data, size_t bytes, int component_type, size_t count, const char* type,
               bool normalized = false) {
    const int v = view(append(data, bytes), bytes);
    json a = {{"bufferView", v}, {"componentType", component_type}, {"count", count}, {"type", type}};
    if (normalized) a["normalized"] = true;
    g["accessors"].push_back(a);
    return int(g["accessors"].size()) - 1;
  }
  int floats(const std::vector<float>& v, const char* type, int components) {
    return accessor(v.data(), v.size() * 4, kFloat, v.size() / size_t(components), type);
  }
  int indices(const std::vector<uint32_t>& idx, int component_type) {
    std::vector<uint8_t> raw;
    for (uint32_t i : idx) {
      const int size = component_type == kByte ? 1 : component_type == kShort ? 2 : 4;
      for (int b = 0; b < size; ++b) raw.push_back(uint8_t(i >> (8 * b)));
    }
    return accessor(raw.data(), raw.size(), component_type, idx.size(), "SCALAR");
  }
  // Buffer 0 as a data URI (a .gltf) or as the GLB's BIN chunk.
  std::string gltf_text() {
    json doc = g;
    doc["buffers"] = json::array(
        {{{"byteLength", bin.size()}, {"uri", "data:application/octet-stream;base64," + base64(bin)}}});
    return doc.dump();
  }
  std::string glb() {
    json doc = g;
    std::vector<uint8_t> b = bin;
    while (b.size() % 4) b.push_back(0);
    doc["buffers"] = json::array({{{"byteLength", bin.size()}}});
    std::string text = doc.dump();
    while (text.size() % 4) text += ' ';
    std::string out = "glTF";
    auto u32 = [&](uint32_t v) {
      for (int i = 0; i < 4; ++i) out += char((v >> (8 * i)) & 0xFF);
    };
    u32(2);
    u32(uint32_t(12 + 8 + text.size() + 8 + b.size()));
    u32(uint32_t(text.size()));
    u32(0x4E4F534Au);  // "JSON"
    out += text;
    u32(uint32_t(b.size()));
    u32(0x004E4942u);  // "BIN\0"
    out.append(reinterpret_cast<const char*>(b.data()), b.size());
    return out;
  }
};

// A unit right triangle in the XY plane (positions, normals towards +Z), one primitive.
void add_triangle_mesh(Gltf& t, const std::string& name, json primitive_extra = json::object()) {
  const int pos = t.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
  const float s = float(1.0 / std::sqrt(2.0));
  const int nrm = t.floats({s, s, 0, s, s, 0, s, s, 0}, "VEC3", 3);
  json prim = {{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}}}};
  prim.update(primitive_extra);
  t.g["meshes"].push_back({{"name", name}, {"primitives", json::array({prim})}});
}

bool load(const std::string& path, GltfImport* out, std::string* error,
          std::vector<std::string>* warnings = nullptr) {
  std::vector<std::string> w;
  return load_gltf(path, out, error, warnings ? warnings : &w);
}

void expect_near(const glm::dvec3& a, const glm::dvec3& b, const std::string& what) {
  EXPECT_NEAR(a.x, b.x, 1e-12) << what;
  EXPECT_NEAR(a.y, b.y, 1e-12) << what;
  EXPECT_NEAR(a.z, b.z, 1e-12) << what;
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// ---- geometry -------------------------------------------------------------------------------

TEST(GltfGeometry, NodeHierarchyTransformsPositionsAndNormals) {
  Gltf t;
  add_triangle_mesh(t, "Tri");
  // Root: T(10, 0, 0) R(90 degrees about +Z) S(2); its child: a column-major matrix with a
  // translation (1, 2, 3) and a scale of 3 along Y. A third node is in no scene.
  const double h = std::sqrt(0.5);
  t.g["nodes"] = json::array(
      {{{"name", "Root"},
        {"mesh", 0},
        {"translation", {10, 0, 0}},
        {"rotation", {0, 0, h, h}},
        {"scale", {2, 2, 2}},
        {"children", {1}}},
       {{"name", "Child"}, {"mesh", 0}, {"matrix", {1, 0, 0, 0, 0, 3, 0, 0, 0, 0, 1, 0, 1, 2, 3, 1}}},
       {{"name", "Stray"}, {"mesh", 0}}});
  t.g["scenes"] = json::array({{{"nodes", {0}}}});
  t.g["scene"] = 0;
  GltfImport imp;
  std::string error;
  ASSERT_TRUE(load(write_file("hierarchy.gltf", t.gltf_text()), &imp, &error)) << error;
  ASSERT_EQ(imp.primitives.size(), 2u);  // Root's, then Child's; Stray is in no scene

  const GltfPrimitive& root = imp.primitives[0];
  EXPECT_EQ(root.name, "mesh 'Tri' primitive 0 (node 'Root')");
  EXPECT_EQ(root.material, -1);
  ASSERT_EQ(root.mesh.positions.size(), 3u);
  // p -> 10 + Rz(90) * 2p: (x, y) -> (-2y, 2x).
  expect_near(root.mesh.positions[0], {10, 0, 0}, "root p0");
  expect_near(root.mesh.positions[1], {10, 2, 0}, "root p1");
  expect_near(root.mesh.positions[2], {8, 0, 0}, "root p2");

  const GltfPrimitive& child = imp.primitives[1];
  EXPECT_EQ(child.name, "mesh 'Tri' primitive 0 (node 'Child')");
  // p -> 10 + Rz(90) * 2 * ((1, 2, 3) + diag(1, 3, 1) p).
  expect_near(child.mesh.positions[0], {6, 2, 6}, "child p0");
  expect_near(child.mesh.positions[1], {6, 4, 6}, "child p1");
  expect_near(child.mesh.positions[2], {0, 2, 6}, "child p2");
  // Normals by the inverse transpose: n = (1, 1, 0)/sqrt 2 -> Rz(90) diag(1, 1/3, 1) n,
  // normalised: (-1/3, 1, 0) / |.|.
  ASSERT_EQ(child.mesh.normals.size(), 3u);
  const glm::dvec3 expected = glm::normalize(glm::dvec3(-1.0 / 3.0, 1.0, 0.0));
  for (const glm::dvec3& n : child.mesh.normals) expect_near(n, expected, "child normal");
  ASSERT_EQ(child.mesh.indices.size(), 1u);
  EXPECT_EQ(child.mesh.indices[0], glm::uvec3(0, 1, 2));
}

TEST(GltfGeometry, MirroringNodeFlipsWindingAndTangentHandedness) {
  Gltf t;
  const int pos = t.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
  const int nrm = t.floats({0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3", 3);
  const int tan = t.floats({1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, -1}, "VEC4", 4);
  t.g["meshes"] = json::array(
      {{{"primitives",
         json::array({{{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}, {"TANGENT", tan}}}}})}}});
  t.g["nodes"] = json::array({{{"mesh", 0}, {"scale", {-1, 1, 1}}}});
  GltfImport imp;
  std::string error;
  ASSERT_TRUE(load(write_file("mirror.gltf", t.gltf_text()), &imp, &error)) << error;
  ASSERT_EQ(imp.primitives.size(), 1u);  // no scenes array: every root node
  const aw::scene_detail::DMesh& m = imp.primitives[0].mesh;
  EXPECT_EQ(imp.primitives[0].name, "mesh 0 primitive 0 (node 0)");
  ASSERT_EQ(m.indices.size(), 1u);
  EXPECT_EQ(m.indices[0], glm::uvec3(0, 2, 1));
  // The winding's normal still agrees with the vertex normals.
  const glm::dvec3 face = glm::cross(m.positions[m.indices[0].y] - m.positions[m.indices[0].x],
                                     m.positions[m.indices[0].z] - m.positions[m.indices[0].x]);
  EXPECT_GT(glm::dot(face, m.normals[0]), 0.0);
  ASSERT_EQ(m.tangents.size(), 3u);
  expect_near(glm::dvec3(m.tangents[0]), {-1, 0, 0}, "tangent");
  EXPECT_EQ(m.tangents[0].w, -1.0);
  EXPECT_EQ(m.tangents[2].w, 1.0);
}

TEST(GltfGeometry, UvsAreFlippedAndNormalizedIntegersDecoded) {
  Gltf t;
  const int pos = t.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
  const int uv_f = t.floats({0.25f, 0.0f, 1.0f, 0.75f, 0.5f, 1.0f}, "VEC2", 2);
  const uint16_t u16[6] = {0, 0, 65535, 16384, 32768, 65535};
  const int uv_s = t.accessor(u16, sizeof(u16), kShort, 3, "VEC2", true);
  const uint8_t u8[6] = {255, 51, 0, 0, 102, 255};
  const int uv_b = t.accessor(u8, sizeof(u8), kByte, 3, "VEC2", true);
  t.g["meshes"] = json::array(
      {{{"primitives", json::array({{{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv_f}}}},
                                    {{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv_s}}}},
                                    {{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv_b}}}}})}}});
  t.g["nodes"] = json::array({{{"mesh", 0}}});
  GltfImport imp;
  std::string error;
  ASSERT_TRUE(load(write_file("uvs.gltf", t.gltf_text()), &imp, &error)) << error;
  ASSERT_EQ(imp.primitives.size(), 3u);
  const auto& f = imp.primitives[0].mesh.uvs;
  ASSERT_EQ(f.size(), 3u);
  EXPECT_EQ(f[0], glm::dvec2(0.25, 1.0));
  EXPECT_EQ(f[1], glm::dvec2(1.0, 0.25));
  EXPECT_EQ(f[2], glm::dvec2(0.5, 0.0));
  const auto& s = imp.primitives[1].mesh.uvs;
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s[0], glm::dvec2(0.0, 1.0));
  EXPECT_EQ(s[1], glm::dvec2(1.0, 1.0 - 16384 / 65535.0));
  EXPECT_EQ(s[2], glm::dvec2(32768 / 65535.0, 0.0));
  const auto& b = imp.primitives[2].mesh.uvs;
  ASSERT_EQ(b.size(), 3u);
  EXPECT_EQ(b[0], glm::dvec2(1.0, 1.0 - 51 / 255.0));
  EXPECT_EQ(b[1], glm::dvec2(0.0, 1.0));
  EXPECT_EQ(b[2], glm::dvec2(102 / 255.0, 0.0));
}

// TEXCOORD_1 is the second UV set (flipped as TEXCOORD_0), and a textureInfo's texCoord 1
// binds its texture to it; texCoord 2 (no such set here) warns and reads set 0.
TEST(GltfGeometry, SecondUvSetAndTexCoord) {
  const std::vector<uint8_t> png = png_2x2(kPixels);
  Gltf t;
  const int pos = t.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
  const int uv0 = t.floats({0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 1.0f}, "VEC2", 2);
  const int uv1 = t.floats({0.5f, 0.25f, 2.0f, 0.25f, 0.5f, 3.0f}, "VEC2", 2);
  t.g["meshes"] = json::array({{{"primitives", json::array({{{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv0},
                                                                             {"TEXCOORD_1", uv1}}},
                                                             {"material", 0}}})}}});
  t.g["nodes"] = json::array({{{"mesh", 0}}});
  t.g["images"] = json::array({{{"uri", "data:image/png;base64," + base64(png)}}});
  t.g["textures"] = json::array({{{"source", 0}}});
  t.g["materials"] = json::array({{{"name", "Two"},
                                   {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}, {"texCoord", 1}}},
                                                             {"metallicRoughnessTexture", {{"index", 0}, {"texCoord", 2}}}}}}});
  GltfImport imp;
  std::string error;
  std::vector<std::string> warnings;
  ASSERT_TRUE(load(write_file("uv2.gltf", t.gltf_text()), &imp, &error, &warnings)) << error;
  ASSERT_EQ(imp.primitives.size(), 1u);
  const auto& m = imp.primitives[0].mesh;
  ASSERT_EQ(m.uvs2.size(), 3u);
  EXPECT_EQ(m.uvs2[0], glm::dvec2(0.5, 0.75));
  EXPECT_EQ(m.uvs2[1], glm::dvec2(2.0, 0.75));
  EXPECT_EQ(m.uvs2[2], glm::dvec2(0.5, -2.0));
  EXPECT_EQ(m.uvs[2], glm::dvec2(0.0, 0.0));
  const aw::TextureBindings& b = imp.bindings[0];
  EXPECT_EQ(b.at("diffuse.color").uv_set, 1);
  EXPECT_EQ(b.at("reflection.glossiness").uv_set, 0);
  bool warned = false;
  for (const std::string& w : warnings) warned |= contains(w, "texCoord 2");
  EXPECT_TRUE(warned);
}

// A quad of four vertices, two triangles, indexed with each unsigned type; the indices start
// at vertex 2 so that the importer's renumbering (order of first use) is exercised too.
TEST(GltfGeometry, IndicesOfEveryComponentType) {
  const std::vector<float> quad = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  const std::vector<uint32_t> idx = {2, 3, 0, 2, 0, 1};
  for (int type : {kByte, kShort, kInt}) {
    Gltf t;
    const int pos = t.floats(quad, "VEC3", 3);
    const int ind = t.indices(idx, type);
    t.g["meshes"] = json::array(
        {{{"primitives", json::array({{{"attributes", {{"POSITION", pos}}}, {"indices", ind}}})}}});
    t.g["nodes"] = json::array({{{"mesh", 0}}});
    GltfImport imp;
    std::string error;
    ASSERT_TRUE(load(write_file("indices_" + std::to_string(type) + ".gltf", t.gltf_text()), &imp, &error))
        << type << ": " << error;
    ASSERT_EQ(imp.primitives.size(), 1u);
    const auto& m = imp.primitives[0].mesh;
    ASSERT_EQ(m.indices.size(), 2u) << type;
    ASSERT_EQ(m.positions.size(), 4u) << type;
    for (size_t tri = 0; tri < 2; ++tri) {
      for (int c = 0; c < 3; ++c) {
        const uint32_t original = idx[tri * 3 + size_t(c)];
        const glm::dvec3 want(quad[3 * original], quad[3 * original + 1], quad[3 * original + 2]);
        EXPECT_EQ(m.positions[m.indices[tri][c]], want)
            << "type " << type << " triangle " << tri << " corner " << c;
      }
    }
  }
}

TEST(GltfGeometry, NonIndexedTrianglesStripsAndFans) {
  Gltf t;
  // Six vertices: as TRIANGLES two triangles; as a strip four; as a fan four.
  const int pos = t.floats({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 2, 0, 1, 2, 0}, "VEC3", 3);
  t.g["meshes"] =
      json::array({{{"primitives", json::array({{{"attributes", {{"POSITION", pos}}}},
                                                {{"attributes", {{"POSITION", pos}}}, {"mode", 5}},
                                                {{"attributes", {{"POSITION", pos}}}, {"mode", 6}},
                                                {{"attributes", {{"POSITION", pos}}}, {"mode", 1}}})}}});
  t.g["nodes"] = json::array({{{"mesh", 0}}});
  GltfImport imp;
  std::string error;
  std::vector<std::string> warnings;
  ASSERT_TRUE(load(write_file("topology.gltf", t.gltf_text()), &imp, &error, &warnings)) << error;
  ASSERT_EQ(imp.primitives.size(), 3u);  // the LINES primitive is skipped with a warning
  bool warned = false;
  for (const std::string& w : warnings) warned = warned || contains(w, "points or lines");
  EXPECT_TRUE(warned);

  auto corner = [](const aw::scene_detail::DMesh& m, size_t tri, int c) {
    return m.positions[m.indices[tri][c]];
  };
  const auto& tris = imp.primitives[0].mesh;
  ASSERT_EQ(tris.indices.size(), 2u);
  EXPECT_EQ(corner(tris, 1, 0), glm::dvec3(1, 1, 0));
  // Strip: p_i = {v_i, v_(i+1+i%2), v_(i+2-i%2)}; every triangle counter-clockwise seen from +Z.
  const auto& strip = imp.primitives[1].mesh;
  ASSERT_EQ(strip.indices.size(), 4u);
  for (size_t tri = 0; tri < 4; ++tri) {
    const glm::dvec3 n = glm::cross(corner(strip, tri, 1) - corner(strip, tri, 0),
                                    corner(strip, tri, 2) - corner(strip, tri, 0));
    EXPECT_GT(n.z, 0.0) << "strip triangle " << tri;
  }
  EXPECT_EQ(corner(strip, 1, 0), glm::dvec3(1, 0, 0));  // {v1, v3, v2}
  EXPECT_EQ(corner(strip, 1, 1), glm::dvec3(1, 1, 0));
  EXPECT_EQ(corner(strip, 1, 2), glm::dvec3(0, 1, 0));
  // Fan: p_i = {v_(i+1), v_(i+2), v_0}.
  const auto& fan = imp.primitives[2].mesh;
  ASSERT_EQ(fan.indices.size(), 4u);
  EXPECT_EQ(corner(fan, 3, 0), glm::dvec3(0, 2, 0));
  EXPECT_EQ(corner(fan, 3, 1), glm::dvec3(1, 2, 0));
  EXPECT_EQ(corner(fan, 3, 2), glm::dvec3(0, 0, 0));
}

// Two primitives share one vertex accessor, each using part of it (each gets only its own
// vertices); the accessor is sparse: vertex 3 is replaced (glTF 2.0 §3.6.2.3).
TEST(GltfGeometry, SharedSparseVertexAccessor) {
  Gltf t;
  const int pos = t.floats({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, "VEC3", 3);
  const uint8_t sparse_index[1] = {3};
  const float sparse_value[3] = {0, 2, 0};
  const int iv = t.view(t.append(sparse_index, 1), 1);
  const int vv = t.view(t.append(sparse_value, sizeof(sparse_value)), sizeof(sparse_value));
  t.g["accessors"][pos]["sparse"] = {{"count", 1},
                                     {"indices", {{"bufferView", iv}, {"componentType", kByte}}},
                                     {"values", {{"bufferView", vv}}}};
  const int a = t.indices({0, 1, 2}, kByte), b = t.indices({2, 3, 0}, kByte);
  t.g["meshes"] =
      json::array({{{"primitives", json::array({{{"attributes", {{"POSITION", pos}}}, {"indices", a}},
                                                {{"attributes", {{"POSITION", pos}}}, {"indices", b}}})}}});
  t.g["nodes"] = json::array({{{"mesh", 0}}});
  GltfImport imp;
  std::string error;
  ASSERT_TRUE(load(write_file("sparse.gltf", t.gltf_text()), &imp, &error)) << error;
  ASSERT_EQ(imp.primitives.size(), 2u);
  EXPECT_EQ(imp.primitives[0].mesh.positions.size(), 3u);
  const auto& m = imp.primitives[1].mesh;
  ASSERT_EQ(m.positions.size(), 3u);
  EXPECT_EQ(m.indices[0], glm::uvec3(0, 1, 2));
  EXPECT_EQ(m.positions[0], glm::dvec3(1, 1, 0));
  EXPECT_EQ(m.positions[1], glm::dvec3(0, 2, 0));  // the sparse replacement
  EXPECT_EQ(m.positions[2], glm::dvec3(0, 0, 0));
}

// ---- materials ------------------------------------------------------------------------------

TEST(GltfMaterials, MetallicRoughnessAndExtensionsMapToTheArchitecturalMaterial) {
  Gltf t;
  add_triangle_mesh(t, "Tri", {{"material", 0}});
  t.g["nodes"] = json::array({{{"mesh", 0}}});
  t.g["materials"] = json::array({
      {{"name", "Gold"},
       {"pbrMetallicRoughness",
        {{"baseColorFactor", {1.0, 0.766, 0.336, 1.0}}, {"metallicFactor", 1.0}, {"roughnessFactor", 0.25}}}},
      {{"name", "Glass"},
       {"pbrMetallicRoughness",
        {{"baseColorFactor", {0.9, 0.9, 0.9, 1.0}}, {"metallicFactor", 0.0}, {"roughnessFactor", 0.0}}},
       {"extensions",
        {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}},
         {"KHR_materials_ior", {{"ior", 1.45}}}}}},
      {{"name", "Solid glass"},
       {"pbrMetallicRoughness", {{"metallicFactor", 0.0}, {"roughnessFactor", 0.2}}},
       {"extensions",
        {{"KHR_materials_transmission", {{"transmissionFactor", 0.8}}},
         {"KHR_materials_volume",
          {{"thicknessFactor", 0.1}, {"attenuationDistance", 2.0}, {"attenuationColor", {0.5, 0.8, 0.9}}}}}}},
      {{"name", "Lamp"},
       {"pbrMetallicRoughness", {{"metallicFactor", 0.0}}},
       {"emissiveFactor", {1.0, 0.5, 0.25}},
       {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 5.0}}}}}},
      {{"name", "Car paint"},
       {"pbrMetallicRoughness",
        {{"baseColorFactor", {0.5, 0.0, 0.0, 1.0}}, {"metallicFactor", 0.0}, {"roughnessFactor", 0.5}}},
       {"extensions",
        {{"KHR_materials_clearcoat", {{"clearcoatFactor", 0.8}, {"clearcoatRoughnessFactor", 0.1}}},
         {"KHR_materials_specular", {{"specularFactor", 0.5}, {"specularColorFactor", {1.0, 0.9, 0.8}}}}}}},
      json::object(),  // no properties: glTF's defaults, a white fully rough metal (§3.9.6)
      {{"name", "Leaves"},
       {"pbrMetallicRoughness", {{"baseColorFactor", {0.2, 0.6, 0.1, 0.2}}, {"metallicFactor", 0.3}}},
       {"alphaMode", "MASK"},
       {"alphaCutoff", 0.3}},
  });
  GltfImport imp;
  std::string error;
  std::vector<std::string> warnings;
  ASSERT_TRUE(load(write_file("materials.gltf", t.gltf_text()), &imp, &error, &warnings)) << error;
  ASSERT_EQ(imp.materials.size(), 7u);
  ASSERT_EQ(imp.material_names.size(), 7u);
  ASSERT_EQ(imp.bindings.size(), 7u);
  EXPECT_TRUE(imp.textures.empty());
  EXPECT_EQ(imp.primitives.at(0).material, 0);
  EXPECT_EQ(imp.material_names[0], "Gold");
  EXPECT_EQ(imp.material_names[5], "material 5");

  const aw::MaterialDesc& gold = imp.materials[0];
  EXPECT_TRUE(gold.metal);
  EXPECT_EQ(gold.diffuse.color, glm::vec3(1.0f, 0.766f, 0.336f));
  EXPECT_EQ(gold.reflection.weight, 1.0f);
  EXPECT_EQ(gold.reflection.color, glm::vec3(1.0f));  // `metal` tints it with the diffuse colour
  EXPECT_EQ(gold.reflection.brdf, aw::Brdf::Ggx);
  EXPECT_FLOAT_EQ(gold.reflection.glossiness, 0.75f);
  EXPECT_FALSE(gold.reflection.fresnel.use_ior);  // reflectance 1 x base colour at every angle
  EXPECT_EQ(gold.reflection.fresnel.facing, 1.0f);
  EXPECT_EQ(gold.reflection.fresnel.perpendicular, 1.0f);
  EXPECT_EQ(gold.refraction.weight, 0.0f);

  const aw::MaterialDesc& glass = imp.materials[1];
  EXPECT_FALSE(glass.metal);
  EXPECT_EQ(glass.refraction.weight, 1.0f);
  EXPECT_FLOAT_EQ(glass.refraction.ior, 1.45f);
  EXPECT_TRUE(glass.refraction.thin_walled);  // no KHR_materials_volume: a thin wall
  EXPECT_EQ(glass.refraction.color, glm::vec3(0.9f));
  EXPECT_EQ(glass.refraction.glossiness, 1.0f);
  EXPECT_TRUE(glass.reflection.fresnel.use_ior);
  EXPECT_TRUE(glass.reflection.fresnel.lock_to_refraction_ior);
  EXPECT_EQ(glass.reflection.glossiness, 1.0f);

  const aw::MaterialDesc& solid = imp.materials[2];
  EXPECT_FLOAT_EQ(solid.refraction.weight, 0.8f);
  EXPECT_FALSE(solid.refraction.thin_walled);
  EXPECT_FLOAT_EQ(solid.refraction.ior, 1.5f);
  EXPECT_FLOAT_EQ(solid.refraction.glossiness, 0.8f);
  EXPECT_TRUE(solid.refraction.fog.enable);
  EXPECT_TRUE(solid.refraction.fog.use_end_color);
  EXPECT_EQ(solid.refraction.fog.distance, 2.0f);
  EXPECT_EQ(solid.refraction.fog.end_color, glm::vec3(0.5f, 0.8f, 0.9f));

  const aw::MaterialDesc& lamp = imp.materials[3];
  EXPECT_EQ(lamp.incandescent.color, glm::vec3(1.0f, 0.5f, 0.25f));
  EXPECT_EQ(lamp.incandescent.scale, 5.0f);

  const aw::MaterialDesc& paint = imp.materials[4];
  EXPECT_FALSE(paint.metal);
  EXPECT_EQ(paint.diffuse.color, glm::vec3(0.5f, 0.0f, 0.0f));
  EXPECT_FLOAT_EQ(paint.reflection.glossiness, 0.5f);
  EXPECT_EQ(paint.reflection.weight, 0.5f);  // KHR_materials_specular
  EXPECT_EQ(paint.reflection.color, glm::vec3(1.0f, 0.9f, 0.8f));
  EXPECT_FLOAT_EQ(paint.reflection2.weight, 0.8f);
  EXPECT_FLOAT_EQ(paint.reflection2.glossiness, 0.9f);
  EXPECT_EQ(paint.reflection2.brdf, aw::Brdf::Ggx);
  EXPECT_TRUE(paint.reflection2.fresnel.use_ior);
  EXPECT_FALSE(paint.reflection2.fresnel.lock_to_refraction_ior);
  EXPECT_EQ(paint.reflection2.fresnel.ior, 1.5f);

  const aw::MaterialDesc& plain = imp.materials[5];
  EXPECT_TRUE(plain.metal);
  EXPECT_EQ(plain.diffuse.color, glm::vec3(1.0f));
  EXPECT_EQ(plain.reflection.glossiness, 0.0f);

  const aw::MaterialDesc& leaves = imp.materials[6];
  EXPECT_FALSE(leaves.metal);              // metallicFactor 0.3: a dielectric, with a warning
  EXPECT_EQ(leaves.cutout_opacity, 0.0f);  // alpha 0.2 < alphaCutoff 0.3: a hole everywhere
  bool warned = false;
  for (const std::string& w : warnings)
    warned = warned || (contains(w, "'Leaves'") && contains(w, "metallicFactor 0.3"));
  EXPECT_TRUE(warned);
}

// ---- textures -------------------------------------------------------------------------------

// KHR_texture_transform is defined in glTF's UV space (v down); TextureDesc transforms
// archwave's V-up UVs. Looking up at the TextureDesc-transformed flipped UV must give the
// texel that glTF's transform picks, for any UV.
void expect_transform_matches_gltf(const TextureDesc& t, glm::dvec2 offset, double rotation,
                                   glm::dvec2 scale) {
  const double a = double(t.rotation) * kPi / 180.0;
  for (const glm::dvec2 uv_g :
       {glm::dvec2(0, 0), glm::dvec2(1, 0), glm::dvec2(0.3, 0.7), glm::dvec2(-2, 5)}) {
    // glTF: uv' = offset + [[cos r, sin r], [-sin r, cos r]] (scale * uv).
    const glm::dvec2 s = scale * uv_g;
    const glm::dvec2 gltf = offset + glm::dvec2(std::cos(rotation) * s.x + std::sin(rotation) * s.y,
                                                -std::sin(rotation) * s.x + std::cos(rotation) * s.y);
    const glm::dvec2 want(gltf.x, 1.0 - gltf.y);  // archwave's (u, 1 - v) of it
    // TextureDesc: uv' = R(rotation, counter-clockwise) (uv * scale) + offset on uv = (u, 1 - v).
    const glm::dvec2 uv(uv_g.x, 1.0 - uv_g.y);
    const glm::dvec2 su = uv * glm::dvec2(t.scale);
    const glm::dvec2 got =
        glm::dvec2(std::cos(a) * su.x - std::sin(a) * su.y, std::sin(a) * su.x + std::cos(a) * su.y) +
        glm::dvec2(t.offset);
    EXPECT_NEAR(got.x, want.x, 1e-5) << uv_g.x << ", " << uv_g.y;
    EXPECT_NEAR(got.y, want.y, 1e-5) << uv_g.x << ", " << uv_g.y;
  }
}

// Needs host/scene/texture_image.cpp (decode_texture_image).
TEST(GltfTextures, DataUriImageBindingsCutoutAndTextureTransform) {
  const std::vector<uint8_t> png = png_2x2(kPixels);
  ASSERT_FALSE(png.empty());
  Gltf t;
  add_triangle_mesh(t, "Tri", {{"material", 0}});
  t.g["nodes"] = json::array({{{"mesh", 0}}});
  t.g["images"] = json::array({{{"uri", "data:image/png;base64," + base64(png)}}});
  t.g["samplers"] = json::array({{{"wrapS", 33071}, {"wrapT", 33071}}});
  t.g["textures"] = json::array({{{"source", 0}, {"sampler", 0}}, {{"source", 0}}});
  const double rotation = kPi / 2;
  t.g["materials"] =
      json::array({{{"name", "Fence"},
                    {"pbrMetallicRoughness",
                     {{"baseColorTexture",
                       {{"index", 0},
                        {"extensions",
                         {{"KHR_texture_transform",
                           {{"offset", {0.25, 0.5}}, {"rotation", rotation}, {"scale", {2, 3}}}}}}}},
                      {"metallicRoughnessTexture", {{"index", 1}}},
                      {"metallicFactor", 0.0},
                      {"roughnessFactor", 0.3}}},
                    {"alphaMode", "MASK"},
                    {"alphaCutoff", 0.3}}});
  GltfImport imp;
  std::string error;
  ASSERT_TRUE(load(write_file("fence.gltf", t.gltf_text()), &imp, &error)) << error;
  ASSERT_EQ(imp.materials.size(), 1u);
  ASSERT_EQ(imp.textures.size(), 2u);
  const aw::TextureBindings& b = imp.bindings[0];
  ASSERT_EQ(b.size(), 3u);

  const TextureRef& colour = b.at("diffuse.color");
  EXPECT_EQ(colour.channel, -1);
  EXPECT_EQ(colour.multiplier, 1.0f);
  EXPECT_EQ(colour.offset, 0.0f);
  const TextureRef& gloss = b.at("reflection.glossiness");
  EXPECT_EQ(gloss.channel, 1);  // roughness is G
  EXPECT_FLOAT_EQ(gloss.multiplier, -0.3f);
  EXPECT_EQ(gloss.offset, 1.0f);
  const TextureRef& cutout = b.at("cutout_opacity");
  EXPECT_EQ(cutout.texture, colour.texture);
  EXPECT_EQ(cutout.channel, 3);
  EXPECT_NEAR(cutout.offset + cutout.multiplier * 0.3f, 0.5f, 1e-6f);  // alpha = cutoff -> 0.5
  EXPECT_NEAR(cutout.offset + cutout.multiplier * 1.0f, 1.0f, 1e-6f);  // opaque stays 1
  EXPECT_GE(cutout.offset, 0.0f);                                      // transparent stays >= 0

  const TextureDesc& base = imp.textures[colour.texture];
  const TextureDesc& rough = imp.textures[gloss.texture];
  ASSERT_NE(colour.texture, gloss.texture);
  EXPECT_EQ(base.name, "fence.gltf#texture 0");
  EXPECT_EQ(rough.name, "fence.gltf#texture 1");
  EXPECT_EQ(base.colorspace, TextureDesc::ColorSpace::Srgb);
  EXPECT_EQ(rough.colorspace, TextureDesc::ColorSpace::Linear);
  EXPECT_EQ(base.wrap, TextureDesc::Wrap::Clamp);
  EXPECT_EQ(rough.wrap, TextureDesc::Wrap::Repeat);
  ASSERT_EQ(base.width, 2);
  ASSERT_EQ(base.height, 2);
  ASSERT_EQ(base.texels.size(), 16u);
  ASSERT_EQ(rough.texels.size(), 16u);
  // Texel 1 of row 0 (the file's top row): green 128, alpha 128; sRGB for the base colour,
  // linear for the roughness map; alpha is always linear.
  EXPECT_NEAR(base.texels[4 + 1], srgb_to_linear(128 / 255.0), 1e-6);
  EXPECT_NEAR(rough.texels[4 + 1], 128 / 255.0, 1e-6);
  EXPECT_NEAR(base.texels[4 + 3], 128 / 255.0, 1e-6);
  EXPECT_EQ(base.texels[0], 1.0f);  // red

  // KHR_texture_transform: the same angle (degrees), the same scale, the offset of the V flip.
  EXPECT_FLOAT_EQ(base.rotation, 90.0f);
  EXPECT_EQ(base.scale, glm::vec2(2.0f, 3.0f));
  EXPECT_NEAR(base.offset.x, 3.25f, 1e-6f);
  EXPECT_NEAR(base.offset.y, 0.5f, 1e-6f);
  expect_transform_matches_gltf(base, {0.25, 0.5}, rotation, {2, 3});
  EXPECT_EQ(rough.rotation, 0.0f);
  EXPECT_EQ(rough.offset, glm::vec2(0.0f));
  EXPECT_EQ(rough.scale, glm::vec2(1.0f));
}

TEST(GltfTextures, TransformRuleMatchesGltfAtAnotherAngle) {
  TextureDesc t;
  // Computed by the importer's rule for offset (0.1, 0.2), rotation 0.3 rad, scale (1.5, -2):
  // (o_u + s_v sin r, 1 - o_v - s_v cos r); checked against glTF's own formula below.
  const double r = 0.3;
  t.rotation = float(r * 180.0 / kPi);
  t.scale = glm::vec2(1.5f, -2.0f);
  t.offset = glm::vec2(float(0.1 + -2.0 * std::sin(r)), float(1.0 - 0.2 - -2.0 * std::cos(r)));
  expect_transform_matches_gltf(t, {0.1, 0.2}, r, {1.5, -2});
}

// A .glb with its geometry and an emissive PNG in the BIN chunk (the image in a bufferView).
// Needs host/scene/texture_image.cpp (decode_texture_image).
TEST(GltfTextures, GlbWithBufferViewImage) {
  Gltf t;
  const int pos = t.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
  const int ind = t.indices({0, 1, 2}, kShort);
  const std::vector<uint8_t> png = png_2x2(kPixels);
  const int image_view = t.view(t.append(png.data(), png.size()), png.size());
  t.g["images"] = json::array({{{"bufferView", image_view}, {"mimeType", "image/png"}}});
  t.g["textures"] = json::array({{{"source", 0}}});
  t.g["materials"] = json::array({{{"emissiveFactor", {1, 1, 1}}, {"emissiveTexture", {{"index", 0}}}}});
  t.g["meshes"] = json::array(
      {{{"primitives",
         json::array({{{"attributes", {{"POSITION", pos}}}, {"indices", ind}, {"material", 0}}})}}});
  t.g["nodes"] = json::array({{{"mesh", 0}, {"translation", {0, 0, -1}}}});
  t.g["scenes"] = json::array({{{"nodes", {0}}}});
  GltfImport imp;
  std::string error;
  ASSERT_TRUE(load(write_file("lamp.glb", t.glb()), &imp, &error)) << error;
  ASSERT_EQ(imp.primitives.size(), 1u);
  expect_near(imp.primitives[0].mesh.positions[1], {1, 0, -1}, "glb position");
  ASSERT_EQ(imp.textures.size(), 1u);
  const TextureDesc& tex = imp.textures[0];
  EXPECT_EQ(tex.source, "lamp.glb, image 0");
  EXPECT_EQ(tex.colorspace, TextureDesc::ColorSpace::Srgb);
  ASSERT_EQ(tex.texels.size(), 16u);
  EXPECT_NEAR(tex.texels[8 + 2], 1.0f, 1e-6f);  // row 1's blue
  const TextureRef& e = imp.bindings[0].at("incandescent.color");
  EXPECT_EQ(e.texture, 0u);
  EXPECT_EQ(e.multiplier, 1.0f);
}

// ---- malformed files ------------------------------------------------------------------------

// One triangle (36 bytes of positions) for the malformed-file cases to break.
Gltf triangle_file() {
  Gltf t;
  add_triangle_mesh(t, "Tri");
  t.g["nodes"] = json::array({{{"mesh", 0}}});
  return t;
}

std::string load_error(const std::string& name, const std::string& contents) {
  GltfImport imp;
  std::string error;
  if (load(write_file(name, contents), &imp, &error)) return "<loaded>";
  EXPECT_TRUE(imp.primitives.empty() && imp.materials.empty()) << "a failed import leaves nothing behind";
  return error;
}

TEST(GltfErrors, TruncatedGlb) {
  const std::string glb = triangle_file().glb();
  const std::string e = load_error("truncated.glb", glb.substr(0, glb.size() / 2));
  EXPECT_TRUE(contains(e, "truncated .glb")) << e;
  EXPECT_TRUE(contains(e, std::to_string(glb.size()))) << e;
  EXPECT_TRUE(contains(load_error("tiny.glb", "glTF\x02"), "truncated .glb"));
}

TEST(GltfErrors, BufferShorterThanTheAccessorNeeds) {
  Gltf t = triangle_file();
  t.g["accessors"][0]["count"] = 4;  // 48 bytes from a 36-byte bufferView
  const std::string e = load_error("short_accessor.gltf", t.gltf_text());
  EXPECT_TRUE(contains(e, "accessor 0 (POSITION of mesh 'Tri' primitive 0 (node 0))")) << e;
  EXPECT_TRUE(contains(e, "36 bytes of bufferView 0")) << e;

  Gltf v = triangle_file();
  v.g["bufferViews"][1]["byteLength"] = 64;  // the normals' view runs past the 72-byte buffer
  const std::string e2 = load_error("short_buffer.gltf", v.gltf_text());
  EXPECT_TRUE(contains(e2, "bufferView 1")) << e2;
  EXPECT_TRUE(contains(e2, "past the end of buffer 0")) << e2;
}

TEST(GltfErrors, IndexOutOfRange) {
  Gltf t = triangle_file();
  const int ind = t.indices({0, 1, 7}, kShort);
  t.g["meshes"][0]["primitives"][0]["indices"] = ind;
  const std::string e = load_error("bad_index.gltf", t.gltf_text());
  EXPECT_TRUE(contains(e, "index 7")) << e;
  EXPECT_TRUE(contains(e, "out of range")) << e;
  EXPECT_TRUE(contains(e, "3 vertices")) << e;
}

TEST(GltfErrors, MissingExternalBuffer) {
  Gltf t = triangle_file();
  json doc = t.g;
  doc["buffers"] = json::array({{{"byteLength", t.bin.size()}, {"uri", "missing.bin"}}});
  const std::string e = load_error("missing_buffer.gltf", doc.dump());
  EXPECT_TRUE(contains(e, "missing.bin")) << e;
  EXPECT_TRUE(contains(e, "not found")) << e;
}

TEST(GltfGeometry, ExternalBufferNextToTheFile) {
  Gltf t = triangle_file();
  write_file("tri.bin", std::string(t.bin.begin(), t.bin.end()));
  json doc = t.g;
  doc["buffers"] = json::array({{{"byteLength", t.bin.size()}, {"uri", "tri.bin"}}});
  GltfImport imp;
  std::string error;
  ASSERT_TRUE(load(write_file("external_buffer.gltf", doc.dump()), &imp, &error)) << error;
  EXPECT_EQ(imp.primitives.size(), 1u);
}

TEST(GltfErrors, NotJsonAtAll) {
  EXPECT_TRUE(contains(load_error("text.gltf", "hello, world"), "not a glTF file"));
  const std::string e = load_error("broken.gltf", "{\"asset\": {\"version\": \"2.0\"");
  EXPECT_NE(e, "<loaded>");
  EXPECT_FALSE(e.empty());
  GltfImport imp;
  std::string error;
  EXPECT_FALSE(load(temp_dir() + "does_not_exist.gltf", &imp, &error));
  EXPECT_EQ(error, "no such file");
}

TEST(GltfErrors, StructuralProblemsAreNamed) {
  Gltf cycle = triangle_file();
  cycle.g["nodes"] = json::array({{{"mesh", 0}, {"children", {1}}}, {{"children", {0}}}});
  cycle.g["scenes"] = json::array({{{"nodes", {0}}}});
  EXPECT_TRUE(contains(load_error("cycle.gltf", cycle.gltf_text()), "node 0 is reached twice"));

  Gltf draco = triangle_file();
  draco.g["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  EXPECT_TRUE(contains(load_error("draco.gltf", draco.gltf_text()),
                       "requires the extension KHR_draco_mesh_compression"));

  Gltf nan = triangle_file();
  const float bad[9] = {0, 0, 0, NAN, 0, 0, 0, 1, 0};
  nan.g["meshes"][0]["primitives"][0]["attributes"]["POSITION"] =
      nan.accessor(bad, sizeof(bad), kFloat, 3, "VEC3");
  EXPECT_TRUE(contains(load_error("nan.gltf", nan.gltf_text()), "element 1 has a value that is not finite"));

  Gltf mat = triangle_file();
  mat.g["meshes"][0]["primitives"][0]["material"] = 4;
  EXPECT_TRUE(contains(load_error("no_material.gltf", mat.gltf_text()), "material 4 does not exist"));
}

// Robustness: every truncation of a small .glb, and every digit of its JSON or byte of its BIN
// chunk changed, either loads or fails with a message; none crashes or hangs.
TEST(GltfErrors, DamagedGlbNeverCrashes) {
  Gltf t;
  const int pos = t.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
  const int uv = t.floats({0, 0, 1, 0, 0, 1}, "VEC2", 2);
  const int ind = t.indices({0, 1, 2}, kShort);
  const std::vector<uint8_t> png = png_2x2(kPixels);
  const int image_view = t.view(t.append(png.data(), png.size()), png.size());
  t.g["images"] = json::array({{{"bufferView", image_view}, {"mimeType", "image/png"}}});
  t.g["textures"] = json::array({{{"source", 0}}});
  t.g["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
  t.g["meshes"] =
      json::array({{{"primitives", json::array({{{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv}}},
                                                 {"indices", ind},
                                                 {"material", 0}}})}}});
  t.g["nodes"] = json::array({{{"mesh", 0}}});
  const std::string glb = t.glb();
  const size_t json_end = 20 + (size_t(uint8_t(glb[12])) | size_t(uint8_t(glb[13])) << 8);
  size_t loaded = 0, failed = 0;
  auto attempt = [&](const std::string& bytes) {
    GltfImport imp;
    std::string error;
    if (load(write_file("damaged.glb", bytes), &imp, &error)) {
      ++loaded;
    } else {
      ++failed;
      EXPECT_FALSE(error.empty());
    }
  };
  for (size_t n = 0; n < glb.size(); ++n) attempt(glb.substr(0, n));
  for (size_t i = 20; i < json_end; ++i) {
    if (!std::isdigit(static_cast<unsigned char>(glb[i]))) continue;
    std::string d = glb;
    d[i] = '9';
    attempt(d);
  }
  for (size_t i = json_end; i < glb.size(); ++i) {
    std::string d = glb;
    d[i] = char(0xFF);
    attempt(d);
  }
  EXPECT_GT(failed, glb.size());  // at least every truncation
  EXPECT_GT(loaded, 0u);          // some damage is harmless (texels, a padding byte)
}

}  // namespace
