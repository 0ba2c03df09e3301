// The flattened BVH4 (kernels/types/bvh.h) traversed by W rays at once, one per lane: the
// ray stages of the lane program (integrator/kernels_lanes.cl), W > 1 only; included by
// bvh/traverse.h, whose one-ray traversal serves W = 1.
//
// Why a second traversal loop. The one-ray loop puts SIMD across a node's four children
// (Wald et al. 2008, "Getting Rid of Packets", Sec. 3): four lanes of a 16-lane machine, and a
// work-item at a time on PoCL. This loop puts SIMD across W rays, as a packet traversal does
// (Wald, Slusallek, Benthin & Wagner 2001, "Interactive Rendering with Coherent Ray Tracing",
// Sec. 3.2; Embree's rtcIntersect16): a node's box is tested against all W rays in one vector
// operation per slab, and a leaf's triangles against all W rays by the same
// intersect_triangle, written on lanes. The node and leaf tests are the one-ray loop's
// operations per lane (the same slabs, the same conservative far distance, the same
// watertight triangle test), so each lane finds the hit the one-ray loop finds for its ray;
// only the visiting order differs, which can change which of two triangles at exactly the
// same distance is reported (a ray through the line where two surfaces meet).
//
// The packet's order: a node's children that some lane enters are visited nearest first by
// the smallest entry distance over the lanes that enter them (the others are pushed, farthest
// first; shadow rays, which need any hit, take them in their stored order), each with its own
// lanes: a lane that misses a child's box takes no part in its
// subtree. The stack keeps, per entry, each lane's entry distance (NaN for a lane that does
// not enter), so that a popped entry is skipped by the lanes whose hit is already nearer than
// where they enter it: the one-ray loop's test of that box against the hit so far, as
// tf <= min(box far, hit) * (1 + 2 gamma(3)) (Ize 2013, Sec. 3) becomes tn <= hit * (1 + 2 gamma(3)).
//
// Left out (the host uses it only for scenes without them: host/render/wavefront.cpp):
// instances (two-level BVH) and cutouts (textures are not on lanes).
#ifndef AW_BVH_TRAVERSE_LANES_H
#define AW_BVH_TRAVERSE_LANES_H

#include "common/lanes.h"
#include "types/bvh.h"
#include "bvh/intersect_sphere.h"
#include "bvh/intersect_triangle.h"
#include "common/features.h"

// safe_rcp of bvh/traverse.h per lane: zero components become a huge finite value of their
// sign, so 0 * inf never makes a NaN in the slab test.
AW_FN lfloat l_safe_rcp(lfloat x) { return L_SEL(fabs(x) < 1e-30f, copysign((lfloat)(1e30f), x), 1.0f / x); }
AW_FN lfloat l_min_nn(lfloat a, lfloat b) { return L_SEL(a < b, a, b); }
AW_FN lfloat l_max_nn(lfloat a, lfloat b) { return L_SEL(a > b, a, b); }

// One child box (lo, hi) against every lane's ray: the entry distance where the lane's ray
// meets the box in (t_min, t_max), NaN where it does not. The one-ray loop's slab test
// (bvh/traverse.h), operation for operation.
AW_FN lfloat l_box_entry(float lx, float hx, float ly, float hy, float lz, float hz, lfloat3 org, lfloat ix, lfloat iy,
                         lfloat iz, lfloat t_min, lfloat t_max) {
  lfloat tx0 = (lx - org.x) * ix, tx1 = (hx - org.x) * ix;
  lfloat ty0 = (ly - org.y) * iy, ty1 = (hy - org.y) * iy;
  lfloat tz0 = (lz - org.z) * iz, tz1 = (hz - org.z) * iz;
  lfloat tn = l_max_nn(l_max_nn(l_min_nn(tx0, tx1), l_min_nn(ty0, ty1)), l_max_nn(l_min_nn(tz0, tz1), t_min));
  lfloat tf = l_min_nn(l_min_nn(l_max_nn(tx0, tx1), l_max_nn(ty0, ty1)), l_min_nn(l_max_nn(tz0, tz1), t_max));
  tf = tf * 1.00000036f;
  return L_SEL(tn <= tf, tn, (lfloat)(NAN));
}

