// Rays and robust origins.
#ifndef AW_COMMON_RAY_H
#define AW_COMMON_RAY_H

#include "common/compat.h"
#include "common/lanes.h"

// gamma(n) = n u / (1 - n u), u = 2^-24 the unit roundoff of round-to-nearest floats: the
// bound on the relative error of n chained roundings (Higham 2002, "Accuracy and Stability
// of Numerical Algorithms", Sec. 3.1, Lemma 3.1; Pharr, Jakob & Humphreys, pbrt-v4, Sec. 6.8.1).
#define AW_ROUNDOFF 5.96046448e-8f
AW_FN float aw_gamma(float n) { return n * AW_ROUNDOFF / (1.0f - n * AW_ROUNDOFF); }

// The intersectors' own share of a ray origin's offset, in units of the roundoff times the
// hit primitive's size (the largest distance from the hit point to one of its vertices, a
// sphere's radius). A ray leaving a surface must find its own primitive behind it; the
// distance the intersectors compute carries a rounding error of a few units of roundoff times
// the distance from the origin to the primitive's vertices (bvh/intersect_triangle.h: the
// plane through a corner; intersect_sphere.h: |f|^2 - r^2), which the position's own error
// bound (below) does not contain: pbrt-v4 covers it with a second guard in the triangle test
// (Sec. 6.8.4, deltaT), which Embree (the scalar path's intersector) has not. Measured on
// BvhVsEmbree.RaysLeavingASurfaceNeverHitIt: 4 units already leave no self-hit on well-shaped
// triangles and spheres for Embree and the kernels alike; 64 (3.8e-6 of the primitive's size)
// also keeps Embree's re-hits of slivers, whose plane its test tilts, at 0-20% of the rays
// leaving them, against 22-37% with 4 (docs/numerics.md#ray-origins).
#define AW_OFFSET_EXTENT 64.0f

// One float further from `x` in the direction of the sign of `s` (0: x itself); from zero, the
// smallest normal float, not a denormal, which devices may flush back to zero.
// (On lanes, common/lanes.h: every case computed, the path's own selected. The step is taken
// on the bits as unsigned words, whose wrap-around is defined: x = -0, stepped down and then
// discarded by the selects, is 0x80000000 - 1, which as a signed int overflows, undefined in
// C++ and OpenCL C alike, and caught by UBSan.)
AW_FN lfloat aw_float_step(lfloat x, lfloat s) {
  lmask up = (x > 0.0f) == (s > 0.0f);  // away from zero
  lfloat stepped = L_UINT_AS_FLOAT(L_AS_UINT(x) + L_SEL(up, (luint)(1u), (luint)(0xffffffffu)));
  lfloat from_zero = copysign((lfloat)(1.17549435e-38f), s);
  return L_SEL(s == 0.0f, x, L_SEL(x == 0.0f, from_zero, stepped));
}

// The origin of a ray that leaves a surface point p along the side `n` (a unit normal facing
// where the ray goes) points to, `err` being the bound on the distance from p, as computed, to
// the true surface along n, plus the intersectors' share (AW_OFFSET_EXTENT): p moved by err
// along n, and then one float further in every component n moves, so that the rounding of
// that addition cannot bring it back (pbrt-v4 Sec. 6.8.6, OffsetRayOrigin). The offset scales
// with the scene: with its coordinates' magnitude through the position's error, with its size
// through the primitive's (Extremes.SmallOrDistantScenesRenderTheSameImage). It replaces
// Wächter & Binder's fixed-scale integer offsets (Ray Tracing Gems ch. 6), whose 1/65536 near
// the origin was 30% of a sphere's radius in a scene scaled by 1e-4, and whose 256 ulps were 2
// units at 1e5 from the origin.
AW_FN lfloat3 offset_ray_origin(lfloat3 p, lfloat3 n, lfloat err) {
  lfloat3 o = l3_add(p, l3_scale(n, err));
  return make_lfloat3(aw_float_step(o.x, n.x), aw_float_step(o.y, n.y), aw_float_step(o.z, n.z));
}

// The bound `err` for offset_ray_origin at a triangle hit p = b0 p0 + b1 p1 + b2 p2 as
// classify_hit_point computes it, b0 = 1 - b1 - b2 in floats (after pbrt-v4 Sec. 6.8.5, whose
// gamma(7) sum |b_i p_i| also covers barycentrics it computes itself): b0's two roundings move p
// by at most gamma(2) |p0| off the plane the barycentrics span, the three products and two sums
// by gamma(3) sum |b_i p_i|; `vert_err` the bound on each vertex's own error (an instance's
// transform; 0 for world geometry, whose vertices are the very floats the intersector used);
// all projected on the unit normal ng, plus AW_OFFSET_EXTENT roundoffs of the triangle's size
// seen from p.
AW_FN lfloat triangle_point_error(lfloat3 p, lfloat3 p0, lfloat3 p1, lfloat3 p2, lfloat b0, lfloat b1, lfloat b2,
                                  lfloat3 vert_err, lfloat3 ng) {
  lfloat3 s = l3_add(l3_add(l3_fabs(l3_scale(p0, b0)), l3_fabs(l3_scale(p1, b1))), l3_fabs(l3_scale(p2, b2)));
  lfloat3 e = l3_add(l3_add(l3_scale(l3_fabs(p0), aw_gamma(2.0f)), l3_scale(s, aw_gamma(3.0f))),
                     l3_scale(vert_err, 1.0f + aw_gamma(3.0f)));
  lfloat3 d0 = l3_sub(p0, p), d1 = l3_sub(p1, p), d2 = l3_sub(p2, p);
  lfloat ext2 = fmax(fmax(l3_dot(d0, d0), l3_dot(d1, d1)), l3_dot(d2, d2));
  return l3_dot(l3_fabs(ng), e) + AW_OFFSET_EXTENT * AW_ROUNDOFF * sqrt(ext2);
}

// The same at an analytic sphere's hit p = c + w r (w a unit vector computed with a few
// roundings, then one rounding of the sum), `vert_err` the centre's own error.
AW_FN lfloat sphere_point_error(lfloat3 p, lfloat3 w, lfloat r, lfloat3 vert_err, lfloat3 ng) {
  lfloat3 e = l3_add(l3_add(l3_scale(l3_fabs(p), aw_gamma(1.0f)), l3_scale(l3_fabs(l3_scale(w, r)), aw_gamma(5.0f))),
                     l3_scale(vert_err, 1.0f + aw_gamma(1.0f)));
  return l3_dot(l3_fabs(ng), e) + AW_OFFSET_EXTENT * AW_ROUNDOFF * r;
}

#endif
