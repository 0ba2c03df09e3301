// Watertight ray–triangle intersection: Woop, Benthin & Wald 2013, "Watertight Ray/Triangle
// Intersection", JCGT 2(1). Rays are sheared into a space where they run along +z (Sec. 3),
// so edge tests share their arithmetic between neighbouring triangles and a ray through an
// edge or vertex hits exactly one of the triangles that share it — no cracks, no double hits.
// Written on lanes (common/lanes.h): one ray per call at W = 1 (the one-ray traversal, the
// host's tests), W rays against one triangle at W > 1 (the lane traversal, bvh/traverse.h);
// every lane computes what W = 1 computes for its ray.
#ifndef AW_BVH_INTERSECT_TRIANGLE_H
#define AW_BVH_INTERSECT_TRIANGLE_H

#include "common/compat.h"
#include "common/lanes.h"

// Per-ray constants of the shear transform (Sec. 3, Fig. 2).
//
// On lanes (W > 1) the permutation (kx, ky, kz) differs per lane, and l3_get is two selects
// per coordinate; the compiler kept their masks as bytes across the leaf loop and expanded
// them again before every select (Intel's runtime on AVX2: the triangle test's main block
// was 261 instructions per 16 lanes, 187 with the rows below). So the lanes also carry the
// shear as rows, for dot products with a vertex d (relative to the origin) or a normal n:
//   rx: 1 at kx, -sx at kz, 0 else   d . rx = d_kx - sx d_kz   (the sheared x)
//   ry: 1 at ky, -sy at kz, 0 else   d . ry = d_ky - sy d_kz   (the sheared y)
//   dxy: sx at kx, sy at ky, 0 else  n . dxy = sx n_kx + sy n_ky
//   ez: 1 at kz, 0 else              n . ez = n_kz
// Each dot has at most two nonzero terms; with contraction off (common/compat.h) 1 x a,
// a + 0 and the order of two terms are exact, so each rounds as the W = 1 expression beside
// it does, bit for bit, but for the sign of an exact zero (the lane-against-one-path tests
// compare whole films bit for bit: tests/render/test_lanes.cpp).
typedef struct {
  lint kx, ky, kz;
  lfloat sx, sy, sz;
#if AW_LANES > 1
  lfloat3 rx, ry, dxy, ez;
#endif
} RayShear;

// a b - c d with an error of at most 1.5 ulps of the result, however much the products cancel
// (Kahan's algorithm with a fused multiply-add: Jeannerod, Louvet & Muller 2013, "Further
// analysis of Kahan's algorithm for the accurate computation of 2x2 determinants", Math.
// Comp. 82(284), Theorem 1). fma rounds once on every device and on the host, so both agree.
AW_FN float diff_of_products(float a, float b, float c, float d) {
  float cd = c * d;
  float err = fma(-c, d, cd);  // cd - c d exactly
  return fma(a, b, -cd) + err;
}

#if AW_LANES > 1
// The 3-vector with a at component i, b at component j (i != j, or b = a) and 0 else, per lane.
AW_FN lfloat3 shear_row(lint i, lfloat a, lint j, lfloat b) {
  const lfloat zero = (lfloat)(0.0f);
  return make_lfloat3(L_SEL(i == 0, a, L_SEL(j == 0, b, zero)), L_SEL(i == 1, a, L_SEL(j == 1, b, zero)),
                      L_SEL(i == 2, a, L_SEL(j == 2, b, zero)));
}
#endif

AW_FN RayShear ray_shear_make(lfloat3 dir) {
  RayShear s;
  lfloat ax = fabs(dir.x), ay = fabs(dir.y), az = fabs(dir.z);
  // kz = dimension where the direction is largest in magnitude.
  s.kz = L_SEL(ax > ay, L_SEL(ax > az, (lint)(0), (lint)(2)), L_SEL(ay > az, (lint)(1), (lint)(2)));
  s.kx = L_SEL(s.kz + 1 == 3, (lint)(0), s.kz + 1);
  s.ky = L_SEL(s.kx + 1 == 3, (lint)(0), s.kx + 1);
  // Swap kx and ky to preserve the winding (and so the sign convention of u, v).
  lmask flip = l3_get(dir, s.kz) < 0.0f;
  lint kx = s.kx;
  s.kx = L_SEL(flip, s.ky, s.kx);
  s.ky = L_SEL(flip, kx, s.ky);
  lfloat dz = l3_get(dir, s.kz);
  s.sx = l3_get(dir, s.kx) / dz;
  s.sy = l3_get(dir, s.ky) / dz;
  s.sz = 1.0f / dz;
#if AW_LANES > 1
  s.rx = shear_row(s.kx, (lfloat)(1.0f), s.kz, -s.sx);
  s.ry = shear_row(s.ky, (lfloat)(1.0f), s.kz, -s.sy);
  s.dxy = shear_row(s.kx, s.sx, s.ky, s.sy);
  s.ez = shear_row(s.kz, (lfloat)(1.0f), s.kz, (lfloat)(1.0f));
#endif
  return s;
}

