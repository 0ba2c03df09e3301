// Stack-based traversal of the flattened BVH2 (kernels/types/bvh.h, docs/bvh-layout.md).
// Compiles as OpenCL C (the intersect kernels) and as C++ (tests compare it to Embree).
#ifndef AW_BVH_TRAVERSE_H
#define AW_BVH_TRAVERSE_H

#include "common/compat.h"
#include "types/bvh.h"
#include "bvh/intersect_triangle.h"

typedef struct {
  float t;
  float u, v;
  int prim;  // original triangle id, -1 = no hit
} TriangleHit;

// Slab test against one box with a conservative far distance: Ize 2013, "Robust BVH Ray
// Traversal", JCGT 2(2), Sec. 3: computed as (bound - org) * inv, whose error is relative to
// t, and t_far scaled by 1 + 2 gamma(3), keeps the box test from rejecting a box that the
// watertight triangle test would hit. (The cheaper bound * inv - org * inv form errs relative
// to |org * inv| and left cracks at shared vertices: tests/bvh, heightfield.)
AW_FN int box_hit(float lox, float hix, float loy, float hiy, float loz, float hiz,
                  float3 org, float3 inv, float t_min, float t_max, float* t_near) {
  float tx0 = (lox - org.x) * inv.x, tx1 = (hix - org.x) * inv.x;
  float ty0 = (loy - org.y) * inv.y, ty1 = (hiy - org.y) * inv.y;
  float tz0 = (loz - org.z) * inv.z, tz1 = (hiz - org.z) * inv.z;
  // No NaN can arise here (finite reciprocals, finite bounds), so plain min/max suffice.
  float tn = max_nn(max_nn(min_nn(tx0, tx1), min_nn(ty0, ty1)), max_nn(min_nn(tz0, tz1), t_min));
  float tf = min_nn(min_nn(max_nn(tx0, tx1), max_nn(ty0, ty1)), min_nn(max_nn(tz0, tz1), t_max));
  *t_near = tn;
  return tn <= tf * 1.00000036f;
}

// Reciprocal direction with zero components replaced by a huge finite value of the same
// sign, so 0 * inf never produces NaN in the slab test.
AW_FN float safe_rcp(float x) {
  const float big = 1e30f;
  return fabs(x) < 1e-30f ? copysign(big, x) : 1.0f / x;
}

// Closest hit (any_hit = 0) or first hit found (any_hit = 1, for shadow rays) in (t_min, t_max).
AW_FN TriangleHit bvh_intersect(const AW_GLOBAL float4* nodes, uint num_nodes,
                                const AW_GLOBAL float4* tris, float3 org, float3 dir,
                                float t_min, float t_max, int any_hit) {
  TriangleHit hit;
  hit.t = t_max;
  hit.u = 0.0f;
  hit.v = 0.0f;
  hit.prim = -1;
  if (num_nodes == 0) return hit;

  float3 inv = make_float3(safe_rcp(dir.x), safe_rcp(dir.y), safe_rcp(dir.z));
  RayShear shear = ray_shear_make(dir);

  int stack[AW_BVH_STACK_SIZE];
  int sp = 0;
  int node = 0;
  for (;;) {
    // Inner nodes: test both children, descend into the nearer, push the farther.
    while (node >= 0) {
      float4 a = nodes[node * 4 + 0];
      float4 b = nodes[node * 4 + 1];
      float4 c = nodes[node * 4 + 2];
      float4 d = nodes[node * 4 + 3];
      float t0, t1;
      int h0 = box_hit(a.x, a.y, a.z, a.w, c.x, c.y, org, inv, t_min, hit.t, &t0);
      int h1 = box_hit(b.x, b.y, b.z, b.w, c.z, c.w, org, inv, t_min, hit.t, &t1);
      int c0 = as_int(d.x), c1 = as_int(d.y);
      if (h0 && h1) {
        int near_c = t0 <= t1 ? c0 : c1;
        int far_c = t0 <= t1 ? c1 : c0;
        stack[sp++] = far_c;
        node = near_c;
      } else if (h0) {
        node = c0;
      } else if (h1) {
        node = c1;
      } else {
        if (sp == 0) return hit;
        node = stack[--sp];
      }
    }
    // Leaf: ~node = (first << 3) | (count - 1).
    {
      int packed = ~node;
      int first = packed >> 3;
      int count = (packed & 7) + 1;
      for (int i = first; i < first + count; ++i) {
        float4 p0 = tris[i * 3 + 0];
        float4 p1 = tris[i * 3 + 1];
        float4 p2 = tris[i * 3 + 2];
        float t, u, v;
        if (intersect_triangle(org, shear, make_float3(p0.x, p0.y, p0.z),
                               make_float3(p1.x, p1.y, p1.z), make_float3(p2.x, p2.y, p2.z),
                               t_min, hit.t, &t, &u, &v)) {
          hit.t = t;
          hit.u = u;
          hit.v = v;
          hit.prim = (int)as_uint(p0.w);
          if (any_hit) return hit;
        }
      }
    }
    if (sp == 0) return hit;
    node = stack[--sp];
  }
}

#endif
