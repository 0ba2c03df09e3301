// Microfacet distributions shared by the reflection and refraction lobes: anisotropic
// Beckmann and GGX (Trowbridge–Reitz) normal distributions, Smith masking (height-correlated
// masking-shadowing), visible-normal sampling, and the glossiness/anisotropy → roughness maps
// of docs/material.md §3.3.
//
// USAGE (local shading frame: +z = normal, x = tangent u, y = bitangent v; wo, wi, h unit
// vectors pointing away from the surface):
//
//   float ax, ay;
//   anisotropic_alphas(glossiness_to_alpha(g), aniso_amount, &ax, &ay);
//   Microfacet m;  m.ax = ax;  m.ay = ay;  m.dist = AW_MF_GGX;     // or AW_MF_BECKMANN
//   if (fmax(m.ax, m.ay) < AW_MF_MIRROR_ALPHA) { /* treat as a delta (mirror / smooth) lobe */ }
//   float3 h  = mf_sample_visible(m, wo, u);          // needs wo.z > 0; h.z > 0, wo.h > 0
//   float  ph = mf_pdf_visible(m, wo, h);              // density of that h (solid angle of h)
//   float  d  = mf_D(m, h);                            // 0 for h.z <= 0
//   float  g2 = mf_G2(m, wo, wi, h);                   // height-correlated, for reflection
//   float  g1 = mf_G1(m, wo, h);
//
// Reflection turns ph into a density of wi with the Jacobian 1 / (4 wo.h) (Walter et al. 2007,
// "Microfacet Models for Refraction through Rough Surfaces", Eq. 14); refraction with Walter's
// Eq. 17. mf_proj_area / mf_proj_excess are the numerically robust building blocks (see below);
// lobes that divide by cos theta use them instead of 1 + Lambda so grazing directions stay
// finite.
//
// Roughness range: every function is finite for alphas in [1e-4, ~3.2] (3.2 = the largest
// anisotropic stretch of alpha = 1) and any unit wo with wo.z > 0, including wo.z -> 0+.
// Functions return 0 (never NaN) outside their support.
#ifndef AW_LOBES_MICROFACET_H
#define AW_LOBES_MICROFACET_H

#include "common/compat.h"
#include "common/features.h"
#include "common/lanes.h"
#include "common/sampling.h"

#define AW_MF_BECKMANN 0u
#define AW_MF_GGX 1u
// Beckmann code exists only in builds with a Beckmann reflection lobe (common/features.h);
// GGX, the default and refraction's distribution, is always built.
#define AW_MF_IS_BECKMANN(m) (AW_FEAT_BRDF_BECKMANN && (m).dist == AW_MF_BECKMANN)

// alpha below this is a perfect mirror / smooth interface: a delta lobe (docs/material.md §3.3).
#define AW_MF_MIRROR_ALPHA 1e-3f
// alpha is never below this (docs/material.md §3.3), also after the anisotropic squeeze.
#define AW_MF_MIN_ALPHA 1e-4f
// Lambda of a direction at or below the horizon: finite, large enough that G = 0 in float.
#define AW_MF_LAMBDA_MAX 1e30f

// On lanes (common/lanes.h) each lane's roughness; at W = 1 plain floats. Written on lanes:
// glossiness_to_alpha and the GGX visible-normal sampler (the energy split of classify_hit on
// lanes draws its microfacet normal); the rest is one path per call (AW_LANES == 1 below).
typedef struct {
  lfloat ax;   // roughness along x (tangent u)
  lfloat ay;   // roughness along y (bitangent v)
  luint dist;  // AW_MF_BECKMANN or AW_MF_GGX
} Microfacet;

/* ----------------------------- roughness from the material -------------------------------- */

// docs/material.md §3.3: r = 1 - glossiness, alpha = r^2 (documented choice; Redshift publishes
// none), clamped to >= 1e-4. Glossiness is clamped to [0, 1]; glossiness 1 gives alpha = 1e-4,
// below AW_MF_MIRROR_ALPHA, i.e. a mirror.
AW_FN lfloat glossiness_to_alpha(lfloat g) {
  lfloat r = 1.0f - clamp(g, 0.0f, 1.0f);
  return fmax(r * r, AW_MF_MIN_ALPHA);
}

#if AW_LANES == 1

