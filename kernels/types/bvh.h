// Flattened BVH as the kernels traverse it (docs/bvh-layout.md describes it in full).
// Shared with the host: plain 4-byte fields only, no float3 (16 bytes on device).
#ifndef AW_TYPES_BVH_H
#define AW_TYPES_BVH_H

// BVH4 node: the boxes of up to four children in structure-of-arrays form, so that one float4
// operation runs a slab of all four box tests, as Embree's BVH4 does with SSE on CPUs (Wald et
// al. 2008, "Getting Rid of Packets: Efficient SIMD Single-Ray Traversal using Multi-branching
// BVHs", Sec. 3; Dammertz et al. 2008, "Shallow Bounding Volume Hierarchies for Fast SIMD Ray
// Tracing of Incoherent Rays"). 8 × float4 = 128 bytes, two cache lines:
//   f4[0] = lo.x of children 0..3     f4[1] = hi.x of children 0..3
//   f4[2] = lo.y                      f4[3] = hi.y
//   f4[4] = lo.z                      f4[5] = hi.z
//   f4[6] = (child0, child1, child2, child3) as int bits
//   f4[7] = 0 (padding to the cache line)
// child >= 0: index of an inner node. child < 0: leaf, ~child = (first << 3) | (count - 1),
// i.e. `count` (1..8) consecutive entries of the leaf triangle array starting at `first`.
// child == AW_BVH_EMPTY: no child in this slot (its box is all zeros and never tested: the
// traversal masks the slot by its id, since an "empty box" cannot be encoded robustly, the slab
// test of an inverted box passing for some directions). Slots are filled from 0; a node has at
// least one child (a one-leaf tree is a root with that leaf in slot 0).
typedef struct {
  float lo_x[4], hi_x[4], lo_y[4], hi_y[4], lo_z[4], hi_z[4];
  int child[4];
  int pad[4];
} BvhNode;

#define AW_BVH_WIDTH 4
#define AW_BVH_EMPTY 2147483647  // INT_MAX: never a node index (there are fewer nodes than triangles)

#define AW_BVH_LEAF_MAX 8
// A node pushes at most three children (the nearest is visited next); the tree is at most
// AW_BVH_MAX_DEPTH deep, so the stack never holds more than 3 per level.
#define AW_BVH_MAX_DEPTH 40
#define AW_BVH_STACK_SIZE (3 * AW_BVH_MAX_DEPTH + 4)

// Leaf triangle, in leaf order: the three vertices as float4 (w of v0 holds the original
// triangle id as uint bits, the id Embree reports as primID, so hits name the same triangle
// on both paths), then the plane intersect_triangle measures t from (triangle_plane in
// bvh/intersect_triangle.h, computed once by the flattener: the normal n, and in w the corner k
// it is taken at as uint bits). 64 bytes. An analytic sphere takes the same slot: v0 =
// (centre, id bits), v1 = (radius, 0, 0, AW_LEAF_SPHERE as uint bits; a triangle's v1.w is 0),
// v2 and plane unused; its id follows the triangles' (kernels/bvh/intersect_sphere.h).
typedef struct {
  float v0[4];
  float v1[4];
  float v2[4];
  float plane[4];
} LeafTriangle;
#define AW_LEAF_FLOAT4S 4  // float4s per LeafTriangle: the traversals read tris[i * 4 + k]
#define AW_LEAF_SPHERE 1u
// An instance (two-level BVH, docs/bvh-layout.md#instances) takes the same slot in the top-level
// tree: v0.w = the instance's index in the instance array (uint bits), v1.w = AW_LEAF_INSTANCE;
// the traversal moves the ray into the instance's object space and descends into the root of its
// prototype's tree (InstanceGpu.root), whose leaves hold the prototype's triangles.
#define AW_LEAF_INSTANCE 2u

// One placement of a shared mesh (a prototype): its transform both ways as row-major 3 x 4
// matrices (rows x, y, z of [linear | translation]) and the root node of the prototype's own
// tree in the node array. Object-space hits carry the same t as in world space (the direction is
// transformed, not normalised). flags: AW_INSTANCE_MIRROR when the transform mirrors (det < 0):
// the winding, and so the geometric normal's side, flips. 112 bytes.
typedef struct {
  float o2w[12];
  float w2o[12];
  uint root;
  uint flags;
  uint prototype;
  uint pad;
} InstanceGpu;
#define AW_INSTANCE_MIRROR 1u

// An analytic sphere's TriangleInfo: v[0] = the vertex that holds its centre and radius
// (p = centre, p[3] = radius; n = its x axis, t = its pole axis y: intersect_sphere.h),
// v[1] = AW_SPHERE_MARK, v[2] = v[0].
#define AW_SPHERE_MARK 0xfffffffeu

// Per original triangle: vertex indices into the shared vertex arrays, and the material.
// (Which triangles are lights is a separate array, sc.tri_light, present only in scenes with
// mesh lights, so that this stays one uint4.)
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
// uv2: the second UV set (glTF TEXCOORD_1), read by texture bindings with uv_set 1 and by
// anisotropy.uv_set 1; a copy of uv for meshes without one.
// 64 bytes: one cache line per vertex.
typedef struct {
  float p[4];
  float n[4];
  float uv[2];
  float uv2[2];
  float t[4];
} VertexData;

#endif
