// Flattened BVH as the kernels traverse it (docs/bvh-layout.md describes it in full).
// Shared with the host: plain 4-byte fields only, no float3 (16 bytes on device).
#ifndef AW_TYPES_BVH_H
#define AW_TYPES_BVH_H

// BVH2 node in the Aila–Laine layout (Aila & Laine 2009, "Understanding the Efficiency of
// Ray Traversal on GPUs", Sec. 3): a node stores the boxes of BOTH children, so one node
// fetch (4 × float4 = 64 bytes) tests two boxes and the traversal never loads a box it
// will not test.
//   f4[0] = (c0.lo.x, c0.hi.x, c0.lo.y, c0.hi.y)
//   f4[1] = (c1.lo.x, c1.hi.x, c1.lo.y, c1.hi.y)
//   f4[2] = (c0.lo.z, c0.hi.z, c1.lo.z, c1.hi.z)
//   f4[3] = (child0, child1, 0, 0) as int bits
// child >= 0: index of an inner node. child < 0: leaf, ~child = (first << 3) | (count - 1),
// i.e. `count` (1..8) consecutive entries of the leaf triangle array starting at `first`.
// A tree that is a single leaf gets a root whose two children are that same leaf (an "empty
// box" cannot be encoded robustly: the slab test of an inverted box passes for some
// directions). Testing a handful of triangles twice costs nothing.
typedef struct {
  float bounds[12];
  int child[2];
  int pad[2];
} BvhNode;

#define AW_BVH_LEAF_MAX 8
#define AW_BVH_STACK_SIZE 64

// Leaf triangle, in leaf order: the three vertices as float4 (w of v0 holds the original
// triangle id as uint bits, the id Embree reports as primID, so hits name the same triangle
// on both paths). 48 bytes.
typedef struct {
  float v0[4];
  float v1[4];
  float v2[4];
} LeafTriangle;

// Per original triangle: vertex indices into the shared vertex arrays, and the material.
typedef struct {
  uint v[3];
  uint material;
} TriangleInfo;

// Per vertex shading data: position (w unused), shading normal (w = 0 if the mesh has no
// normals: use the geometric normal), uv, and the mesh tangent for
// anisotropy.orientation = "tangent": xyz a unit vector along increasing u, orthogonal to the
// vertex normal, w = ±1 its handedness (sign of (n × t)·dP/dv; kept for a bitangent, the
// anisotropic frame itself uses n × t). The tangent is all zero where no material of the
// mesh reads it (host/scene/tangents.h); the kernels then fall back to the UV frame.
// 64 bytes: one cache line per vertex.
typedef struct {
  float p[4];
  float n[4];
  float uv[2];
  float pad[2];
  float t[4];
} VertexData;

#endif
