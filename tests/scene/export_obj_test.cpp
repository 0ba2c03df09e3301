// --export-geometry (host/scene/export_obj.h): the OBJ holds archwave's own triangles, read
// back bit for bit, with the per-kind index bases right when flat and smooth meshes mix.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "host/film/image_io.h"
#include "host/scene/export_obj.h"
#include "host/scene/loader_parts.h"
#include "host/scene/scene.h"
#include "tests/scene/scene_test_util.h"

namespace {

std::string src(const std::string& rel) { return std::string(ARCHWAVE_SOURCE_DIR) + "/" + rel; }

struct ObjGroup {
  std::string name, material;
  std::vector<glm::uvec3> v, vn;  // 0-based global indices of each face's corners
  bool smooth = false;
};
struct Obj {
  std::vector<glm::vec3> v, vn;
  std::vector<ObjGroup> groups;
};

// A reader of exactly what write_geometry_obj writes (a test of the writer, not a general
// OBJ reader: tinyobjloader is that, in host/scene/obj_mesh.cpp).
Obj read_back(const std::string& path) {
  Obj o;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (tag == "o") {
      o.groups.emplace_back();
      o.groups.back().name = line.substr(2);
    } else if (tag == "usemtl") {
      o.groups.back().material = line.substr(7);
    } else if (tag == "v" || tag == "vn") {
      std::string x, y, z;
      ls >> x >> y >> z;
      glm::vec3 p(std::strtof(x.c_str(), nullptr), std::strtof(y.c_str(), nullptr), std::strtof(z.c_str(), nullptr));
      (tag == "v" ? o.v : o.vn).push_back(p);
    } else if (tag == "f") {
      glm::uvec3 a, b;
      for (int k = 0; k < 3; ++k) {
        std::string c;
        ls >> c;
        size_t s = c.find("//");
        a[k] = uint32_t(std::stoul(c.substr(0, s)) - 1);
        if (s != std::string::npos) b[k] = uint32_t(std::stoul(c.substr(s + 2)) - 1);
        o.groups.back().smooth = s != std::string::npos;
      }
      o.groups.back().v.push_back(a);
      if (o.groups.back().smooth) o.groups.back().vn.push_back(b);
    }
  }
  return o;
}

void expect_round_trip(const std::string& scene_file) {
  aw::Scene s = aw::load_scene(scene_file);
  std::string path = ::testing::TempDir() + "archwave_export_" + std::to_string(::getpid()) + ".obj";
  aw::write_geometry_obj(s, path);
  Obj o = read_back(path);
  std::remove(path.c_str());
  // Every mesh, then every analytic sphere tessellated as the loader tessellates one.
  ASSERT_EQ(o.groups.size(), s.meshes.size() + s.spheres.size()) << scene_file;
  size_t faces = 0;
  for (size_t g = 0; g < s.meshes.size(); ++g) {
    const aw::TriangleMesh& m = s.meshes[g];
    const ObjGroup& og = o.groups[g];
    EXPECT_EQ(og.name, m.name);
    EXPECT_EQ(og.material, s.material_names[m.material]);
    ASSERT_EQ(og.v.size(), m.indices.size()) << m.name;
    EXPECT_EQ(og.smooth, !m.normals.empty()) << m.name;
    for (size_t t = 0; t < m.indices.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        // Bit for bit: %.9g round-trips a float.
        ASSERT_EQ(o.v[og.v[t][k]], m.positions[m.indices[t][k]]) << m.name << " triangle " << t;
        if (og.smooth) {
          ASSERT_EQ(o.vn[og.vn[t][k]], m.normals[m.indices[t][k]]) << m.name << " triangle " << t;
        }
      }
    faces += og.v.size();
  }
  const size_t per_sphere = aw::scene_detail::sphere_triangle_count(aw::scene_detail::kSphereSegmentsU,
                                                                    aw::scene_detail::kSphereSegmentsV);
  for (size_t k = 0; k < s.spheres.size(); ++k) {
    const aw::SphereDesc& sd = s.spheres[k];
    const ObjGroup& og = o.groups[s.meshes.size() + k];
    EXPECT_EQ(og.name, sd.name);
    EXPECT_EQ(og.material, s.material_names[sd.material]);
    ASSERT_EQ(og.v.size(), per_sphere) << sd.name;
    // Every vertex on the sphere.
    for (const auto& tri : og.v)
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(glm::length(o.v[tri[c]] - sd.center), sd.radius, 1e-5 * sd.radius) << sd.name;
  }
  EXPECT_EQ(faces, s.triangle_count());
}

TEST(ExportGeometry, BuiltInShapesRoundTrip) { expect_round_trip(src("scenes/bench/race_spheres.json")); }
TEST(ExportGeometry, CornellBoxRoundTrips) { expect_round_trip(src("scenes/cornell.json")); }
TEST(ExportGeometry, ObjMeshesRoundTrip) { expect_round_trip(src("scenes/knot.json")); }
// Smooth, flat (no normals), then smooth again, one of them mirrored: the normals' indices
// run on their own count.
TEST(ExportGeometry, FlatAndSmoothMeshesMixed) {
  aw::Scene s = aw::load_scene(aw_test::data_path("good_obj.json"));
  ASSERT_FALSE(s.meshes[0].normals.empty());
  ASSERT_TRUE(s.meshes[1].normals.empty());
  ASSERT_FALSE(s.meshes[2].normals.empty());
  expect_round_trip(aw_test::data_path("good_obj.json"));
}

TEST(ExportGeometry, UnwritablePathIsAnOutputErrorNamingIt) {
  aw::Scene s = aw::load_scene(src("scenes/cornell.json"));
  try {
    aw::write_geometry_obj(s, "/nonexistent-dir/x.obj");
    FAIL() << "no error";
  } catch (const aw::OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/x.obj"), std::string::npos) << e.what();
  }
}

}  // namespace
