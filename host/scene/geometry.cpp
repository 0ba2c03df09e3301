// Built-in shapes, transforms and the float conversion of object geometry.
#include <cmath>
#include <utility>

#include "host/scene/loader_parts.h"

namespace aw {
namespace scene_detail {
namespace {

constexpr double kPi = M_PI;

// cos/sin of an angle in degrees, exact for multiples of 90 degrees. cos(pi/2) in floating
// point is 6e-17, not 0; exactness keeps rotated boxes axis-aligned and their bounds exact.
void cos_sin_degrees(double degrees, double* c, double* s) {
  double r = std::fmod(degrees, 360.0);
  if (r < 0) r += 360.0;
  if (r == 0.0) {
    *c = 1;
    *s = 0;
  } else if (r == 90.0) {
    *c = 0;
    *s = 1;
  } else if (r == 180.0) {
    *c = -1;
    *s = 0;
  } else if (r == 270.0) {
    *c = 0;
    *s = -1;
  } else {
    const double rad = degrees * (kPi / 180.0);
    *c = std::cos(rad);
    *s = std::sin(rad);
  }
}

// glm matrices are column-major; this takes the rows as written on paper.
glm::dmat4 from_rows(const double r[3][3]) {
  glm::dmat4 m(1.0);
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) m[col][row] = r[row][col];
  }
  return m;
}

void add_quad_indices(DMesh* m, uint32_t base) {
  m->indices.emplace_back(base + 0, base + 1, base + 2);
  m->indices.emplace_back(base + 0, base + 2, base + 3);
}

}  // namespace

void orthonormal_basis(const glm::dvec3& n, glm::dvec3* t, glm::dvec3* b) {
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z);
  const double bb = n.x * n.y * a;
  *t = glm::dvec3(1.0 + sign * n.x * n.x * a, sign * bb, -sign * n.x);
  *b = glm::dvec3(bb, sign + n.y * n.y * a, -n.y);
}

DMesh make_sphere(const glm::dvec3& center, double radius, int segments_u, int segments_v) {
  // UV sphere: u = longitude from +X (0..1 once around Y), v = 0 at the -Y pole to 1 at +Y.
  // Vertices on the seam and at the poles are duplicated so every vertex has one UV.
  // Tangent: dP/du / |dP/du| = (-sin(phi), 0, -cos(phi)), along the parallel of latitude in
  // the direction of increasing u; its limit is used at the poles, where dP/du itself
  // vanishes, so every pole copy gets the direction of its own longitude. Handedness +1:
  // (n x dP/du) is dP/dv's direction (the winding comment below).
  DMesh m;
  const int su = segments_u, sv = segments_v;
  for (int j = 0; j <= sv; ++j) {
    const double v = static_cast<double>(j) / sv;
    double sin_t = std::sin(kPi * v), cos_t = std::cos(kPi * v);
    if (j == 0 || j == sv) sin_t = 0.0;  // exact poles
    for (int i = 0; i <= su; ++i) {
      const double u = static_cast<double>(i) / su;
      // The seam column (i == su) uses the angle of i == 0 so both copies coincide exactly.
      const double phi = 2.0 * kPi * static_cast<double>(i % su) / su;
      // z = -sin(theta) sin(phi) makes (dP/du x dP/dv) point outwards for the index order
      // below (counter-clockwise seen from outside).
      const glm::dvec3 dir(sin_t * std::cos(phi), -cos_t, -sin_t * std::sin(phi));
      m.positions.push_back(center + radius * dir);
      m.normals.push_back(dir);
      m.uvs.emplace_back(u, v);
      m.tangents.emplace_back(-std::sin(phi), 0.0, -std::cos(phi), 1.0);
    }
  }
  const auto idx = [su](int i, int j) { return static_cast<uint32_t>(j * (su + 1) + i); };
  for (int j = 0; j < sv; ++j) {
    for (int i = 0; i < su; ++i) {
      const uint32_t a = idx(i, j), b = idx(i + 1, j), c = idx(i + 1, j + 1), d = idx(i, j + 1);
      // At the poles one triangle of each quad has two coincident corners; leave it out.
      if (j != 0) m.indices.emplace_back(a, b, c);
      if (j != sv - 1) m.indices.emplace_back(a, c, d);
    }
  }
  return m;
}

