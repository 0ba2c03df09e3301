// Built-in shapes, OBJ meshes and transforms, checked on the loaded Scene.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/scene/scene_test_util.h"

using aw_test::bounds_of;
using aw_test::centroid;
using aw_test::data_path;
using aw_test::face_normal;

namespace {

// Every triangle's winding normal and every vertex normal point away from `inside` (a point
// inside a convex shape), and vertex normals are unit length.
void expect_outward(const aw::TriangleMesh& m, const glm::vec3& inside) {
  ASSERT_EQ(m.normals.size(), m.positions.size()) << m.name;
  size_t bad_faces = 0, bad_normals = 0, non_unit = 0;
  for (size_t t = 0; t < m.indices.size(); ++t) {
    if (!(glm::dot(face_normal(m, t), centroid(m, t) - inside) > 0)) ++bad_faces;
  }
  for (size_t v = 0; v < m.positions.size(); ++v) {
    if (!(glm::dot(m.normals[v], m.positions[v] - inside) > 0)) ++bad_normals;
    if (std::fabs(glm::length(m.normals[v]) - 1.0f) > 1e-5f) ++non_unit;
  }
  EXPECT_EQ(bad_faces, 0u) << m.name;
  EXPECT_EQ(bad_normals, 0u) << m.name;
  EXPECT_EQ(non_unit, 0u) << m.name;
}

// For flat shapes: the winding normal agrees with the (constant) vertex normal `n`.
void expect_flat(const aw::TriangleMesh& m, const glm::vec3& n) {
  for (size_t t = 0; t < m.indices.size(); ++t) {
    const glm::vec3 f = glm::normalize(face_normal(m, t));
    EXPECT_NEAR(glm::dot(f, n), 1.0f, 1e-5f) << m.name << " triangle " << t;
  }
  for (const glm::vec3& vn : m.normals) {
    EXPECT_NEAR(vn.x, n.x, 1e-6f);
    EXPECT_NEAR(vn.y, n.y, 1e-6f);
    EXPECT_NEAR(vn.z, n.z, 1e-6f);
  }
}

class FullSceneGeometry : public ::testing::Test {
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
aw::Scene* FullSceneGeometry::scene_ = nullptr;

TEST_F(FullSceneGeometry, SphereTessellation) {
  const aw::TriangleMesh& s = scene_->meshes[2];  // center (0,1,0), radius 1
  // 128 segments around x 64 rings; the pole triangles of each quad strip are single.
  EXPECT_EQ(s.indices.size(), 128u * (2u * 64u - 2u));
  EXPECT_EQ(s.positions.size(), 129u * 65u);
  ASSERT_EQ(s.uvs.size(), s.positions.size());
  const glm::vec3 c(0, 1, 0);
  for (size_t v = 0; v < s.positions.size(); ++v) {
    EXPECT_NEAR(glm::length(s.positions[v] - c), 1.0f, 1e-5f);
    EXPECT_GE(s.uvs[v].x, 0.0f);
    EXPECT_LE(s.uvs[v].x, 1.0f);
    EXPECT_GE(s.uvs[v].y, 0.0f);
    EXPECT_LE(s.uvs[v].y, 1.0f);
  }
  expect_outward(s, c);
  // No zero-area triangles are generated at the poles.
  for (size_t t = 0; t < s.indices.size(); ++t) EXPECT_GT(glm::length(face_normal(s, t)), 0.0f);
}

TEST_F(FullSceneGeometry, QuadHasTwoTrianglesAndCornerUvs) {
  const aw::TriangleMesh& q = scene_->meshes[3];  // corner (-5,0,-5), edges 10 x, 10 z
  ASSERT_EQ(q.indices.size(), 2u);
  ASSERT_EQ(q.positions.size(), 4u);
  ASSERT_EQ(q.uvs.size(), 4u);
  // normal = normalize(edge_u x edge_v) = normalize((10,0,0) x (0,0,10)) = (0,-1,0)
  expect_flat(q, glm::vec3(0, -1, 0));
  for (size_t v = 0; v < 4; ++v) {
    // UV (0,0) at the corner, u along edge_u (x), v along edge_v (z).
    EXPECT_FLOAT_EQ(q.positions[v].x, -5.0f + 10.0f * q.uvs[v].x);
    EXPECT_FLOAT_EQ(q.positions[v].z, -5.0f + 10.0f * q.uvs[v].y);
    EXPECT_FLOAT_EQ(q.positions[v].y, 0.0f);
  }
  EXPECT_EQ(q.uvs[0], glm::vec2(0, 0));
  EXPECT_EQ(q.positions[0], glm::vec3(-5, 0, -5));
}

TEST_F(FullSceneGeometry, DiskIsAFanFacingItsNormal) {
  const aw::TriangleMesh& d = scene_->meshes[4];  // center (0,2,0), normal +z, radius 0.5
  EXPECT_EQ(d.indices.size(), 128u);
  EXPECT_EQ(d.positions.size(), 129u);
  expect_flat(d, glm::vec3(0, 0, 1));
  for (size_t v = 1; v < d.positions.size(); ++v) {
    EXPECT_NEAR(glm::length(d.positions[v] - glm::vec3(0, 2, 0)), 0.5f, 1e-6f);
    EXPECT_NEAR(d.positions[v].z, 0.0f, 1e-6f);
  }
}

TEST_F(FullSceneGeometry, BoxHasFlatOutwardFaces) {
  const aw::TriangleMesh& b = scene_->meshes[5];  // min (-1,0,-1), max (1,2,1)
  EXPECT_EQ(b.indices.size(), 12u);
  EXPECT_EQ(b.positions.size(), 24u);
  EXPECT_EQ(b.uvs.size(), 24u);
  expect_outward(b, glm::vec3(0, 1, 0));
  // Flat: the three vertex normals of each triangle equal its winding normal.
  for (size_t t = 0; t < b.indices.size(); ++t) {
    const glm::vec3 f = glm::normalize(face_normal(b, t));
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 n = b.normals[b.indices[t][k]];
      EXPECT_NEAR(glm::dot(f, n), 1.0f, 1e-6f);
    }
  }
  const aw_test::Bounds bb = bounds_of(b);
  EXPECT_EQ(bb.lo, glm::vec3(-1, 0, -1));
  EXPECT_EQ(bb.hi, glm::vec3(1, 2, 1));
}

TEST_F(FullSceneGeometry, TranslatedRotatedScaledBoxBounds) {
  // [0,1]x[0,2]x[0,3], scale 2 -> [0,2]x[0,4]x[0,6]; rotate 90 deg about Y maps
  // (x, y, z) -> (z, y, -x) -> [0,6]x[0,4]x[-2,0]; translate (10,20,30).
  const aw::TriangleMesh& b = scene_->meshes[6];
  const aw_test::Bounds bb = bounds_of(b);
  EXPECT_FLOAT_EQ(bb.lo.x, 10);
  EXPECT_FLOAT_EQ(bb.hi.x, 16);
  EXPECT_FLOAT_EQ(bb.lo.y, 20);
  EXPECT_FLOAT_EQ(bb.hi.y, 24);
  EXPECT_FLOAT_EQ(bb.lo.z, 28);
  EXPECT_FLOAT_EQ(bb.hi.z, 30);
  expect_outward(b, glm::vec3(13, 22, 29));
}

TEST_F(FullSceneGeometry, MatrixTransformIsRowMajor) {
  // Row-major [2 0 0 1; 0 3 0 2; 0 0 4 3; 0 0 0 1] on the unit box: scale (2,3,4) then
  // translate (1,2,3).
  const aw::TriangleMesh& b = scene_->meshes[7];
  const aw_test::Bounds bb = bounds_of(b);
  EXPECT_EQ(bb.lo, glm::vec3(1, 2, 3));
  EXPECT_EQ(bb.hi, glm::vec3(3, 5, 7));
  expect_outward(b, glm::vec3(2, 3.5f, 5));
}

TEST_F(FullSceneGeometry, TranslatedObjMesh) {
  const aw::TriangleMesh& m = scene_->meshes[1];  // two_tris_plain.obj, translate x+10
  const aw_test::Bounds bb = bounds_of(m);
  EXPECT_EQ(bb.lo, glm::vec3(10, 0, 0));
  EXPECT_EQ(bb.hi, glm::vec3(12, 0, 2));
}

TEST(ObjMeshes, NormalsUvsAndDeindexing) {
  const aw::Scene s = aw::load_scene(data_path("good_obj.json"));
  ASSERT_EQ(s.meshes.size(), 3u);

  // One 4-vertex polygon with v/vt/vn: triangulated, 4 unique vertices.
  const aw::TriangleMesh& q = s.meshes[0];
  ASSERT_EQ(q.indices.size(), 2u);
  ASSERT_EQ(q.positions.size(), 4u);
  ASSERT_EQ(q.normals.size(), 4u);
  ASSERT_EQ(q.uvs.size(), 4u);
  // tinyobjloader picks the split diagonal itself; whichever it picks, the two triangles
  // must cover the unit quad with the file's counter-clockwise (+z) winding.
  float area = 0;
  for (size_t t = 0; t < 2; ++t) {
    const glm::vec3 f = face_normal(q, t);
    EXPECT_GT(f.z, 0.0f);
    area += 0.5f * glm::length(f);
  }
  EXPECT_FLOAT_EQ(area, 1.0f);
  for (size_t v = 0; v < 4; ++v) {
    // In this file each vertex's UV equals its xy position.
    EXPECT_EQ(q.uvs[v], glm::vec2(q.positions[v].x, q.positions[v].y));
    EXPECT_EQ(q.normals[v], glm::vec3(0, 0, 1));
  }
  // De-indexing keeps the order of first use: the face starts with OBJ vertex 1.
  EXPECT_EQ(q.positions[0], glm::vec3(0, 0, 0));
  EXPECT_EQ(q.positions[1], glm::vec3(1, 0, 0));

  // Positions only: normals and UVs stay empty (the renderer uses geometric normals).
  const aw::TriangleMesh& p = s.meshes[1];
  EXPECT_EQ(p.indices.size(), 2u);
  EXPECT_EQ(p.positions.size(), 4u);
  EXPECT_TRUE(p.normals.empty());
  EXPECT_TRUE(p.uvs.empty());
  EXPECT_EQ(p.indices[0], glm::uvec3(0, 1, 2));  // f 1 3 2 -> first-use order 0 1 2
  EXPECT_EQ(p.positions[1], glm::vec3(2, 0, 2));

  // Shared positions with different normals become distinct vertices; the mirroring
  // transform (z -> -z) flips the normals and the winding so they still agree.
  const aw::TriangleMesh& n = s.meshes[2];
  ASSERT_EQ(n.positions.size(), 6u);
  ASSERT_EQ(n.normals.size(), 6u);
  EXPECT_TRUE(n.uvs.empty());
  for (size_t v = 0; v < 3; ++v) EXPECT_EQ(n.normals[v], glm::vec3(0, 0, -1));
  for (size_t v = 3; v < 6; ++v) EXPECT_EQ(n.normals[v], glm::vec3(0, 0, 1));
  for (size_t t = 0; t < n.indices.size(); ++t) {
    const glm::vec3 f = glm::normalize(face_normal(n, t));
    EXPECT_NEAR(glm::dot(f, n.normals[n.indices[t].x]), 1.0f, 1e-6f) << "triangle " << t;
  }
}

TEST(ObjMeshes, ZeroLengthNormalsAreDroppedWithAWarning) {
  const aw::Scene s =
      aw::load_scene(data_path("good_obj.json"), {"objects[1].file=meshes/zero_normal.obj"});
  const aw::TriangleMesh& m = s.meshes[1];
  EXPECT_EQ(m.indices.size(), 1u);
  EXPECT_TRUE(m.normals.empty());
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("ignoring the file's normals"), std::string::npos) << s.warnings[0];
}