// Anisotropy a in [-1, 1] (docs/material.md §1: "<0 stretches along u, >0 along v"; §3.3).
// aspect = sqrt(1 - 0.9 |a|); the STRETCHED axis gets alpha / aspect (rougher: the microfacet
// slopes spread more along it, so highlights and sampled reflections spread along it), the
// other alpha * aspect. Sign convention, as the sentence in docs/material.md §1 says:
//   a < 0: ax (u) = alpha / aspect, ay (v) = alpha * aspect  -> stretched along u
//   a > 0: ax (u) = alpha * aspect, ay (v) = alpha / aspect  -> stretched along v
// (An earlier wording of the specification's formula line wrote alpha_u = alpha / aspect "with
// u and v swapped for a < 0", which read literally stretches along v for a < 0, against its own
// sentence. docs/material.md §3.3 states the convention of the sentence, which this follows;
// tests/lobes/test_microfacet.cpp checks that a < 0 spreads sampled directions more in x than
// in y.) The product ax * ay = alpha^2 is kept, so the highlight's solid angle stays roughly
// constant. Both are clamped to >= 1e-4.
AW_FN void anisotropic_alphas(float alpha, float amount, float* ax, float* ay) {
  float a = clamp(amount, -1.0f, 1.0f);
  float aspect = sqrt(1.0f - 0.9f * fabs(a));
  float wide = alpha / aspect;
  float narrow = alpha * aspect;
  if (a < 0.0f) {
    *ax = fmax(wide, AW_MF_MIN_ALPHA);
    *ay = fmax(narrow, AW_MF_MIN_ALPHA);
  } else {
    *ax = fmax(narrow, AW_MF_MIN_ALPHA);
    *ay = fmax(wide, AW_MF_MIN_ALPHA);
  }
}

/* ----------------------------- special functions (float) -------------------------------- */
// Written here on top of exp/log/sqrt so that host and device round the same way (OpenCL C's
// erf and C++'s std::erf are different implementations, and neither has erfinv).

#define AW_MF_INV_SQRT_PI 0.56418958354775628f

// erfc(x) * exp(x^2) for x >= 0: the rational part of Abramowitz & Stegun 1964, "Handbook of
// Mathematical Functions", formula 7.1.26 (|error of erf| <= 1.5e-7, i.e. float precision).
AW_FN float mf_erfc_scaled_pos(float x) {
  float t = 1.0f / (1.0f + 0.3275911f * x);
  return t * (0.254829592f + t * (-0.284496736f + t * (1.421413741f + t * (-1.453152027f + t * 1.061405429f))));
}

// erf(x) from 7.1.26 (odd extension to x < 0). erf(+-inf) = +-1.
AW_FN float mf_erf(float x) {
  float ax = fabs(x);
  float e = 1.0f - mf_erfc_scaled_pos(ax) * exp(-ax * ax);
  return x < 0.0f ? -e : e;
}

// Inverse error function, single precision: Giles 2010, "Approximating the erfinv function"
// (GPU Computing Gems Jade, Ch. 10), the two-branch polynomial in w = -log(1 - x^2) with the
// paper's single-precision coefficients. The input is clamped to the largest float below 1 in
// magnitude, so the result is finite (|result| <= 3.9).
AW_FN float mf_erfinv(float x) {
  x = clamp(x, -0.99999994f, 0.99999994f);
  float w = -log((1.0f - x) * (1.0f + x));
  float p;
  if (w < 5.0f) {
    w = w - 2.5f;
    p = 2.81022636e-08f;
    p = 3.43273939e-07f + p * w;
    p = -3.5233877e-06f + p * w;
    p = -4.39150654e-06f + p * w;
    p = 0.00021858087f + p * w;
    p = -0.00125372503f + p * w;
    p = -0.00417768164f + p * w;
    p = 0.246640727f + p * w;
    p = 1.50140941f + p * w;
  } else {
    w = sqrt(w) - 3.0f;
    p = -0.000200214257f;
    p = 0.000100950558f + p * w;
    p = 0.00134934322f + p * w;
    p = -0.00367342844f + p * w;
    p = 0.00573950773f + p * w;
    p = -0.0076224613f + p * w;
    p = 0.00943887047f + p * w;
    p = 1.00167406f + p * w;
    p = 2.83297682f + p * w;
  }
  return p * x;
}

