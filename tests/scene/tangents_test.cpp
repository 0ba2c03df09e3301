// Tangent frames for anisotropy.orientation = "tangent": generated per vertex for meshes
// (host/scene/tangents.h), analytic for the built-in shapes (geometry.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

#include "host/scene/tangents.h"
#include "kernels/common/compat.h"
#include "kernels/common/sampling.h"
#include "tests/scene/scene_test_util.h"

using aw_test::data_path;

namespace {

// A flat (k+1) x (k+1) grid over [0,1]^2 in the z = 0 plane, counter-clockwise seen from +z,
// with uv = uv_of(x, y). Normals (0, 0, 1) unless `with_normals` is false.
aw::TriangleMesh grid(int k, const std::function<glm::vec2(float, float)>& uv_of, bool with_normals = true) {
  aw::TriangleMesh m;
  for (int j = 0; j <= k; ++j) {
    for (int i = 0; i <= k; ++i) {
      const float x = float(i) / k, y = float(j) / k;
      m.positions.emplace_back(x, y, 0.0f);
      if (with_normals) m.normals.emplace_back(0.0f, 0.0f, 1.0f);
      m.uvs.push_back(uv_of(x, y));
    }
  }
  auto idx = [k](int i, int j) { return uint32_t(j * (k + 1) + i); };
  for (int j = 0; j < k; ++j) {
    for (int i = 0; i < k; ++i) {
      m.indices.emplace_back(idx(i, j), idx(i + 1, j), idx(i + 1, j + 1));
      m.indices.emplace_back(idx(i, j), idx(i + 1, j + 1), idx(i, j + 1));
    }
  }
  return m;
}

// Every tangent is finite, unit length, orthogonal to `normal_of(v)`, with w = ±1.
void expect_valid_frames(const std::vector<glm::vec4>& t, const std::function<glm::vec3(size_t)>& normal_of,
                         const std::string& what) {
  for (size_t v = 0; v < t.size(); ++v) {
    const glm::vec3 d(t[v]);
    ASSERT_TRUE(std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z) && std::isfinite(t[v].w))
        << what << " vertex " << v;
    EXPECT_NEAR(glm::length(d), 1.0f, 1e-5f) << what << " vertex " << v;
    EXPECT_NEAR(glm::dot(d, normal_of(v)), 0.0f, 1e-5f) << what << " vertex " << v;
    EXPECT_TRUE(t[v].w == 1.0f || t[v].w == -1.0f) << what << " vertex " << v << " w " << t[v].w;
  }
}

void expect_all_near(const std::vector<glm::vec4>& t, const glm::vec4& expected, const std::string& what) {
  for (size_t v = 0; v < t.size(); ++v) {
    EXPECT_NEAR(t[v].x, expected.x, 1e-6f) << what << " vertex " << v;
    EXPECT_NEAR(t[v].y, expected.y, 1e-6f) << what << " vertex " << v;
    EXPECT_NEAR(t[v].z, expected.z, 1e-6f) << what << " vertex " << v;
    EXPECT_EQ(t[v].w, expected.w) << what << " vertex " << v;
  }
}

// Which vertices some triangle uses.
std::vector<bool> referenced(const aw::TriangleMesh& m) {
  std::vector<bool> used(m.positions.size(), false);
  for (const glm::uvec3& t : m.indices) used[t.x] = used[t.y] = used[t.z] = true;
  return used;
}

// The kernels' fallback basis around n (Duff et al. 2017), in float.
glm::vec3 kernel_frame_tangent(glm::vec3 n) {
  float3 t, b;
  make_frame(n, &t, &b);
  return t;
}

TEST(Tangents, FollowUOnAPlaneWithRotatedUvs) {
  // u = y, v = -x: the UV layout turned by 90 degrees, so u increases along +y and the
  // tangent must follow it, not the x axis. n x t = z x y = -x points along dP/dv: w = +1.
  const auto rotated = [](float x, float y) { return glm::vec2(y, -x); };
  for (bool with_normals : {true, false}) {
    const std::vector<glm::vec4> t = aw::generate_vertex_tangents(grid(3, rotated, with_normals));
    ASSERT_EQ(t.size(), 16u);
    expect_all_near(t, glm::vec4(0, 1, 0, 1), with_normals ? "rotated uv" : "rotated uv, no normals");
  }
  // The plain layout (u = x, v = y) gives +x.
  expect_all_near(aw::generate_vertex_tangents(grid(3, [](float x, float y) { return glm::vec2(x, y); })),
                  glm::vec4(1, 0, 0, 1), "plain uv");
  // A mirrored layout (u = y, v = x): n x t = -x but dP/dv = +x, so w = -1.
  expect_all_near(aw::generate_vertex_tangents(grid(3, [](float x, float y) { return glm::vec2(y, x); })),
                  glm::vec4(0, 1, 0, -1), "mirrored uv");
  // Scaled and offset UVs do not change the direction.
  expect_all_near(aw::generate_vertex_tangents(grid(2, [](float x, float y) { return glm::vec2(7 - 3 * x, 0.1f * y); })),
                  glm::vec4(-1, 0, 0, -1), "u against x");
}

