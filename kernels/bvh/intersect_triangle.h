// Watertight ray–triangle intersection: Woop, Benthin & Wald 2013, "Watertight Ray/Triangle
// Intersection", JCGT 2(1). Rays are sheared into a space where they run along +z (Sec. 3),
// so edge tests share their arithmetic between neighbouring triangles and a ray through an
// edge or vertex hits exactly one of the triangles that share it — no cracks, no double hits.
#ifndef AW_BVH_INTERSECT_TRIANGLE_H
#define AW_BVH_INTERSECT_TRIANGLE_H

#include "common/compat.h"

// Per-ray constants of the shear transform (Sec. 3, Fig. 2).
typedef struct {
  int kx, ky, kz;
  float sx, sy, sz;
} RayShear;

AW_FN float f3_get(float3 v, int k) { return k == 0 ? v.x : (k == 1 ? v.y : v.z); }

// a b - c d with an error of at most 1.5 ulps of the result, however much the products cancel
// (Kahan's algorithm with a fused multiply-add: Jeannerod, Louvet & Muller 2013, "Further
// analysis of Kahan's algorithm for the accurate computation of 2x2 determinants", Math.
// Comp. 82(284), Theorem 1). fma rounds once on every device and on the host, so both agree.
AW_FN float diff_of_products(float a, float b, float c, float d) {
  float cd = c * d;
  float err = fma(-c, d, cd);  // cd - c d exactly
  return fma(a, b, -cd) + err;
}

AW_FN RayShear ray_shear_make(float3 dir) {
  RayShear s;
  float ax = fabs(dir.x), ay = fabs(dir.y), az = fabs(dir.z);
  // kz = dimension where the direction is largest in magnitude.
  s.kz = (ax > ay) ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
  s.kx = s.kz + 1 == 3 ? 0 : s.kz + 1;
  s.ky = s.kx + 1 == 3 ? 0 : s.kx + 1;
  // Swap kx and ky to preserve the winding (and so the sign convention of u, v).
  if (f3_get(dir, s.kz) < 0.0f) {
    int tmp = s.kx;
    s.kx = s.ky;
    s.ky = tmp;
  }
  float dz = f3_get(dir, s.kz);
  s.sx = f3_get(dir, s.kx) / dz;
  s.sy = f3_get(dir, s.ky) / dz;
  s.sz = 1.0f / dz;
  return s;
}

// Returns 1 and writes t, u, v (barycentrics of v1 and v2, Embree's convention) for a hit
// with tmin < t < *t_max. Triangles are double sided; degenerate ones never hit.
AW_FN int intersect_triangle(float3 org, RayShear s, float3 v0, float3 v1, float3 v2,
                             float t_min, float t_max, float* t_out, float* u_out, float* v_out) {
  float3 a3 = v0 - org, b3 = v1 - org, c3 = v2 - org;
  float az = f3_get(a3, s.kz), bz = f3_get(b3, s.kz), cz = f3_get(c3, s.kz);
  float ax = f3_get(a3, s.kx) - s.sx * az, ay = f3_get(a3, s.ky) - s.sy * az;
  float bx = f3_get(b3, s.kx) - s.sx * bz, by = f3_get(b3, s.ky) - s.sy * bz;
  float cx = f3_get(c3, s.kx) - s.sx * cz, cy = f3_get(c3, s.ky) - s.sy * cz;
  // Scaled barycentrics: 2D edge functions (Sec. 3, Eq. 4).
  float U = cx * by - cy * bx;
  float V = ax * cy - ay * cx;
  float W = bx * ay - by * ax;
  // Edge cases exactly on an edge: recompute in double precision so the sign is exact
  // (Sec. 3.1). Only taken for rays that graze an edge, so the cost is negligible.
  if (U == 0.0f || V == 0.0f || W == 0.0f) {
#if AW_DEVICE && !defined(cl_khr_fp64)
    // No fp64 on this device: the float result stands (still consistent per edge).
#else
    U = (float)((double)cx * (double)by - (double)cy * (double)bx);
    V = (float)((double)ax * (double)cy - (double)ay * (double)cx);
    W = (float)((double)bx * (double)ay - (double)by * (double)ax);
#endif
  }
  if ((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f)) return 0;
  float det = U + V + W;
  if (det == 0.0f) return 0;
  // The hit distance from the triangle's plane, t = ((vk - org) . n) / (dir . n) with
  // dir . n = (sx n_kx + sy n_ky + n_kz) / sz, instead of the paper's scaled distance
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
  float inv_det = 1.0f / det;
  float3 e01 = v1 - v0, e12 = v2 - v1, e20 = v0 - v2;
  float l01 = e01.x * e01.x + e01.y * e01.y + e01.z * e01.z;
  float l12 = e12.x * e12.x + e12.y * e12.y + e12.z * e12.z;
  float l20 = e20.x * e20.x + e20.y * e20.y + e20.z * e20.z;
  // vk and its two edges (both pointing away from it, so n keeps the winding's orientation).
  float3 p = a3, ea = e01, eb = -e20;  // k = 0: the longest edge is v1 v2
  if (l20 >= l12 && l20 >= l01) {      // k = 1: the longest edge is v2 v0
    p = b3;
    ea = e12;
    eb = -e01;
  } else if (l01 >= l12 && l01 >= l20) {  // k = 2: the longest edge is v0 v1
    p = c3;
    ea = e20;
    eb = -e12;
  }
  // Each component of the cross product by diff_of_products: for a sliver (edges nearly
  // parallel or antiparallel) the plain products cancel, and their rounding tilted n by up to
  // u / sin(angle) in any direction, 1e-4 rad for an aspect of 1e-4: a ray leaving such a
  // sliver 3.7e-6 above its plane hit it again 1e-4 farther along (BvhVsEmbree.RaysLeavingA
  // SurfaceNeverHitIt). Rounded once per component, n keeps only the edges' own rounding,
  // which tilts it about the sliver's own axis.
  float3 n = make_float3(diff_of_products(ea.y, eb.z, ea.z, eb.y), diff_of_products(ea.z, eb.x, ea.x, eb.z),
                         diff_of_products(ea.x, eb.y, ea.y, eb.x));
  float dn = s.sx * f3_get(n, s.kx) + s.sy * f3_get(n, s.ky) + f3_get(n, s.kz);
  float t = (p.x * n.x + p.y * n.y + p.z * n.z) * s.sz / dn;
  if (!isfinite(t)) t = (U * (s.sz * az) + V * (s.sz * bz) + W * (s.sz * cz)) * inv_det;
  if (!(t > t_min && t < t_max)) return 0;
  *t_out = t;
  *u_out = V * inv_det;
  *v_out = W * inv_det;
  return 1;
}

#endif