/* ----------------------------- distribution D(h) ---------------------------------------- */

// Anisotropic normal distributions, written in the components of h (hx^2 / hz^2 =
// tan^2(theta) cos^2(phi), ...) so that no tan/cos/phi is formed and nothing overflows near
// the horizon:
//  GGX: Walter et al. 2007, Eq. 33 (isotropic), anisotropic form Heitz 2014, "Understanding
//    the Masking-Shadowing Function in Microfacet-Based BRDFs" (JCGT 3(2)), Eq. 85:
//      D = 1 / (pi ax ay cos^4 (1 + tan^2 (cos^2 phi / ax^2 + sin^2 phi / ay^2))^2)
//        = 1 / (pi ax ay (hx^2/ax^2 + hy^2/ay^2 + hz^2)^2)          (multiply out cos^4)
//  Beckmann: Walter et al. 2007, Eq. 25; anisotropic form Heitz 2014, Eq. 84:
//      D = exp(-(hx^2/ax^2 + hy^2/ay^2) / hz^2) / (pi ax ay hz^4)
// D is a density of microfacet normals per solid angle, normalised as integral D(h) h.z = 1.
AW_FN float mf_D(Microfacet m, float3 h) {
  if (!(h.z > 0.0f)) return 0.0f;
  float sx = h.x / m.ax;
  float sy = h.y / m.ay;
  float s2 = sx * sx + sy * sy;  // tan^2(theta) * (cos^2/ax^2 + sin^2/ay^2) * hz^2
  float z2 = h.z * h.z;
  if (AW_MF_IS_BECKMANN(m)) {
    float e = s2 / z2;
    // exp(-80) ~ 2e-35: beyond it D is 0 in float for every alpha in range (and hz^4 could
    // underflow to 0 next to an exp that already did).
    if (!(e < 80.0f)) return 0.0f;
    return exp(-e) / (M_PI_F * m.ax * m.ay * z2 * z2);
  }
  float d = s2 + z2;
  return 1.0f / (M_PI_F * m.ax * m.ay * d * d);
}

/* ----------------------------- Smith masking --------------------------------------------- */

// Projected roughness times sin(theta): A = sqrt(ax^2 wx^2 + ay^2 wy^2) = alpha_0 tan(theta) wz,
// with alpha_0 the anisotropic projected roughness of Heitz 2014, Eq. 80.
AW_FN float mf_projected_roughness_sin(Microfacet m, float3 w) {
  float x = m.ax * w.x;
  float y = m.ay * w.y;
  return sqrt(x * x + y * y);
}

// The projected area of the microsurface seen from w, per unit macro-surface area:
//   P(w) = integral of max(0, w.h) D(h) dh = w.z (1 + Lambda(w))
// (Heitz 2014, Eq. 2 with Smith's G1 = 1 / (1 + Lambda), Eq. 43). Written without dividing by
// w.z, so it is finite and > 0 down to w.z = 0 (where it is the projected area of the facets
// facing a horizontal direction):
//  GGX (Lambda from Heitz 2014, Eq. 72 with alpha_0 of Eq. 80; = Walter 2007, Eq. 34):
//    Lambda = (-1 + sqrt(1 + A^2 / wz^2)) / 2  ->  P = (wz + sqrt(wz^2 + A^2)) / 2
//  Beckmann, EXACT erf form (Walter 2007, Eq. 26 as Lambda = 1/G1 - 1; Heitz 2014, Sec. 5.1),
//  with a = wz / A = 1 / (alpha_0 tan theta):
//    Lambda = (erf(a) - 1) / 2 + exp(-a^2) / (2 a sqrt(pi))
//    ->  P = wz (1 + erf(a)) / 2 + A exp(-a^2) / (2 sqrt(pi))
// The exact form (not Walter's Eq. 27 rational approximation) because the visible-normal
// sampler below inverts the exact CDF: with the approximation, mf_pdf_visible would not be the
// density of mf_sample_visible (up to ~0.35%), which chi-square tests can see.
// mf_proj_excess(w) = P(w) - wz = wz Lambda(w) >= 0, computed without cancellation for GGX.
AW_FN float mf_proj_excess(Microfacet m, float3 w) {
  float wz = fmax(w.z, 0.0f);
  float A = mf_projected_roughness_sin(m, w);
  if (!(A > 0.0f)) return 0.0f;  // normal incidence: no masking
  if (AW_MF_IS_BECKMANN(m)) {
    float a = wz / A;
    // erfc(a) = scaled(a) exp(-a^2): both terms share exp(-a^2).
    float v = exp(-a * a) * (A * (0.5f * AW_MF_INV_SQRT_PI) - 0.5f * wz * mf_erfc_scaled_pos(a));
    return fmax(v, 0.0f);  // 7.1.26's 1e-7 error can push the tiny difference below 0
  }
  return A * A / (2.0f * (sqrt(wz * wz + A * A) + wz));
}