TEST(Tangents, MirroredHalvesDoNotCancelOnTheMirrorLine) {
  // u = |x - 0.5|: the left half is a mirror image of the right one, as a symmetric model's
  // UVs often are. On the mirror line the two halves' dP/du are opposite; summed together
  // they would cancel. Each side is summed separately and one wins: never a zero vector.
  const aw::TriangleMesh m = grid(4, [](float x, float y) { return glm::vec2(std::fabs(x - 0.5f), y); });
  const std::vector<glm::vec4> t = aw::generate_vertex_tangents(m);
  expect_valid_frames(t, [](size_t) { return glm::vec3(0, 0, 1); }, "mirrored halves");
  for (size_t v = 0; v < t.size(); ++v) {
    EXPECT_NEAR(std::fabs(t[v].x), 1.0f, 1e-6f) << "vertex " << v << " at x = " << m.positions[v].x;
    // The right half's u increases along +x (n x t = +y = dP/dv: w = +1); the left half's
    // along -x, and there n x t = -y against dP/dv = +y: w = -1.
    if (m.positions[v].x > 0.5f) {
      EXPECT_EQ(t[v], glm::vec4(1, 0, 0, 1)) << "vertex " << v;
    } else if (m.positions[v].x < 0.5f) {
      EXPECT_EQ(t[v], glm::vec4(-1, 0, 0, -1)) << "vertex " << v;
    }
  }
}

TEST(Tangents, OrthogonalToCurvedNormalsAndCloseToTheAnalyticOnes) {
  // A sphere's UV mapping has a known tangent; regenerate it from the UVs alone.
  const aw::Scene s = aw::load_scene(data_path("good_small.json"), {"objects[0].segments=[32, 16]"});
  aw::TriangleMesh sphere = s.meshes[0];
  const std::vector<glm::vec4> analytic = sphere.tangents;
  sphere.tangents.clear();
  const std::vector<glm::vec4> t = aw::generate_vertex_tangents(sphere);
  ASSERT_EQ(t.size(), analytic.size());
  expect_valid_frames(t, [&](size_t v) { return sphere.normals[v]; }, "generated sphere");
  // Each triangle's dP/du is the direction of a chord of a 32-gon, 360/64 degrees off the
  // tangent at either end. A vertex inside the UV square averages the chords on both sides
  // with equal angle weights, which cancels the error. The copies on the seam and at the
  // poles (split vertices: their UVs differ) see one side only and keep half a segment.
  const std::vector<bool> used = referenced(sphere);
  const float half_segment = std::cos(5.625f * 3.14159265f / 180.0f) - 1e-6f;
  float worst_edge = 1.0f, worst_inside = 1.0f;
  for (size_t v = 0; v < t.size(); ++v) {
    if (!used[v]) continue;  // the two seam copies of the poles belong to no triangle
    const float c = glm::dot(glm::vec3(t[v]), glm::vec3(analytic[v]));
    const glm::vec2 uv = sphere.uvs[v];
    float& worst = (uv.x == 0.0f || uv.x == 1.0f || uv.y == 0.0f || uv.y == 1.0f) ? worst_edge : worst_inside;
    worst = std::min(worst, c);
    EXPECT_EQ(t[v].w, analytic[v].w) << "vertex " << v;
  }
  std::printf("generated vs analytic sphere tangents: worst cosine %.7f on the seam and poles, %.7f elsewhere\n",
              double(worst_edge), double(worst_inside));
  EXPECT_GE(worst_edge, half_segment);
  EXPECT_GT(worst_inside, 0.99999f);
}

TEST(Tangents, DegenerateUvsGiveTheNormalsBasis) {
  // Every UV the same: no triangle has a dP/du. The tangent is the orthonormal basis around
  // the normal (the same one the kernels fall back to), never NaN.
  const aw::TriangleMesh flat_uv = grid(2, [](float, float) { return glm::vec2(0.5f, 0.5f); });
  const std::vector<glm::vec4> t = aw::generate_vertex_tangents(flat_uv);
  const glm::vec3 expected = kernel_frame_tangent(glm::vec3(0, 0, 1));
  expect_all_near(t, glm::vec4(expected, 1.0f), "constant uv");
  // UVs along a line (zero UV area, but not a single point) and a tilted normal.
  aw::TriangleMesh line_uv = grid(2, [](float x, float y) { return glm::vec2(x + y, 2 * (x + y)); });
  const glm::vec3 n = glm::normalize(glm::vec3(0.3f, -0.2f, 1.0f));
  for (glm::vec3& vn : line_uv.normals) vn = n;
  expect_all_near(aw::generate_vertex_tangents(line_uv), glm::vec4(kernel_frame_tangent(n), 1.0f), "collinear uv");
  // Deterministic: the same mesh gives bit-identical tangents.
  EXPECT_EQ(aw::generate_vertex_tangents(flat_uv), t);
}

