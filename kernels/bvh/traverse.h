// Stack-based traversal of the flattened BVH4 (kernels/types/bvh.h, docs/bvh-layout.md).
// Compiles as OpenCL C (the intersect kernels) and as C++ (tests compare it to Embree).
#ifndef AW_BVH_TRAVERSE_H
#define AW_BVH_TRAVERSE_H

#include "common/compat.h"
#include "common/lanes.h"
#include "types/bvh.h"
#include "bvh/instance.h"
#include "bvh/intersect_sphere.h"
#include "bvh/intersect_triangle.h"
#include "common/features.h"
#include "texture/material_textures.h"

// A ray's hit, per lane at W > 1 (common/lanes.h).
typedef struct {
  lfloat t;
  lfloat u, v;
  lint prim;  // original triangle id, -1 = no hit
  luint inst; // the instance it belongs to (types/bvh.h, InstanceGpu), AW_NONE for world geometry
} TriangleHit;

// Reciprocal direction with zero components replaced by a huge finite value of the same
// sign, so 0 * inf never produces NaN in the slab test.
AW_FN float safe_rcp(float x) {
  const float big = 1e30f;
  return fabs(x) < 1e-30f ? copysign(big, x) : 1.0f / x;
}

// Component-wise min/max without IEEE NaN handling, for the slab tests below (no NaN can arise
// there: finite reciprocals, finite bounds), as min_nn/max_nn (common/compat.h) for floats.
AW_FN float4 min4_nn(float4 a, float4 b) {
#if AW_DEVICE
  return select(b, a, a < b);
#else
  return glm::min(a, b);
#endif
}
AW_FN float4 max4_nn(float4 a, float4 b) {
#if AW_DEVICE
  return select(b, a, a > b);
#else
  return glm::max(a, b);
#endif
}

#if AW_LANES == 1
// The ray as one traversal level sees it: origin, and for the slab tests the broadcast origin
// and reciprocal direction; for the triangle test the shear (intersect_triangle.h).
typedef struct {
  float3 org, dir;
  float4 ox, oy, oz, ix, iy, iz;
  RayShear shear;
} TraversalRay;

AW_FN TraversalRay traversal_ray_make(float3 org, float3 dir) {
  TraversalRay r;
  r.org = org;
  r.dir = dir;
  float3 inv = make_float3(safe_rcp(dir.x), safe_rcp(dir.y), safe_rcp(dir.z));
  r.shear = ray_shear_make(dir);
  r.ox = make_float4(org.x, org.x, org.x, org.x);
  r.oy = make_float4(org.y, org.y, org.y, org.y);
  r.oz = make_float4(org.z, org.z, org.z, org.z);
  r.ix = make_float4(inv.x, inv.x, inv.x, inv.x);
  r.iy = make_float4(inv.y, inv.y, inv.y, inv.y);
  r.iz = make_float4(inv.z, inv.z, inv.z, inv.z);
  return r;
}

