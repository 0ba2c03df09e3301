// Per-vertex tangents for anisotropy.orientation = "tangent" (docs/material.md, "Anisotropy
// frames"). Built-in shapes get analytic tangents from the loader (geometry.cpp); OBJ files
// have none, so they are generated here from the UV parametrisation.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "host/scene/material_desc.h"
#include "host/scene/scene.h"

namespace aw {

// One tangent per vertex of `mesh`, in the form of TriangleMesh::tangents: xyz a unit vector
// orthogonal to the vertex normal, along increasing u; w = ±1 the handedness.
//
// Each triangle's dP/du (and dP/dv for the handedness) is solved from its UVs (Lengyel 2001,
// "Computing Tangent Space Basis Vectors for an Arbitrary Mesh"), projected into the tangent
// plane of each corner's normal and normalised, and accumulated onto the corner's vertex
// weighted by the triangle's angle at that corner, as MikkTSpace does (Mikkelsen 2008,
// "Simulation of Wrinkled Surfaces Revisited", MSc thesis, Univ. of Copenhagen): angle
// weights do not depend on how a surface is split into triangles (Thürmer & Wüthrich 1998,
// "Computing Vertex Normals from Polygonal Facets", the same argument for normals). The sum
// is then Gram-Schmidt orthogonalised against the vertex normal (Lengyel 2001).
//
// The corner normal is the vertex normal; for a mesh without normals, the angle-weighted
// average of the face normals around the vertex (the renderer shades such a mesh with face
// normals; the kernels project the tangent onto those again).
//
// Triangles of opposite handedness meeting at a vertex (a mirrored UV layout) are summed
// separately, and the side with the larger total angle wins: summing them together would
// cancel the tangents along the mirror line.
//
// Never NaN, always deterministic: a vertex whose triangles give no usable dP/du (no UVs,
// zero-area UV triangles, tangents that cancel) gets the tangent of the orthonormal basis
// around its normal (the same Duff et al. 2017 basis the kernels fall back to), w = +1.
std::vector<glm::vec4> generate_vertex_tangents(const TriangleMesh& mesh);

// The tangents to upload for `mesh` drawn with `material`: the mesh's own (analytic) ones,
// else generated ones when the material reads them (anisotropy with orientation "tangent"),
// else none (empty), so scenes without anisotropy do not pay for the generation.
std::vector<glm::vec4> tangents_for_material(const TriangleMesh& mesh, const MaterialDesc& material);

}  // namespace aw