TEST(Tangents, OneDegenerateTriangleDoesNotSpoilItsNeighbours) {
  // Two triangles share an edge; the second one's UVs are collapsed to a point. The shared
  // vertices take the first one's tangent; the second one's own corner falls back.
  aw::TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  m.normals.assign(4, glm::vec3(0, 0, 1));
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0.5f, 0.5f}};  // triangle (0, 2, 3): UVs on the line u = v
  m.indices = {{0, 1, 2}, {0, 2, 3}};
  const std::vector<glm::vec4> t = aw::generate_vertex_tangents(m);
  expect_valid_frames(t, [](size_t) { return glm::vec3(0, 0, 1); }, "half degenerate");
  for (size_t v : {0u, 1u, 2u}) EXPECT_EQ(t[v], glm::vec4(1, 0, 0, 1)) << "vertex " << v;
  EXPECT_NEAR(glm::dot(glm::vec3(t[3]), kernel_frame_tangent(glm::vec3(0, 0, 1))), 1.0f, 1e-6f);
}

TEST(Tangents, MeshWithoutUvsOrNormalsOrAreaIsFinite) {
  // No UVs and no normals: the face normals decide the basis. A zero-area triangle (its
  // three corners on a line) and an unreferenced vertex must not produce NaN either.
  aw::TriangleMesh m;
  m.positions = {{0, 0, 0}, {0, 0, 1}, {0, 1, 0}, {0, 2, 0}, {0, 3, 0}, {5, 5, 5}};
  m.indices = {{0, 1, 2}, {2, 3, 4}};  // the second is degenerate (collinear)
  const std::vector<glm::vec4> t = aw::generate_vertex_tangents(m);
  ASSERT_EQ(t.size(), m.positions.size());
  // The first triangle faces -x (winding (0,0,1) x (0,1,0) = -x).
  const glm::vec3 face(-1, 0, 0);
  for (size_t v : {0u, 1u, 2u}) EXPECT_NEAR(glm::dot(glm::vec3(t[v]), kernel_frame_tangent(face)), 1.0f, 1e-6f);
  for (size_t v = 0; v < t.size(); ++v) {
    const glm::vec3 d(t[v]);
    EXPECT_TRUE(std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z)) << "vertex " << v;
    EXPECT_NEAR(glm::length(d), 1.0f, 1e-6f) << "vertex " << v;
    EXPECT_EQ(t[v].w, 1.0f);
  }
  // The same with UVs present on the degenerate triangle.
  m.uvs = {{0, 0}, {1, 0}, {0, 1}, {0, 2}, {1, 3}, {0, 0}};
  for (const glm::vec4& v : aw::generate_vertex_tangents(m)) {
    EXPECT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z));
    EXPECT_NEAR(glm::length(glm::vec3(v)), 1.0f, 1e-6f);
  }
}

