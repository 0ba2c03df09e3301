// Warps from the unit square and local frames, shared by every lobe and light.
#ifndef AW_COMMON_SAMPLING_H
#define AW_COMMON_SAMPLING_H

#include "common/compat.h"

// sin x and cos x for |x| <= pi/4, by the minimax polynomials of Cephes' single-precision
// sinf/cosf for that range (S. L. Moshier 1989, "Methods and Programs for Mathematical
// Functions", Cephes Math Library: sinf.c, its sincof/coscof tables). Measured against double
// precision over 4M points of the range: relative error <= 7.3e-8 (sin), 1.1e-7 (cos), about one
// ulp (tests/lobes/test_diffuse.cpp checks 2.5e-7). Why not sin()/cos(): PoCL's run a
// Payne-Hanek argument reduction on every call (__pocl_argReductionS: 3.3% of the Cornell box's
// render time), which a known quarter-range argument does not need; and these few
// multiply-adds, with contraction off on both sides, round the same on the host and every
// device, where two math libraries differed by an ulp.
AW_FN void sincos_quarter(float x, float* s, float* c) {
  float z = x * x;
  *s = x + x * z * (-1.6666654611e-1f + z * (8.3321608736e-3f + z * -1.9515295891e-4f));
  *c = 1.0f - 0.5f * z + z * z * (4.166664568298827e-2f + z * (-1.388731625493765e-3f + z * 2.443315711809948e-5f));
}

// sin and cos of 2 pi u for u in [0, 1] (a uniformly sampled azimuth), through
// sincos_quarter: 8u splits into an octant o and an exact fraction f (8u is exact, and so is
// 8u - floor(8u)); the angle is q pi/2 + x (o = 2q) or (q + 1) pi/2 - x (o = 2q + 1) with
// x in [0, pi/4], and a quarter turn only swaps and negates. Same reasons as above: no
// argument reduction, the same rounding on every side.
AW_FN void sincos_turn(float u, float* s, float* c) {
  float t = 8.0f * u;
  float o = floor(t);
  float f = t - o;
  int k = (int)o;
  int odd = k & 1;
  float sx, cx;
  sincos_quarter((odd ? 1.0f - f : f) * (M_PI_F / 4.0f), &sx, &cx);
  float a = cx, b = odd ? -sx : sx;  // cos and sin of +-x
  switch (((k >> 1) + odd) & 3) {    // the quarter turns
    case 0: *c = a; *s = b; break;
    case 1: *c = -b; *s = a; break;
    case 2: *c = -a; *s = -b; break;
    default: *c = b; *s = -a; break;
  }
}

// Concentric square-to-disk map: Shirley & Chiu 1997, "A Low Distortion Map Between Disk and
// Square", Sec. 3 (in the polar form of Shirley's later note). Keeps strata compact. The angle
// is phi = (pi/4)(b/a) in the wedges |a| > |b|, else pi/2 - (pi/4)(a/b); both are a quarter-range
// angle x = (pi/4) * ratio, and cos(pi/2 - x) = sin x, sin(pi/2 - x) = cos x.
AW_FN float2 sample_concentric_disk(float2 u) {
  float a = 2.0f * u.x - 1.0f;
  float b = 2.0f * u.y - 1.0f;
  if (a == 0.0f && b == 0.0f) return make_float2(0.0f, 0.0f);
  float s, c;
  if (fabs(a) > fabs(b)) {
    sincos_quarter((M_PI_F / 4.0f) * (b / a), &s, &c);
    return make_float2(a * c, a * s);
  }
  sincos_quarter((M_PI_F / 4.0f) * (a / b), &s, &c);
  return make_float2(b * s, b * c);
}

// Cosine-weighted hemisphere around +z (Malley's method: project the disk up), pdf cos/pi.
AW_FN float3 sample_cosine_hemisphere(float2 u) {
  float2 d = sample_concentric_disk(u);
  float z = safe_sqrt(1.0f - d.x * d.x - d.y * d.y);
  return make_float3(d.x, d.y, z);
}

AW_FN float pdf_cosine_hemisphere(float cos_theta) { return fmax(cos_theta, 0.0f) * (1.0f / M_PI_F); }

// Uniform direction in the cone cos(theta) >= cos_max around +z; pdf 1/(2 pi (1 - cos_max)).
AW_FN float3 sample_uniform_cone(float2 u, float cos_max) {
  float cos_t = 1.0f - u.x * (1.0f - cos_max);
  float sin_t = safe_sqrt(1.0f - cos_t * cos_t);
  float sp, cp;
  sincos_turn(u.y, &sp, &cp);  // phi = 2 pi u.y
  return make_float3(cp * sin_t, sp * sin_t, cos_t);
}

// Orthonormal basis from a unit normal without branches on a near-degenerate axis:
// Duff et al. 2017, "Building an Orthonormal Basis, Revisited", JCGT 6(1), Listing 3.
AW_FN void make_frame(float3 n, float3* t, float3* b) {
  float s = copysign(1.0f, n.z);
  float a = -1.0f / (s + n.z);
  float c = n.x * n.y * a;
  *t = make_float3(1.0f + s * n.x * n.x * a, s * c, -s * n.x);
  *b = make_float3(c, s + n.y * n.y * a, -n.y);
}

AW_FN float3 frame_to_world(float3 v, float3 t, float3 b, float3 n) { return v.x * t + v.y * b + v.z * n; }
AW_FN float3 frame_to_local(float3 v, float3 t, float3 b, float3 n) {
  return make_float3(dot(v, t), dot(v, b), dot(v, n));
}

// Power heuristic with beta = 2: Veach 1997, "Robust Monte Carlo Methods for Light Transport
// Simulation", Sec. 9.2.4, Eq. 9.13. Written so that an infinite pdf (delta) wins cleanly.
AW_FN float mis_power(float pdf_a, float pdf_b) {
  float a = pdf_a * pdf_a;
  float b = pdf_b * pdf_b;
  if (!(a + b > 0.0f)) return 0.0f;
  if (!isfinite(a)) return 1.0f;
  return a / (a + b);
}

#endif