DMesh make_quad(const glm::dvec3& corner, const glm::dvec3& edge_u, const glm::dvec3& edge_v) {
  DMesh m;
  const glm::dvec3 n = glm::normalize(glm::cross(edge_u, edge_v));
  m.positions = {corner, corner + edge_u, corner + edge_u + edge_v, corner + edge_v};
  m.normals = {n, n, n, n};
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  // u runs along edge_u, which is orthogonal to n = edge_u x edge_v (normalised): handedness +1.
  const glm::dvec4 t(glm::normalize(edge_u), 1.0);
  m.tangents = {t, t, t, t};
  add_quad_indices(&m, 0);
  return m;
}

DMesh make_disk(const glm::dvec3& center, const glm::dvec3& normal, double radius, int segments) {
  DMesh m;
  const glm::dvec3 n = glm::normalize(normal);
  // Right-handed orthonormal basis (t, b, n), t x b = n; deterministic and continuous except at
  // n.z = 0 crossings.
  glm::dvec3 t, b;
  orthonormal_basis(n, &t, &b);
  // Planar UVs over the disk's bounding square: (0.5, 0.5) at the centre, u along t, v along
  // b. For a disk facing +Y that is u along +X and v along -Z, like the top face of a box.
  // So the tangent is t everywhere, handedness +1.
  m.positions.push_back(center);
  m.normals.push_back(n);
  m.uvs.emplace_back(0.5, 0.5);
  m.tangents.emplace_back(t, 1.0);
  for (int k = 0; k < segments; ++k) {
    const double angle = 2.0 * kPi * k / segments;
    const double c = std::cos(angle), s = std::sin(angle);
    m.positions.push_back(center + radius * (c * t + s * b));
    m.normals.push_back(n);
    m.uvs.emplace_back(0.5 + 0.5 * c, 0.5 + 0.5 * s);
    m.tangents.emplace_back(t, 1.0);
  }
  for (int k = 0; k < segments; ++k) {
    // Counter-clockwise around n because t x b = n.
    m.indices.emplace_back(0u, static_cast<uint32_t>(1 + k),
                           static_cast<uint32_t>(1 + (k + 1) % segments));
  }
  return m;
}

DMesh make_box(const glm::dvec3& min, const glm::dvec3& max) {
  // Per face: the axis of its outward normal and its sign, then the u and v directions
  // (axis, sign) chosen so that u x v is the outward normal and, seen from outside with +Y
  // up (or -Z up for the top and bottom), u runs to the right and v upwards.
  struct Face {
    int axis, sign, u_axis, u_sign, v_axis, v_sign;
  };
  static const Face kFaces[6] = {
      {0, -1, 2, +1, 1, +1},  // -X
      {0, +1, 2, -1, 1, +1},  // +X
      {1, -1, 0, +1, 2, +1},  // -Y
      {1, +1, 0, +1, 2, -1},  // +Y
      {2, -1, 0, -1, 1, +1},  // -Z
      {2, +1, 0, +1, 1, +1},  // +Z
  };
  DMesh m;
  for (const Face& f : kFaces) {
    const uint32_t base = static_cast<uint32_t>(m.positions.size());
    glm::dvec3 n(0.0);
    n[f.axis] = f.sign;
    glm::dvec4 tangent(0.0, 0.0, 0.0, 1.0);  // the face's u direction; u x v = n: handedness +1
    tangent[f.u_axis] = f.u_sign;
    // Corners are picked from min/max per axis (never computed as centre +- half extent) so
    // that the box's vertices are exactly its bounds.
    const int uv_corners[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (const auto& c : uv_corners) {
      glm::dvec3 p;
      p[f.axis] = f.sign > 0 ? max[f.axis] : min[f.axis];
      p[f.u_axis] = ((f.u_sign > 0) == (c[0] == 1)) ? max[f.u_axis] : min[f.u_axis];
      p[f.v_axis] = ((f.v_sign > 0) == (c[1] == 1)) ? max[f.v_axis] : min[f.v_axis];
      m.positions.push_back(p);
      m.normals.push_back(n);
      m.uvs.emplace_back(c[0], c[1]);
      m.tangents.push_back(tangent);
    }
    add_quad_indices(&m, base);
  }
  return m;
}

glm::dmat4 rotation_xyz_degrees(const glm::dvec3& degrees) {
  double cx, sx, cy, sy, cz, sz;
  cos_sin_degrees(degrees.x, &cx, &sx);
  cos_sin_degrees(degrees.y, &cy, &sy);
  cos_sin_degrees(degrees.z, &cz, &sz);
  const double rx[3][3] = {{1, 0, 0}, {0, cx, -sx}, {0, sx, cx}};
  const double ry[3][3] = {{cy, 0, sy}, {0, 1, 0}, {-sy, 0, cy}};
  const double rz[3][3] = {{cz, -sz, 0}, {sz, cz, 0}, {0, 0, 1}};
  // X is applied first: p' = Rz * Ry * Rx * p.
  return from_rows(rz) * from_rows(ry) * from_rows(rx);
}

bool is_singular(const glm::dmat4& m) {
  const glm::dmat3 l(m);
  const double det = glm::determinant(l);
  double norm2 = 0.0;
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) norm2 += l[c][r] * l[c][r];
  }
  const double norm = std::sqrt(norm2);
  if (!std::isfinite(det) || !std::isfinite(norm)) return true;
  // Relative test: a uniform scale of 1e-4 (det 1e-12) is fine; rank deficiency leaves only
  // rounding noise, many orders of magnitude below norm^3.
  return std::fabs(det) <= 1e-12 * norm * norm * norm;
}

