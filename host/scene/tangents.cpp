// Per-vertex tangent generation (the method and its references are in tangents.h).
#include "host/scene/tangents.h"

#include <array>
#include <cmath>

#include "host/scene/loader_parts.h"

namespace aw {

namespace {

// A UV triangle whose signed area is below this fraction of the products of its edge extents
// is degenerate: with float UVs the determinant is then rounding noise (float's relative
// precision is 6e-8) and so is the direction of dP/du solved with it.
constexpr double kUvDegenerate = 1e-6;

// Angle of triangle corner `p` between the edges to `a` and `b`; 0 for a zero-length edge.
// atan2 of |cross| and dot is accurate at every angle, unlike acos of the normalised dot.
double corner_angle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 ea = a - p, eb = b - p;
  return std::atan2(glm::length(glm::cross(ea, eb)), glm::dot(ea, eb));
}

glm::dvec3 normalised_or_zero(const glm::dvec3& v) {
  const double len = glm::length(v);
  return len > 0.0 && std::isfinite(len) ? v / len : glm::dvec3(0.0);
}

}  // namespace

std::vector<glm::vec4> generate_vertex_tangents(const TriangleMesh& mesh) {
  const size_t nv = mesh.positions.size();
  const bool has_normals = mesh.normals.size() == nv;
  const bool has_uvs = mesh.uvs.size() == nv;
  auto pos = [&](uint32_t i) { return glm::dvec3(mesh.positions[i]); };
  auto valid = [&](const glm::uvec3& t) { return t.x < nv && t.y < nv && t.z < nv; };

  // The normal each vertex's tangent is made orthogonal to: the mesh's own, or the
  // angle-weighted face normals (Thürmer & Wüthrich 1998) where it has none (or a zero one).
  std::vector<glm::dvec3> normal(nv, glm::dvec3(0.0));
  std::vector<glm::dvec3> face_sum(nv, glm::dvec3(0.0));
  for (const glm::uvec3& t : mesh.indices) {
    if (!valid(t)) continue;
    const glm::dvec3 p[3] = {pos(t.x), pos(t.y), pos(t.z)};
    const glm::dvec3 fn = normalised_or_zero(glm::cross(p[1] - p[0], p[2] - p[0]));
    for (int k = 0; k < 3; ++k) face_sum[t[k]] += corner_angle(p[k], p[(k + 1) % 3], p[(k + 2) % 3]) * fn;
  }
  for (size_t v = 0; v < nv; ++v) {
    normal[v] = has_normals ? normalised_or_zero(glm::dvec3(mesh.normals[v])) : glm::dvec3(0.0);
    if (normal[v] == glm::dvec3(0.0)) normal[v] = normalised_or_zero(face_sum[v]);
    if (normal[v] == glm::dvec3(0.0)) normal[v] = glm::dvec3(0.0, 0.0, 1.0);  // isolated or degenerate
  }

  // Angle-weighted sums of the triangles' unit tangents, one per handedness (0: +1, 1: -1).
  std::array<std::vector<glm::dvec3>, 2> sum{std::vector<glm::dvec3>(nv, glm::dvec3(0.0)),
                                             std::vector<glm::dvec3>(nv, glm::dvec3(0.0))};
  std::array<std::vector<double>, 2> weight{std::vector<double>(nv, 0.0), std::vector<double>(nv, 0.0)};
  if (has_uvs) {
    for (const glm::uvec3& t : mesh.indices) {
      if (!valid(t)) continue;
      const glm::dvec3 p[3] = {pos(t.x), pos(t.y), pos(t.z)};
      const glm::dvec2 uv0(mesh.uvs[t.x]), uv1(mesh.uvs[t.y]), uv2(mesh.uvs[t.z]);
      const double du1 = uv1.x - uv0.x, dv1 = uv1.y - uv0.y;
      const double du2 = uv2.x - uv0.x, dv2 = uv2.y - uv0.y;
      const double det = du1 * dv2 - du2 * dv1;
      if (!(std::fabs(det) > kUvDegenerate * (std::fabs(du1 * dv2) + std::fabs(du2 * dv1)))) continue;
      // The edges in terms of the UV differences, e1 = du1 dP/du + dv1 dP/dv and
      // e2 = du2 dP/du + dv2 dP/dv, solved for dP/du and dP/dv (Lengyel 2001).
      const glm::dvec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
      const glm::dvec3 dpdu = (dv2 * e1 - dv1 * e2) / det;
      const glm::dvec3 dpdv = (du1 * e2 - du2 * e1) / det;
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = t[k];
        const double angle = corner_angle(p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
        const glm::dvec3& n = normal[v];
        // Projected into the vertex's tangent plane first (MikkTSpace does the same), so
        // triangles that are tilted against the vertex normal add only their in-plane part.
        const glm::dvec3 tu = normalised_or_zero(dpdu - n * glm::dot(n, dpdu));
        if (!(angle > 0.0) || tu == glm::dvec3(0.0)) continue;
        // Handedness (Lengyel 2001): does n x t point along dP/dv or against it?
        const int side = glm::dot(glm::cross(n, tu), dpdv) < 0.0 ? 1 : 0;
        sum[side][v] += angle * tu;
        weight[side][v] += angle;
      }
    }
  }

  std::vector<glm::vec4> out(nv);
  for (size_t v = 0; v < nv; ++v) {
    const glm::dvec3& n = normal[v];
    const int side = weight[1][v] > weight[0][v] ? 1 : 0;
    // Gram-Schmidt against the vertex normal (Lengyel 2001). A sum much shorter than its
    // weight means the contributions cancelled: its direction is not meaningful.
    glm::dvec3 t = sum[side][v] - n * glm::dot(n, sum[side][v]);
    const double len = glm::length(t);
    if (len > 1e-6 * weight[side][v] && std::isfinite(len)) {
      out[v] = glm::vec4(glm::vec3(t / len), side == 1 ? -1.0f : 1.0f);
    } else {
      glm::dvec3 b;
      scene_detail::orthonormal_basis(n, &t, &b);
      out[v] = glm::vec4(glm::vec3(t), 1.0f);
    }
  }
  return out;
}

std::vector<glm::vec4> tangents_for_material(const TriangleMesh& mesh, const MaterialDesc& material) {
  if (mesh.tangents.size() == mesh.positions.size()) return mesh.tangents;
  if (material.anisotropy.amount == 0.0f || material.anisotropy.orientation != AnisoOrientation::Tangent) return {};
  return generate_vertex_tangents(mesh);
}

}  // namespace aw