// Closest hit (any_hit = 0) or, for shadow rays, a hit (any_hit = 1) in (t_min, t_max) of the
// lanes in `active`; the other lanes' results are no hit.
AW_FN TriangleHit bvh_intersect_lanes(const AW_GLOBAL float4* nodes, uint num_nodes, const AW_GLOBAL float4* tris,
                                      lfloat3 org, lfloat3 dir, lfloat t_min, lfloat t_max, int any_hit,
                                      lmask active) {
  TriangleHit hit;
  hit.t = t_max;
  hit.u = (lfloat)(0.0f);
  hit.v = (lfloat)(0.0f);
  hit.prim = (lint)(-1);
  hit.inst = (luint)(AW_NONE);
  if (num_nodes == 0u || !L_ANY(active)) return hit;
  lfloat ix = l_safe_rcp(dir.x), iy = l_safe_rcp(dir.y), iz = l_safe_rcp(dir.z);
  RayShear shear = ray_shear_make(dir);

  lmask open = active;  // lanes still searching (any_hit: not yet occluded)
  lmask act = active;   // lanes that take part in the current node
  int stack_node[AW_BVH_STACK_SIZE];
  float stack_tn[AW_BVH_STACK_SIZE * AW_LANES];  // per entry, each lane's entry distance
  int sp = 0;
  int node = 0;
  for (;;) {
    // Inner nodes: every child box against the lanes of this node.
    while (node >= 0) {
      const AW_GLOBAL float4* nd = nodes + (uint)node * 8u;
      float4 lx = nd[0], hx = nd[1], ly = nd[2], hy = nd[3], lz = nd[4], hz = nd[5];
      int4 ch = as_int4(nd[6]);
      int hn[4];
      float hk[4];
      lfloat htn[4];
      int k = 0;
#define AW_LANE_CHILD(c)                                                                                    \
  if ((c) == 0 || ch.s##c != AW_BVH_EMPTY) {                                                             \
    lfloat e = l_box_entry(lx.s##c, hx.s##c, ly.s##c, hy.s##c, lz.s##c, hz.s##c, org, ix, iy, iz, t_min, hit.t); \
    lmask m = act && e == e; /* not NaN: the lane enters */                                              \
    if (L_ANY(m)) {                                                                                       \
      hn[k] = ch.s##c;                                                                                    \
      htn[k] = L_SEL(m, e, (lfloat)(NAN));                                                                \
      hk[k] = any_hit ? 0.0f : l_hmin(L_SEL(m, e, (lfloat)(INFINITY)));                                    \
      ++k;                                                                                                \
    }                                                                                                     \
  }
      AW_LANE_CHILD(0)
      AW_LANE_CHILD(1)
      AW_LANE_CHILD(2)
      AW_LANE_CHILD(3)
#undef AW_LANE_CHILD
      if (k == 0) break;
      // Farthest first (insertion sort of at most four by the nearest lane's entry), so the
      // stack pops them nearest first; the nearest is visited now. Shadow rays (any_hit) take
      // the children in their stored order: any occluder ends a lane, whichever is found first,
      // and the sort and its horizontal minima cost their stage 14% on Intel's runtime
      // (docs/performance.md, "Shadow rays without the children's sort").
      for (int i = 1; !any_hit && i < k; ++i) {
        int n_i = hn[i];
        float k_i = hk[i];
        lfloat t_i = htn[i];
        int j = i - 1;
        while (j >= 0 && hk[j] <= k_i) {
          hn[j + 1] = hn[j];
          hk[j + 1] = hk[j];
          htn[j + 1] = htn[j];
          --j;
        }
        hn[j + 1] = n_i;
        hk[j + 1] = k_i;
        htn[j + 1] = t_i;
      }
      for (int i = 0; i < k - 1; ++i) {
        stack_node[sp] = hn[i];
        L_STORE(htn[i], stack_tn, sp);
        ++sp;
      }
      node = hn[k - 1];
      act = htn[k - 1] == htn[k - 1];
    }
    // Leaf: ~node = (first << 3) | (count - 1); its entries against the lanes that entered it.
    if (node < 0) {
      int packed = ~node;
      int first = packed >> 3;
      int count = (packed & 7) + 1;
      for (int i = first; i < first + count; ++i) {
        float4 p0 = tris[i * AW_LEAF_FLOAT4S + 0];
        float4 p1 = tris[i * AW_LEAF_FLOAT4S + 1];
        float4 p2 = tris[i * AW_LEAF_FLOAT4S + 2];
        float4 pl = tris[i * AW_LEAF_FLOAT4S + 3];
        lfloat t, u = (lfloat)(0.0f), v = (lfloat)(0.0f);
        lmask h;
        if (AW_FEAT_SPHERE && as_uint(p1.w) == AW_LEAF_SPHERE)
          h = intersect_sphere(org, dir, p0.xyz, p1.x, t_min, hit.t, &t);
        else
          h = intersect_triangle(org, shear, p0.xyz, p1.xyz, p2.xyz, pl.xyz, as_uint(pl.w), t_min, hit.t, &t, &u, &v);
        h = h && act;
        hit.t = L_SEL(h, t, hit.t);
        hit.u = L_SEL(h, u, hit.u);
        hit.v = L_SEL(h, v, hit.v);
        hit.prim = L_SEL(h, (lint)(as_int(p0.w)), hit.prim);
        if (any_hit) {
          open = open && !h;
          act = act && !h;
          if (!L_ANY(open)) return hit;
          if (!L_ANY(act)) break;
        }
      }
    }
    // The next entry some lane still needs.
    for (;;) {
      if (sp == 0) return hit;
      --sp;
      node = stack_node[sp];
      act = open && L_LOAD(stack_tn, sp) <= hit.t * 1.00000036f;
      if (L_ANY(act)) break;
    }
  }
}

#endif
