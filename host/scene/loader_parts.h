// The scene loader's internal pieces, split by topic (materials, geometry, overrides).
// Private to host/scene.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "host/scene/loader_context.h"
#include "host/scene/material_desc.h"
#include "host/scene/scene.h"

namespace aw {
namespace scene_detail {

// ---- materials (material_parse.cpp) --------------------------------------------------------
// Parses one entry of "materials" (docs/material.md §1). Out-of-range values are clamped with one
// warning per key; unknown keys and wrong types are errors.
MaterialDesc parse_material(LoadContext& ctx, const Node& n, const std::string& name);

// ---- -D overrides (overrides.cpp) ----------------------------------------------------------
// Applies each "dotted.path=value" to `root` (creating intermediate objects, and arrays when
// the segment has an index) and marks the touched paths in `ctx` so that messages about them
// say "command line -D ...". A malformed entry is a SceneError.
void apply_overrides(LoadContext& ctx, Json& root, const std::vector<std::string>& overrides);

// ---- geometry (geometry.cpp) ---------------------------------------------------------------
// Object-space meshes are built in double precision and converted to float once, after the
// transform, so that a large translation does not round the shape twice.
struct DMesh {
  std::vector<glm::dvec3> positions;
  std::vector<glm::dvec3> normals;  // empty or one per position
  std::vector<glm::dvec2> uvs;      // empty or one per position
  std::vector<glm::dvec2> uvs2;     // the second UV set (glTF TEXCOORD_1): empty or one per position
  // Empty or one per position: analytic tangent along increasing u (unit, orthogonal to the
  // normal) and handedness w = ±1, as TriangleMesh::tangents.
  std::vector<glm::dvec4> tangents;
  std::vector<glm::uvec3> indices;
};

// Right-handed orthonormal basis (t, b, n) with t x b = n for a unit n (Duff et al. 2017,
// "Building an Orthonormal Basis, Revisited", JCGT 6(1), Listing 3); deterministic, and the
// same formula as the kernels' make_frame (kernels/common/sampling.h), in double.
void orthonormal_basis(const glm::dvec3& n, glm::dvec3* t, glm::dvec3* b);

// Built-in shapes' default tessellation, and the triangle counts make_sphere / make_disk
// produce (the loader's memory estimate reads them before tessellating).
constexpr int kSphereSegmentsU = 128, kSphereSegmentsV = 64, kDiskSegments = 128;
constexpr uint64_t sphere_triangle_count(int64_t segments_u, int64_t segments_v) {
  return uint64_t(segments_u) * uint64_t(2 * segments_v - 2);  // no triangle at the two pole rows' tips
}
constexpr uint64_t disk_triangle_count(int64_t segments) { return uint64_t(segments); }
DMesh make_sphere(const glm::dvec3& center, double radius, int segments_u, int segments_v);
DMesh make_quad(const glm::dvec3& corner, const glm::dvec3& edge_u, const glm::dvec3& edge_v);
DMesh make_disk(const glm::dvec3& center, const glm::dvec3& normal, double radius, int segments);
DMesh make_box(const glm::dvec3& min, const glm::dvec3& max);

// Rotation in degrees about X, then Y, then Z. Multiples of 90 degrees are exact, so an
// axis-aligned box stays exactly axis-aligned.
glm::dmat4 rotation_xyz_degrees(const glm::dvec3& degrees);
// |det| of the linear part is negligible relative to its size (or not finite).
bool is_singular(const glm::dmat4& m);

// Applies an affine `transform` (positions by M, normals by the inverse transpose,
// renormalised; tangents by M, renormalised, their handedness negated by a mirroring
// transform; winding flipped for mirroring transforms so the geometric normal still agrees
// with the shading normals) and converts to float. Returns false if a position, normal or
// tangent is not finite afterwards.
bool finalize_mesh(const DMesh& in, const glm::dmat4& transform, TriangleMesh* out);

// A copy of `part` (a prototype's, in its own space) carried to world space by `transform`,
// as finalize_mesh carries a mesh it loads; material and light sampling kept.
TriangleMesh place_mesh(const TriangleMesh& part, const glm::dmat4& transform);

// Reads an OBJ file (tinyobjloader, triangulated) into `out`, de-indexing the separate
// position/normal/uv indices into unique vertex tuples in order of first use. Returns false
// with a message (without the path) on any failure. Warnings are appended to `warnings`.
bool load_obj(const std::string& resolved_path, DMesh* out, std::string* error,
              std::vector<std::string>* warnings);

}  // namespace scene_detail
}  // namespace aw