// Closest hit (any_hit = 0) or first hit found (any_hit = 1, for shadow rays) in (t_min, t_max).
// Each node: the four box tests as SIMD slabs, then the children hit are visited nearest
// first (the others pushed farthest first, so the stack pops them in order of entry distance);
// shadow rays take them in slot order.
// The slab test keeps a conservative far distance: Ize 2013, "Robust BVH Ray Traversal",
// JCGT 2(2), Sec. 3: computed as (bound - org) * inv, whose error is relative to t, and t_far
// scaled by 1 + 2 gamma(3), it never rejects a box that the watertight triangle test would
// hit. (The cheaper bound * inv - org * inv form errs relative to |org * inv| and left cracks
// at shared vertices: tests/bvh, heightfield.) Lanes of empty slots are tested too (their
// boxes are zeros) and masked by their child id.
// Cutouts: with `cut` non-null, a triangle hit where the material's cutout opacity is below
// 0.5 is not a hit (texture/material_textures.h, material_opaque_at), so every kind of ray
// passes through the hole and the traversal goes on as if the triangle were not there.
// Instances (a two-level BVH, docs/bvh-layout.md#instances): an instance entry in a top-level
// leaf pushes the rest of its leaf, notes the stack depth, moves the ray into the instance's
// object space (the direction is transformed, not normalised, so t means the same distance
// along the ray in both spaces and hit.t keeps bounding the search) and descends into its
// prototype's tree; when the stack falls back to the noted depth, the world ray is restored.
AW_FN TriangleHit bvh_intersect_cut(const AW_GLOBAL float4* nodes, uint num_nodes,
                                    const AW_GLOBAL float4* tris, const AW_GLOBAL InstanceGpu* insts, float3 org,
                                    float3 dir, float t_min, float t_max, int any_hit, const TextureScene* cut) {
  TriangleHit hit;
  hit.t = t_max;
  hit.u = 0.0f;
  hit.v = 0.0f;
  hit.prim = -1;
  hit.inst = AW_NONE;
  if (num_nodes == 0) return hit;

  TraversalRay r = traversal_ray_make(org, dir);
  const float4 tmin4 = make_float4(t_min, t_min, t_min, t_min);
  uint cur_inst = AW_NONE;  // the instance being traversed
  int inst_sp = -1;         // the stack depth at which it was entered

  int stack[AW_BVH_STACK_SIZE];
  int sp = 0;
  int node = 0;
  for (;;) {
    // Inner nodes: test the four children, descend into the nearest hit, push the others.
    int at_leaf = 1;
    while (node >= 0) {
      const AW_GLOBAL float4* nd = nodes + (uint)node * 8u;
      float4 tx0 = (nd[0] - r.ox) * r.ix, tx1 = (nd[1] - r.ox) * r.ix;
      float4 ty0 = (nd[2] - r.oy) * r.iy, ty1 = (nd[3] - r.oy) * r.iy;
      float4 tz0 = (nd[4] - r.oz) * r.iz, tz1 = (nd[5] - r.oz) * r.iz;
      float4 tmax4 = make_float4(hit.t, hit.t, hit.t, hit.t);
      float4 tn = max4_nn(max4_nn(min4_nn(tx0, tx1), min4_nn(ty0, ty1)), max4_nn(min4_nn(tz0, tz1), tmin4));
      float4 tf = min4_nn(min4_nn(max4_nn(tx0, tx1), max4_nn(ty0, ty1)), min4_nn(max4_nn(tz0, tz1), tmax4));
      tf = tf * 1.00000036f;
      float4 ch = nd[6];
      // The children hit, in slot order, with their entry distances.
      int hn[4];
      float ht[4];
      int k = 0;
      if (tn.x <= tf.x) { hn[k] = as_int(ch.x); ht[k] = tn.x; ++k; }
      if (tn.y <= tf.y && as_int(ch.y) != AW_BVH_EMPTY) { hn[k] = as_int(ch.y); ht[k] = tn.y; ++k; }
      if (tn.z <= tf.z && as_int(ch.z) != AW_BVH_EMPTY) { hn[k] = as_int(ch.z); ht[k] = tn.z; ++k; }
      if (tn.w <= tf.w && as_int(ch.w) != AW_BVH_EMPTY) { hn[k] = as_int(ch.w); ht[k] = tn.w; ++k; }
      if (k == 0) {
        at_leaf = 0;
        break;
      }
      // Sort by entry distance, farthest first (insertion sort of at most four; ties keep
      // slot order reversed, so equal distances are visited in slot order). Not for shadow
      // rays (any_hit): any occluder ends them, whichever is found first; without the sort
      // their stage took 0.91-0.92x the time on both CPU runtimes (docs/performance.md,
      // "Shadow rays without the children's sort").
      for (int i = 1; !any_hit && i < k; ++i) {
        int n_i = hn[i];
        float t_i = ht[i];
        int j = i - 1;
        while (j >= 0 && ht[j] <= t_i) {
          hn[j + 1] = hn[j];
          ht[j + 1] = ht[j];
          --j;
        }
        hn[j + 1] = n_i;
        ht[j + 1] = t_i;
      }
      for (int i = 0; i < k - 1; ++i) stack[sp++] = hn[i];
      node = hn[k - 1];
    }
    // Leaf: ~node = (first << 3) | (count - 1).
    if (at_leaf) {
      int packed = ~node;
      int first = packed >> 3;
      int count = (packed & 7) + 1;
      int entered = 0;
      for (int i = first; i < first + count; ++i) {
        float4 p0 = tris[i * AW_LEAF_FLOAT4S + 0];
        float4 p1 = tris[i * AW_LEAF_FLOAT4S + 1];
        float4 p2 = tris[i * AW_LEAF_FLOAT4S + 2];
        float t, u, v;
        if (AW_FEAT_INSTANCE && as_uint(p1.w) == AW_LEAF_INSTANCE) {
          // The rest of this leaf waits on the stack, below the instance's own entries.
          if (i + 1 < first + count) stack[sp++] = ~(((i + 1) << 3) | (first + count - i - 2));
          inst_sp = sp;
          cur_inst = as_uint(p0.w);
          const AW_GLOBAL InstanceGpu* in = &insts[cur_inst];
          r = traversal_ray_make(xform_point(in->w2o, org), xform_vector(in->w2o, dir));
          node = (int)in->root;
          entered = 1;
          break;
        }
        // An analytic sphere (types/bvh.h): its hit's (u, v) is the sphere's UV.
        if (AW_FEAT_SPHERE && as_uint(p1.w) == AW_LEAF_SPHERE) {
          if (!intersect_sphere(r.org, r.dir, make_float3(p0.x, p0.y, p0.z), p1.x, t_min, hit.t, &t)) continue;
          u = 0.0f;
          v = 0.0f;
          if (cut && !material_opaque_at_sphere(*cut, as_uint(p0.w), r.org + r.dir * t)) continue;
          hit.t = t;
          hit.u = u;
          hit.v = v;
          hit.prim = (int)as_uint(p0.w);
          hit.inst = cur_inst;
          if (any_hit) return hit;
          continue;
        }
        float4 pl = tris[i * AW_LEAF_FLOAT4S + 3];
        if (intersect_triangle(r.org, r.shear, make_float3(p0.x, p0.y, p0.z),
                               make_float3(p1.x, p1.y, p1.z), make_float3(p2.x, p2.y, p2.z),
                               make_float3(pl.x, pl.y, pl.z), as_uint(pl.w), t_min, hit.t, &t, &u, &v)) {
          if (cut && !material_opaque_at(*cut, as_uint(p0.w), u, v)) continue;
          hit.t = t;
          hit.u = u;
          hit.v = v;
          hit.prim = (int)as_uint(p0.w);
          hit.inst = cur_inst;
          if (any_hit) return hit;
        }
      }
      if (entered) continue;
    }
    // Back out of an instance whose subtree is done: the world ray again.
    if (AW_FEAT_INSTANCE && sp == inst_sp) {
      r = traversal_ray_make(org, dir);
      cur_inst = AW_NONE;
      inst_sp = -1;
    }
    if (sp == 0) return hit;
    node = stack[--sp];
  }
}

// Without cutouts (the BVH tests, the traversal benchmark).
AW_FN TriangleHit bvh_intersect(const AW_GLOBAL float4* nodes, uint num_nodes, const AW_GLOBAL float4* tris,
                                const AW_GLOBAL InstanceGpu* insts, float3 org, float3 dir, float t_min, float t_max,
                                int any_hit) {
  return bvh_intersect_cut(nodes, num_nodes, tris, insts, org, dir, t_min, t_max, any_hit, 0);
}

#else  // AW_LANES > 1

#include "bvh/traverse_lanes.h"

#endif
#endif