AW_FN float mf_proj_area(Microfacet m, float3 w) { return fmax(w.z, 0.0f) + mf_proj_excess(m, w); }

// Smith's Lambda(w) for w.z > 0 (see mf_proj_area); AW_MF_LAMBDA_MAX at or below the horizon.
AW_FN float mf_lambda(Microfacet m, float3 w) {
  if (!(w.z > 0.0f)) return AW_MF_LAMBDA_MAX;
  return fmin(mf_proj_excess(m, w) / w.z, AW_MF_LAMBDA_MAX);
}

// Smith masking G1(w, h) = chi+(w.h) chi+(w.z) / (1 + Lambda(w))   (Heitz 2014, Eq. 43).
AW_FN float mf_G1(Microfacet m, float3 w, float3 h) {
  if (!(dot(w, h) > 0.0f) || !(w.z > 0.0f)) return 0.0f;
  return 1.0f / (1.0f + mf_lambda(m, w));
}

// Height-correlated masking-shadowing (Heitz 2014, Eq. 99):
//   G2(wo, wi, h) = chi+(wo.h) chi+(wi.h) / (1 + Lambda(wo) + Lambda(wi)).
// For transmission (wi.z < 0, used by refraction.h) wi is flipped to the upper hemisphere:
// Lambda depends only on the slope of the direction, and the visibility test becomes
// wi.h < 0 (wi on the far side of the microfacet). This is the reflection formula applied
// to transmission (as pbrt-v4 does), not Heitz 2014's separate height-correlated
// transmission form; refraction.h states that choice.
AW_FN float mf_G2(Microfacet m, float3 wo, float3 wi, float3 h) {
  if (!(dot(wo, h) > 0.0f) || !(wo.z > 0.0f)) return 0.0f;
  float3 wi_up = wi;
  float ih = dot(wi, h);
  if (wi.z < 0.0f) {
    wi_up = make_float3(-wi.x, -wi.y, -wi.z);
    ih = -ih;
  }
  if (!(ih > 0.0f) || !(wi_up.z > 0.0f)) return 0.0f;
  return 1.0f / (1.0f + mf_lambda(m, wo) + mf_lambda(m, wi_up));
}

/* ----------------------------- visible normals ------------------------------------------- */

// Density of the distribution of visible normals seen from wo, per solid angle of h
// (Heitz & d'Eon 2014, Sec. 3; Heitz 2014, Sec. 2 — normalised by Eq. 2):
//   D_wo(h) = G1(wo, h) max(0, wo.h) D(h) / wo.z = max(0, wo.h) D(h) / P(wo)
// (the second form, with the projected area P = wo.z (1 + Lambda), stays finite as wo.z -> 0).
AW_FN float mf_pdf_visible(Microfacet m, float3 wo, float3 h) {
  float oh = dot(wo, h);
  if (!(oh > 0.0f) || !(wo.z > 0.0f)) return 0.0f;
  float p = mf_proj_area(m, wo);
  if (!(p > 0.0f)) return 0.0f;
  return oh * mf_D(m, h) / p;
}

#endif  // AW_LANES == 1