// The plane intersect_triangle measures a hit's distance t from, t = ((vk - org) . n) /
// (dir . n) with dir . n = (sx n_kx + sy n_ky + n_kz) / sz, instead of the paper's scaled distance
// T = U az + V bz + W cz (Sec. 3): T adds the edge functions times the vertices' distances
// along the ray, so their rounding (absolute, of the size of the products of the sheared
// coordinates) is multiplied by those distances. For a long, thin triangle far larger than
// the ray's distance to it that error exceeds t itself: a 2e4 x 1 triangle at distance ~1
// got t wrong by up to 13, and 2-3% of the rays that hit it missed (t < 0), where the plane
// errs by 5e-6 as Embree does (BvhVsEmbree.LongThinTrianglesKeepTheirDistance,
// Extremes.DegenerateMeshGeometryRendersCleanAndWatertight). The plane is taken at vk, the
// corner opposite the longest edge, with n the cross product of the two shorter edges, which
// meet there at the triangle's widest angle: from a needle's tip, two long, nearly parallel
// edges cancel in the cross product, and a ray starting 1e-5 from a needle's plane got the
// wrong sign of t (BvhVsEmbree.RandomSoupWithSlivers, built with clang). The edge functions
// alone still decide hit or miss (watertight). Written out, not dot/cross, so that the host
// and the device round the same operations. T stays the fallback where the plane gives no
// finite t (a sliver whose edges' cross product rounds to 0).
//
// Returns k, the corner v_k the plane is taken at (0, 1, 2), and writes its normal n. A
// triangle's own, the same for every ray: the flattener computes it once into
// LeafTriangle.plane (host/bvh/flat_bvh.cpp) with this function compiled as C++, contraction
// off on both sides, so every traversal reads the bits the kernels computed before
// (docs/performance.md, "Each triangle's plane at flatten time").
AW_FN uint triangle_plane(float3 v0, float3 v1, float3 v2, float3* n_out) {
  float3 e01 = v1 - v0, e12 = v2 - v1, e20 = v0 - v2;
  float l01 = e01.x * e01.x + e01.y * e01.y + e01.z * e01.z;
  float l12 = e12.x * e12.x + e12.y * e12.y + e12.z * e12.z;
  float l20 = e20.x * e20.x + e20.y * e20.y + e20.z * e20.z;
  // vk and its two edges (both pointing away from it, so n keeps the winding's orientation).
  uint k = 0u;  // the longest edge is v1 v2
  float3 ea = e01, eb = -e20;
  if (l20 >= l12 && l20 >= l01) {  // k = 1: the longest edge is v2 v0
    k = 1u;
    ea = e12;
    eb = -e01;
  } else if (l01 >= l12 && l01 >= l20) {  // k = 2: the longest edge is v0 v1
    k = 2u;
    ea = e20;
    eb = -e12;
  }
  // Each component of the cross product by diff_of_products: for a sliver (edges nearly
  // parallel or antiparallel) the plain products cancel, and their rounding tilted n by up to
  // u / sin(angle) in any direction, 1e-4 rad for an aspect of 1e-4: a ray leaving such a
  // sliver 3.7e-6 above its plane hit it again 1e-4 farther along (BvhVsEmbree.RaysLeavingA
  // SurfaceNeverHitIt). Rounded once per component, n keeps only the edges' own rounding,
  // which tilts it about the sliver's own axis.
  *n_out = make_float3(diff_of_products(ea.y, eb.z, ea.z, eb.y), diff_of_products(ea.z, eb.x, ea.x, eb.z),
                       diff_of_products(ea.x, eb.y, ea.y, eb.x));
  return k;
}

