// Warps from the unit square and local frames, shared by every lobe and light. Written on
// lanes (common/lanes.h): at AW_LANES = 1 the types are float, float2 and float3 and this is
// the scalar code; at W > 1 each call serves W paths, every choice a select.
#ifndef AW_COMMON_SAMPLING_H
#define AW_COMMON_SAMPLING_H

#include "common/compat.h"
#include "common/lanes.h"

// sin x and cos x for |x| <= pi/4, by the minimax polynomials of Cephes' single-precision
// sinf/cosf for that range (S. L. Moshier 1989, "Methods and Programs for Mathematical
// Functions", Cephes Math Library: sinf.c, its sincof/coscof tables). Measured against double
// precision over 4M points of the range: relative error <= 7.3e-8 (sin), 1.1e-7 (cos), about one
// ulp (tests/lobes/test_diffuse.cpp checks 2.5e-7). Why not sin()/cos(): PoCL's run a
// Payne-Hanek argument reduction on every call (__pocl_argReductionS: 3.3% of the Cornell box's
// render time), which a known quarter-range argument does not need; and these few
// multiply-adds, with contraction off on both sides, round the same on the host and every
// device, where two math libraries differed by an ulp.
AW_FN void sincos_quarter(lfloat x, lfloat* s, lfloat* c) {
  lfloat z = x * x;
  *s = x + x * z * (-1.6666654611e-1f + z * (8.3321608736e-3f + z * -1.9515295891e-4f));
  *c = 1.0f - 0.5f * z + z * z * (4.166664568298827e-2f + z * (-1.388731625493765e-3f + z * 2.443315711809948e-5f));
}

// sin and cos of 2 pi u for u in [0, 1] (a uniformly sampled azimuth), through
// sincos_quarter: 8u splits into an octant o and an exact fraction f (8u is exact, and so is
// 8u - floor(8u)); the angle is q pi/2 + x (o = 2q) or (q + 1) pi/2 - x (o = 2q + 1) with
// x in [0, pi/4], and a quarter turn only swaps and negates. Same reasons as above: no
// argument reduction, the same rounding on every side.
AW_FN void sincos_turn(lfloat u, lfloat* s, lfloat* c) {
  lfloat t = 8.0f * u;
  lfloat o = floor(t);
  lfloat f = t - o;
  lint k = L_TO_INT(o);
  lmask odd = (k & 1) != 0;
  lfloat sx, cx;
  sincos_quarter(L_SEL(odd, 1.0f - f, f) * (M_PI_F / 4.0f), &sx, &cx);
  lfloat a = cx, b = L_SEL(odd, -sx, sx);  // cos and sin of +-x
  // The quarter turns q: (cos, sin) = (a, b), (-b, a), (-a, -b), (b, -a).
  lint q = ((k >> 1) + (k & 1)) & 3;
  *c = L_SEL(q == 0, a, L_SEL(q == 1, -b, L_SEL(q == 2, -a, b)));
  *s = L_SEL(q == 0, b, L_SEL(q == 1, a, L_SEL(q == 2, -b, -a)));
}

// sin x and cos x for |x| < 8192 (a spherical rectangle's angles, lights/lights.h), through
// sincos_quarter: the argument reduced to r = |x| - j pi/4 with j the even multiple nearest
// |x| / (pi/4), |r| <= pi/4, by Cody & Waite's reduction with pi/4 split into three parts of
// which j times the first two are exact (W. J. Cody & W. Waite 1980, "Software Manual for the
// Elementary Functions", Ch. 8; the split of Cephes' sinf.c); then j / 2 quarter turns. Same
// reasons as above: one rounding at every width and on every side, which sin() and cos() do
// not promise. Error against double precision: LaneMath.SinCosIsAccurate.
AW_FN void l_sincos(lfloat x, lfloat* s, lfloat* c) {
  lfloat ax = fabs(x);
  lint j = L_TO_INT(ax * 1.27323954473516f);  // 4 / pi
  j = j + (j & 1);
  lfloat y = L_TO_FLOAT(j);
  lfloat r = ((ax - y * 0.78515625f) - y * 2.4187564849853515625e-4f) - y * 3.77489497744594108e-8f;
  lfloat sr, cr;
  sincos_quarter(r, &sr, &cr);
  lint q = (j >> 1) & 3;  // quarter turns: (sin, cos) = (s, c), (c, -s), (-s, -c), (-c, s)
  lfloat sa = L_SEL(q == 0, sr, L_SEL(q == 1, cr, L_SEL(q == 2, -sr, -cr)));
  *c = L_SEL(q == 0, cr, L_SEL(q == 1, -sr, L_SEL(q == 2, -cr, sr)));
  *s = L_SEL(x < 0.0f, -sa, sa);
}