bool finalize_mesh(const DMesh& in, const glm::dmat4& transform, TriangleMesh* out) {
  const glm::dmat3 linear(transform);
  // Normals transform by the inverse transpose; positions by the matrix itself.
  const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(linear));
  const bool mirrored = glm::determinant(linear) < 0.0;

  out->positions.clear();
  out->normals.clear();
  out->uvs.clear();
  out->indices.clear();
  out->positions.reserve(in.positions.size());
  for (const glm::dvec3& p : in.positions) {
    const glm::dvec3 q = glm::dvec3(transform * glm::dvec4(p, 1.0));
    const glm::vec3 f(q);
    if (!std::isfinite(f.x) || !std::isfinite(f.y) || !std::isfinite(f.z)) return false;
    out->positions.push_back(f);
  }
  out->normals.reserve(in.normals.size());
  for (const glm::dvec3& n : in.normals) {
    glm::dvec3 q = normal_matrix * n;
    const double len = glm::length(q);
    if (len > 0.0) q /= len;
    const glm::vec3 f(q);
    if (!std::isfinite(f.x) || !std::isfinite(f.y) || !std::isfinite(f.z)) return false;
    out->normals.push_back(f);
  }
  out->uvs.reserve(in.uvs.size());
  for (const glm::dvec2& uv : in.uvs) out->uvs.emplace_back(uv);
  out->uvs2.clear();
  out->uvs2.reserve(in.uvs2.size());
  for (const glm::dvec2& uv : in.uvs2) out->uvs2.emplace_back(uv);
  // Tangents are tangent vectors (dP/du), so they transform like positions' differences, by
  // M itself; that keeps them orthogonal to the inverse-transpose normals, (M t)·(M^-T n) =
  // t·n = 0 (up to rounding, removed by one Gram-Schmidt step). The handedness compares
  // n x t with dP/dv; M maps t x b to det(M) M^-T (t x b), so a mirror flips it.
  out->tangents.clear();
  out->tangents.reserve(in.tangents.size());
  for (size_t i = 0; i < in.tangents.size(); ++i) {
    glm::dvec3 t = linear * glm::dvec3(in.tangents[i]);
    if (i < out->normals.size()) {
      const glm::dvec3 n(out->normals[i]);
      t -= n * glm::dot(n, t);
    }
    const double len = glm::length(t);
    if (len > 0.0) t /= len;
    const glm::vec4 f(glm::dvec4(t, mirrored ? -in.tangents[i].w : in.tangents[i].w));
    if (!std::isfinite(f.x) || !std::isfinite(f.y) || !std::isfinite(f.z)) return false;
    out->tangents.push_back(f);
  }
  out->indices = in.indices;
  if (mirrored) {
    // A mirroring transform reverses the winding; swap two corners so that the geometric
    // normal (from the winding) keeps agreeing with the transformed shading normals.
    for (glm::uvec3& t : out->indices) std::swap(t.y, t.z);
  }
  return true;
}

TriangleMesh place_mesh(const TriangleMesh& part, const glm::dmat4& transform) {
  DMesh d;
  for (const glm::vec3& p : part.positions) d.positions.emplace_back(p);
  for (const glm::vec3& n : part.normals) d.normals.emplace_back(n);
  for (const glm::vec2& uv : part.uvs) d.uvs.emplace_back(uv);
  for (const glm::vec2& uv : part.uvs2) d.uvs2.emplace_back(uv);
  for (const glm::vec4& t : part.tangents) d.tangents.emplace_back(t);
  d.indices = part.indices;
  TriangleMesh t;
  finalize_mesh(d, transform, &t);  // finite: the loader checked the placed bounds
  t.material = part.material;
  t.name = part.name;
  t.light_sampling = part.light_sampling;
  return t;
}

}  // namespace scene_detail
}  // namespace aw