// GGX: Heitz 2018, "Sampling the GGX Distribution of Visible Normals" (JCGT 7(4)), Sec. 2–4.
// The GGX microsurface is the stretched hemisphere configuration; in the stretched space
// (alpha = 1) the visible normals are uniformly distributed over the projected area of a
// hemisphere seen from the stretched view direction, which is a disk plus a half ellipse:
//  1. stretch wo to the alpha = 1 configuration, v = normalize(ax wo.x, ay wo.y, wo.z);
//  2. a frame (t1, t2, v) around it;
//  3. a uniform point on the unit disk in polar form, (p1, p2') = sqrt(u1) (cos, sin)(2 pi u2),
//     with its t2 coordinate remapped, p2 = (1 - s) c + s p2' with c = sqrt(1 - p1^2) and
//     s = (1 + v.z) / 2, so the half of the disk that is seen through the ellipse is covered;
//  4. lift the point onto the hemisphere along v by sqrt(1 - p1^2 - p2^2);
//  5. unstretch the hemisphere normal (the normal transforms with the inverse: multiply x, y
//     by alpha) and normalise.
// Conditioning (our addition): near the disk's rim 1 - p1^2 - p2^2 is a difference of numbers
// close to 1, and an ulp in sin/cos moved h by up to ~3e-4. Here it is formed from the
// uniform variate without cancellation:
//   c^2 = 1 - p1^2 = (1 - u1) + u1 sin^2,  c^2 - p2'^2 = 1 - r^2 = 1 - u1,
//   1 - p1^2 - p2^2 = (c - p2)(c + p2) = s (c - p2') ((1 - s) 2c + s (c + p2')),
// with c -+ p2' = (1 - u1) / (c +- p2') on the side where the direct difference would cancel.
// Written on lanes: every branch a select per lane; cross and normalize written out
// (common/lanes.h: l3_cross, l3_normalize), so every width rounds alike.
AW_FN lfloat3 mf_sample_visible_ggx(Microfacet m, lfloat3 wo, lfloat2 u) {
  lfloat3 v = l3_normalize(make_lfloat3(m.ax * wo.x, m.ay * wo.y, wo.z));
  lfloat len2 = v.x * v.x + v.y * v.y;
  lfloat3 t1 = l3_sel(len2 > 0.0f, l3_scale(make_lfloat3(-v.y, v.x, (lfloat)(0.0f)), 1.0f / sqrt(len2)),
                      make_lfloat3((lfloat)(1.0f), (lfloat)(0.0f), (lfloat)(0.0f)));
  lfloat3 t2 = l3_cross(v, t1);
  lfloat r = sqrt(u.x);
  lfloat one_m_r2 = 1.0f - u.x;
  lfloat sp, cp;
  sincos_turn(u.y, &sp, &cp);  // phi = 2 pi u.y (common/sampling.h)
  lfloat p1 = r * cp;
  lfloat q = r * sp;  // p2' before the remap
  lfloat c = sqrt(one_m_r2 + u.x * sp * sp);
  // q > 0: c + q directly, c - q from it; otherwise c - q directly, c + q from it.
  lmask q_pos = q > 0.0f;
  lfloat direct = L_SEL(q_pos, c + q, c - q);
  lfloat other = L_SEL(q_pos || direct > 0.0f, one_m_r2 / direct, (lfloat)(0.0f));
  lfloat c_plus_q = L_SEL(q_pos, direct, other);
  lfloat c_minus_q = L_SEL(q_pos, other, direct);
  lfloat s = 0.5f * (1.0f + v.z);
  lfloat p2 = (1.0f - s) * c + s * q;
  lfloat lift = l_safe_sqrt(s * c_minus_q * ((1.0f - s) * 2.0f * c + s * c_plus_q));
  lfloat3 nh = l3_add(l3_add(l3_scale(t1, p1), l3_scale(t2, p2)), l3_scale(v, lift));
  return l3_normalize(make_lfloat3(m.ax * nh.x, m.ay * nh.y, fmax(nh.z, 0.0f)));
}