TEST(Tangents, SphereHasAnalyticTangentsAlongIncreasingU) {
  // The sphere's documented mapping: u is the longitude from +X, increasing towards -Z (z =
  // -sin(theta) sin(phi)), i.e. counter-clockwise seen from +Y. dP/du is then parallel to
  // up x (p - center), also at the poles where it is the limit along the vertex's longitude.
  const aw::Scene s = aw::load_scene(data_path("good_small.json"), {"objects[0].center=[1, 2, 3]", "objects[0].segments=[128, 64]"});
  const aw::TriangleMesh& m = s.meshes[0];
  ASSERT_EQ(m.tangents.size(), m.positions.size());
  expect_valid_frames(m.tangents, [&](size_t v) { return m.normals[v]; }, "sphere");
  const glm::vec3 center(1, 2, 3);
  size_t checked = 0;
  for (size_t v = 0; v < m.positions.size(); ++v) {
    const glm::vec3 d = m.positions[v] - center;
    const glm::vec3 along = glm::cross(glm::vec3(0, 1, 0), d);
    if (glm::length(along) < 1e-3f) continue;  // the poles: checked below
    EXPECT_NEAR(glm::dot(glm::vec3(m.tangents[v]), glm::normalize(along)), 1.0f, 1e-5f) << "vertex " << v;
    EXPECT_EQ(m.tangents[v].w, 1.0f);
    ++checked;
  }
  EXPECT_GT(checked, m.positions.size() / 2);
  // Numerically along increasing u: the UV-derivative tangent of each triangle points the
  // same way as its vertices' analytic tangents.
  for (const glm::uvec3& tri : m.indices) {
    const glm::vec3 e1 = m.positions[tri.y] - m.positions[tri.x], e2 = m.positions[tri.z] - m.positions[tri.x];
    const glm::vec2 d1 = m.uvs[tri.y] - m.uvs[tri.x], d2 = m.uvs[tri.z] - m.uvs[tri.x];
    const glm::vec3 dpdu = (d2.y * e1 - d1.y * e2) / (d1.x * d2.y - d2.x * d1.y);
    for (int k = 0; k < 3; ++k) ASSERT_GT(glm::dot(dpdu, glm::vec3(m.tangents[tri[k]])), 0.0f);
  }
  // Poles: each copy has the tangent of its own longitude, orthogonal to the axis.
  for (size_t v = 0; v < m.positions.size(); ++v) {
    if (glm::length(glm::cross(glm::vec3(0, 1, 0), m.positions[v] - center)) >= 1e-3f) continue;
    EXPECT_NEAR(m.tangents[v].y, 0.0f, 1e-6f) << "pole vertex " << v;
    const float phi = 2.0f * 3.14159265f * m.uvs[v].x;
    EXPECT_NEAR(m.tangents[v].x, -std::sin(phi), 1e-5f) << "pole vertex " << v;
    EXPECT_NEAR(m.tangents[v].z, -std::cos(phi), 1e-5f) << "pole vertex " << v;
  }
}

// Every built-in shape: the analytic tangents agree with the ones generated from its UVs
// (direction and handedness), also under a mirroring, shearing transform.
TEST(Tangents, BuiltInShapesAgreeWithGeneratedOnes) {
  for (const char* transform : {"", R"({"scale": [-1, 2, 0.5], "rotate": [30, 40, 50]})"}) {
    std::vector<std::string> overrides;
    if (*transform) {
      for (int i : {2, 3, 4, 5}) overrides.push_back("objects[" + std::to_string(i) + "].transform=" + transform);
    }
    const aw::Scene s = aw::load_scene(data_path("good_full.json"), overrides);
    for (size_t i : {2u, 3u, 4u, 5u}) {  // sphere, quad, disk, box
      aw::TriangleMesh m = s.meshes[i];
      ASSERT_EQ(m.tangents.size(), m.positions.size()) << m.name;
      expect_valid_frames(m.tangents, [&](size_t v) { return m.normals[v]; }, m.name + " " + transform);
      const std::vector<glm::vec4> analytic = m.tangents;
      m.tangents.clear();
      const std::vector<glm::vec4> generated = aw::generate_vertex_tangents(m);
      const std::vector<bool> used = referenced(m);
      size_t far = 0, flipped = 0;
      for (size_t v = 0; v < analytic.size(); ++v) {
        if (!used[v]) continue;  // no triangle: the generator can only fall back
        if (glm::dot(glm::vec3(generated[v]), glm::vec3(analytic[v])) < 0.99f) ++far;
        if (generated[v].w != analytic[v].w) ++flipped;
      }
      EXPECT_EQ(far, 0u) << m.name << " " << transform;
      EXPECT_EQ(flipped, 0u) << m.name << " " << transform;
      // A mirroring transform flips the handedness of every tangent.
      for (const glm::vec4& t : analytic) ASSERT_EQ(t.w, *transform ? -1.0f : 1.0f) << m.name;
    }
  }
}

TEST(Tangents, GeneratedOnlyWhereAMaterialReadsThem) {
  const aw::Scene s = aw::load_scene(data_path("good_obj.json"));
  const aw::TriangleMesh& obj = s.meshes[0];  // quad_full.obj: UVs = xy, normals +z
  EXPECT_TRUE(obj.tangents.empty()) << "OBJ meshes carry no tangents of their own";
  aw::MaterialDesc mat;
  EXPECT_TRUE(aw::tangents_for_material(obj, mat).empty()) << "isotropic: nothing reads them";
  mat.anisotropy.amount = 0.5f;
  mat.anisotropy.orientation = aw::AnisoOrientation::Uv;
  EXPECT_TRUE(aw::tangents_for_material(obj, mat).empty()) << "uv orientation: the kernels use dP/du";
  mat.anisotropy.orientation = aw::AnisoOrientation::Tangent;
  expect_all_near(aw::tangents_for_material(obj, mat), glm::vec4(1, 0, 0, 1), "quad_full.obj");
  // Built-in shapes always bring their own.
  const aw::Scene full = aw::load_scene(data_path("good_full.json"));
  EXPECT_EQ(aw::tangents_for_material(full.meshes[3], aw::MaterialDesc()), full.meshes[3].tangents);
}

}  // namespace