// Concentric square-to-disk map: Shirley & Chiu 1997, "A Low Distortion Map Between Disk and
// Square", Sec. 3 (in the polar form of Shirley's later note). Keeps strata compact. The angle
// is phi = (pi/4)(b/a) in the wedges |a| > |b|, else pi/2 - (pi/4)(a/b); both are a quarter-range
// angle x = (pi/4) * ratio, and cos(pi/2 - x) = sin x, sin(pi/2 - x) = cos x.
AW_FN lfloat2 sample_concentric_disk(lfloat2 u) {
  lfloat a = 2.0f * u.x - 1.0f;
  lfloat b = 2.0f * u.y - 1.0f;
  lmask wide = fabs(a) > fabs(b);
  lfloat s, c;
  // The ratio of the smaller to the larger coordinate; 0/0 at the centre, which is selected
  // away below.
  sincos_quarter((M_PI_F / 4.0f) * (L_SEL(wide, b, a) / L_SEL(wide, a, b)), &s, &c);
  lmask centre = a == 0.0f && b == 0.0f;
  lfloat x = L_SEL(wide, a * c, b * s), y = L_SEL(wide, a * s, b * c);
  return make_lfloat2(L_SEL(centre, (lfloat)(0.0f), x), L_SEL(centre, (lfloat)(0.0f), y));
}

// Cosine-weighted hemisphere around +z (Malley's method: project the disk up), pdf cos/pi.
AW_FN lfloat3 sample_cosine_hemisphere(lfloat2 u) {
  lfloat2 d = sample_concentric_disk(u);
  lfloat z = l_safe_sqrt(1.0f - d.x * d.x - d.y * d.y);
  return make_lfloat3(d.x, d.y, z);
}

AW_FN lfloat pdf_cosine_hemisphere(lfloat cos_theta) { return fmax(cos_theta, (lfloat)(0.0f)) * (1.0f / M_PI_F); }

// Uniform direction in the cone cos(theta) >= cos_max around +z; pdf 1/(2 pi (1 - cos_max)).
AW_FN lfloat3 sample_uniform_cone(lfloat2 u, lfloat cos_max) {
  lfloat cos_t = 1.0f - u.x * (1.0f - cos_max);
  lfloat sin_t = l_safe_sqrt(1.0f - cos_t * cos_t);
  lfloat sp, cp;
  sincos_turn(u.y, &sp, &cp);  // phi = 2 pi u.y
  return make_lfloat3(cp * sin_t, sp * sin_t, cos_t);
}

// Orthonormal basis from a unit normal without branches on a near-degenerate axis:
// Duff et al. 2017, "Building an Orthonormal Basis, Revisited", JCGT 6(1), Listing 3.
AW_FN void make_frame(lfloat3 n, lfloat3* t, lfloat3* b) {
  lfloat s = copysign((lfloat)(1.0f), n.z);
  lfloat a = -1.0f / (s + n.z);
  lfloat c = n.x * n.y * a;
  *t = make_lfloat3(1.0f + s * n.x * n.x * a, s * c, -s * n.x);
  *b = make_lfloat3(c, s + n.y * n.y * a, -n.y);
}

AW_FN lfloat3 frame_to_world(lfloat3 v, lfloat3 t, lfloat3 b, lfloat3 n) {
  return l3_add(l3_add(l3_scale(t, v.x), l3_scale(b, v.y)), l3_scale(n, v.z));
}
AW_FN lfloat3 frame_to_local(lfloat3 v, lfloat3 t, lfloat3 b, lfloat3 n) {
  return make_lfloat3(l3_dot(v, t), l3_dot(v, b), l3_dot(v, n));
}

// Power heuristic with beta = 2: Veach 1997, "Robust Monte Carlo Methods for Light Transport
// Simulation", Sec. 9.2.4, Eq. 9.13. Written so that an infinite pdf (delta) wins cleanly.
AW_FN lfloat mis_power(lfloat pdf_a, lfloat pdf_b) {
  lfloat a = pdf_a * pdf_a;
  lfloat b = pdf_b * pdf_b;
  lfloat w = L_SEL(isfinite(a), a / (a + b), (lfloat)(1.0f));
  return L_SEL(a + b > 0.0f, w, (lfloat)(0.0f));  // also 0 for a NaN density
}

#endif