#if AW_LANES == 1
// Beckmann: the stretch / rotate / sample-slopes / unstretch procedure of Heitz & d'Eon 2014,
// "Importance Sampling Microfacet-Based BSDFs using the Distribution of Visible Normals"
// (EGSR), Sec. 4, with the slope sampling of Jakob 2014, "An Improved Visible Normal Sampling
// Routine for the Beckmann Distribution" (tech. report, ETH Zürich): invert the marginal CDF of
// the visible slope x numerically in the erf domain, then draw the other slope from its
// (Gaussian) conditional.
//
// In the stretched (alpha = 1), rotated frame wo = (sin t, 0, cos t) and mu = cot t. A facet of
// slope (x, y) has normal (-x, -y, 1)/|.|, is visible when x < mu, and the visible slopes have
// density proportional to (mu - x) exp(-x^2 - y^2). The marginal CDF of x is
//   C(x) = mu (1 + erf x) / 2 + exp(-x^2) / (2 sqrt(pi))        (x <= mu), total C(mu).
// With b = erf(x) as the unknown (Jakob's choice: bounded, b in [-1, erf mu]):
//   F(b) = mu (1 + b) / 2 + exp(-x(b)^2) / (2 sqrt(pi)) - u1 C(mu),  x(b) = erfinv(b),
//   F'(b) = (mu - x) / 2  (dx/db = sqrt(pi) exp(x^2) / 2).
// F is increasing and concave in b, so Newton's method converges monotonically; a bisection
// fallback keeps every iterate inside the bracket. The initial guess b0 = -1 + u1 (1 + erf mu)
// is our own (exact as mu -> inf, where x is Gaussian); Jakob's fitted initial guess is not
// reproduced. Given x, y ~ exp(-y^2) / sqrt(pi): y = erfinv(2 u2 - 1).
AW_FN float3 mf_sample_visible_beckmann(Microfacet m, float3 wo, float2 u) {
  float3 v = normalize(make_float3(m.ax * wo.x, m.ay * wo.y, wo.z));
  float sin_t = sqrt(v.x * v.x + v.y * v.y);
  float cos_p = 1.0f, sin_p = 0.0f;
  if (sin_t > 0.0f) {
    cos_p = v.x / sin_t;
    sin_p = v.y / sin_t;
  }
  // mu = cot t; capped at 1e4 (t < 1e-4): the density's (mu - x) factor then differs from the
  // uncapped one by < 4e-4 relative, in a 1e-8-sr cone of directions.
  float mu = fmin(fmax(v.z, 0.0f) / sin_t, 1e4f);
  float total = 0.5f * mu * (1.0f + mf_erf(mu)) + 0.5f * AW_MF_INV_SQRT_PI * exp(-mu * mu);
  float target = u.x * total;
  float lo = -1.0f;
  float hi = mf_erf(mu);
  float b = clamp(-1.0f + u.x * (1.0f + hi), lo, hi);
  float x = mf_erfinv(b);
  for (int it = 0; it < 24; ++it) {
    x = mf_erfinv(b);
    float f = 0.5f * mu * (1.0f + b) + 0.5f * AW_MF_INV_SQRT_PI * exp(-x * x) - target;
    if (fabs(f) <= 1e-6f * total) break;
    if (f > 0.0f) hi = b; else lo = b;
    float d = 0.5f * (mu - x);
    float nb = d > 0.0f ? b - f / d : 0.5f * (lo + hi);
    if (!(nb > lo && nb < hi)) nb = 0.5f * (lo + hi);
    if (nb == b) break;  // bracket exhausted in float
    b = nb;
  }
  x = fmin(mf_erfinv(b), mu);
  float y = mf_erfinv(2.0f * u.y - 1.0f);
  // Rotate back by the azimuth of v, unstretch the slopes (slopes scale with alpha).
  float sx = m.ax * (cos_p * x - sin_p * y);
  float sy = m.ay * (sin_p * x + cos_p * y);
  return normalize(make_float3(-sx, -sy, 1.0f));
}

#endif  // AW_LANES == 1

// A microfacet normal h (h.z >= 0) drawn with density mf_pdf_visible(m, wo, h). Requires
// wo.z > 0 (returns +z otherwise). On lanes GGX only: a lane program is built only for scenes
// without a Beckmann lobe (host/render/wavefront.cpp, build_lanes_program).
AW_FN lfloat3 mf_sample_visible(Microfacet m, lfloat3 wo, lfloat2 u) {
  const lfloat3 up = make_lfloat3((lfloat)(0.0f), (lfloat)(0.0f), (lfloat)(1.0f));
#if AW_LANES == 1
  if (!(wo.z > 0.0f)) return up;
  if (AW_MF_IS_BECKMANN(m)) return mf_sample_visible_beckmann(m, wo, u);
  return mf_sample_visible_ggx(m, wo, u);
#else
  return l3_sel(wo.z > 0.0f, mf_sample_visible_ggx(m, wo, u), up);
#endif
}

#endif  // AW_LOBES_MICROFACET_H