// Returns true (per lane) for a hit with t_min < t < t_max and writes t, u, v (barycentrics
// of v1 and v2, Embree's convention); where it returns false they hold anything. Triangles
// are double sided; degenerate ones never hit.
AW_FN lmask intersect_triangle(lfloat3 org, RayShear s, float3 v0, float3 v1, float3 v2, float3 n, uint k,
                               lfloat t_min, lfloat t_max, lfloat* t_out, lfloat* u_out, lfloat* v_out) {
  lfloat3 a3 = l3_sub(l3_bcast(v0), org), b3 = l3_sub(l3_bcast(v1), org), c3 = l3_sub(l3_bcast(v2), org);
  lfloat az = l3_get(a3, s.kz), bz = l3_get(b3, s.kz), cz = l3_get(c3, s.kz);
#if AW_LANES > 1  // the rows of RayShear: the same numbers without a select per lane
  lfloat ax = l3_dot(a3, s.rx), ay = l3_dot(a3, s.ry);
  lfloat bx = l3_dot(b3, s.rx), by = l3_dot(b3, s.ry);
  lfloat cx = l3_dot(c3, s.rx), cy = l3_dot(c3, s.ry);
#else
  lfloat ax = l3_get(a3, s.kx) - s.sx * az, ay = l3_get(a3, s.ky) - s.sy * az;
  lfloat bx = l3_get(b3, s.kx) - s.sx * bz, by = l3_get(b3, s.ky) - s.sy * bz;
  lfloat cx = l3_get(c3, s.kx) - s.sx * cz, cy = l3_get(c3, s.ky) - s.sy * cz;
#endif
  // Scaled barycentrics: 2D edge functions (Sec. 3, Eq. 4).
  lfloat U = cx * by - cy * bx;
  lfloat V = ax * cy - ay * cx;
  lfloat W = bx * ay - by * ax;
  // Edge cases exactly on an edge: recompute in double precision so the sign is exact
  // (Sec. 3.1). Only taken for rays that graze an edge, so the cost is negligible.
  lmask on_edge = U == 0.0f || V == 0.0f || W == 0.0f;
  if (L_ANY(on_edge)) {
#if AW_HAVE_LDOUBLE
    ldouble dax = L_TO_DOUBLE(ax), day = L_TO_DOUBLE(ay), dbx = L_TO_DOUBLE(bx), dby = L_TO_DOUBLE(by);
    ldouble dcx = L_TO_DOUBLE(cx), dcy = L_TO_DOUBLE(cy);
    U = L_SEL(on_edge, L_DOUBLE_TO_FLOAT(dcx * dby - dcy * dbx), U);
    V = L_SEL(on_edge, L_DOUBLE_TO_FLOAT(dax * dcy - day * dcx), V);
    W = L_SEL(on_edge, L_DOUBLE_TO_FLOAT(dbx * day - dby * dax), W);
#else
    // No fp64 on this device: the float result stands (still consistent per edge).
#endif
  }
  lfloat det = U + V + W;
  lmask hit = !((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f)) && det != 0.0f;
  // One ray leaves here on a miss. W rays go on whatever their lanes found: whether any lane
  // of an incoherent packet hits a triangle is close to a coin toss, and the branch on it was
  // mispredicted often enough that computing t for every lane costs less (Intel's runtime, an
  // AVX-512 EPYC: intersect_closest 0.874x, intersect_shadow 0.920x the time, the Cornell box
  // 0.939x; PoCL level; films bit for bit the same: docs/performance.md, "On an AMD EPYC with
  // AVX-512 (Zen 4)"). The lanes that miss compute values the caller never takes
  // (bvh/traverse_lanes.h selects by `hit`), and no_plane below is only the hits'.
#if AW_LANES == 1
  if (!L_ANY(hit)) return hit;
#endif
  // The hit distance from the triangle's plane (triangle_plane, below: its normal n at its
  // corner v_k), t = ((v_k - org) . n) / (dir . n) with dir . n = (sx n_kx + sy n_ky + n_kz) / sz.
  lfloat inv_det = 1.0f / det;
  lfloat3 p = a3;
  if (k == 1u)
    p = b3;
  else if (k == 2u)
    p = c3;
  lfloat3 nl = l3_bcast(n);
#if AW_LANES > 1
  lfloat dn = l3_dot(nl, s.dxy) + l3_dot(nl, s.ez);
#else
  lfloat dn = s.sx * l3_get(nl, s.kx) + s.sy * l3_get(nl, s.ky) + l3_get(nl, s.kz);
#endif
  lfloat t = (p.x * n.x + p.y * n.y + p.z * n.z) * s.sz / dn;
  lmask no_plane = hit && !isfinite(t);
  if (L_ANY(no_plane)) t = L_SEL(no_plane, (U * (s.sz * az) + V * (s.sz * bz) + W * (s.sz * cz)) * inv_det, t);
  hit = hit && t > t_min && t < t_max;
  *t_out = t;
  *u_out = V * inv_det;
  *v_out = W * inv_det;
  return hit;
}

#endif