TEST(Transforms, MirroringKeepsWindingAndNormalsOutward) {
  // A box under a transform with negative determinant (mirror in x plus rotation).
  const aw::Scene s =
      aw::load_scene(data_path("good_full.json"),
                     {R"(objects[5].transform={"scale": [-1, 1, 1], "rotate": [30, 40, 50]})"});
  const aw::TriangleMesh& b = s.meshes[5];
  const aw_test::Bounds bb = bounds_of(b);
  expect_outward(b, (bb.lo + bb.hi) * 0.5f);
}

TEST(Transforms, NonUniformScaleUsesInverseTransposeForNormals) {
  // Unit sphere scaled by (2,1,1): an ellipsoid x^2/4 + y^2 + z^2 = 1, whose normal is the
  // gradient direction (x/4, y, z) -- not the scaled normal (2x, y, z).
  const aw::Scene s = aw::load_scene(data_path("good_small.json"),
                                     {R"(objects[0].transform={"scale": [2, 1, 1]})"});
  const aw::TriangleMesh& e = s.meshes[0];
  const aw_test::Bounds bb = bounds_of(e);
  EXPECT_NEAR(bb.hi.x, 2.0f, 1e-5f);
  EXPECT_NEAR(bb.hi.y, 1.0f, 1e-5f);
  for (size_t v = 0; v < e.positions.size(); ++v) {
    const glm::vec3 p = e.positions[v];
    const glm::vec3 expected = glm::normalize(glm::vec3(p.x / 4.0f, p.y, p.z));
    EXPECT_NEAR(glm::dot(e.normals[v], expected), 1.0f, 1e-5f) << "vertex " << v;
  }
  expect_outward(e, glm::vec3(0));
}

TEST(Transforms, RotationOrderIsXThenYThenZ) {
  // rotate [90, 90, 0], X applied first. The box
  // [0,1]x[0,2]x[0,3]: Rx(90): (x,y,z) -> (x,-z,y) = [0,1]x[-3,0]x[0,2];
  // then Ry(90): (x,y,z) -> (z,y,-x) = [0,2]x[-3,0]x[-1,0].
  // (Y before X would give [0,3]x[0,1]x[0,2].)
  const aw::Scene s = aw::load_scene(data_path("good_full.json"),
                                     {R"(objects[6].transform={"rotate": [90, 90, 0]})"});
  const aw_test::Bounds bb = bounds_of(s.meshes[6]);
  EXPECT_EQ(bb.lo, glm::vec3(0, -3, -1));
  EXPECT_EQ(bb.hi, glm::vec3(2, 0, 0));
}

}  // namespace
