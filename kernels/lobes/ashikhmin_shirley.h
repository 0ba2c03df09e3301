// Ashikhmin–Shirley specular lobe: Ashikhmin & Shirley 2000, "An Anisotropic Phong BRDF
// Model", JGT 5(2), the specular term (their Eq. 4) and its half-vector sampling (Sec. 3).
// Local frame: +z = normal, x = tangent u, y = bitangent v; wo, wi point away from the surface.
//
//   rho_s(k1, k2) = sqrt((nu + 1)(nv + 1)) / (8 pi)
//                   * (n.h)^((nu (h.u)^2 + nv (h.v)^2) / (1 - (n.h)^2))
//                   / ((h.k) max(n.k1, n.k2)) * F(h.k)
//
// with h the half vector and k either direction (h.k1 = h.k2). Note the normalisation is the
// SQUARE ROOT of (nu + 1)(nv + 1) over 8 pi: it comes from the half-vector density
//   p_h(h) = sqrt((nu + 1)(nv + 1)) / (2 pi) (n.h)^(nu cos^2 phi + nv sin^2 phi),
// which integrates to 1 over the hemisphere, and rho_s = p_h F / (4 (h.k) max(n.k1, n.k2)).
// The max() makes the BRDF symmetric in k1, k2 (reciprocal) and bounds the albedo by the
// Fresnel factor: the sampling weight rho_s cos(theta_i) / pdf is F cos_i / max(cos_i, cos_o)
// <= F. Fresnel: FresnelParams at the half-vector angle h.k (docs/material.md §3.3, §3.4:
// microfacet angle), in place of the paper's Schlick approximation.
//
// Exponents. From the roughness alpha of docs/material.md §3.3: n = 2 / alpha^2 - 2 (so alpha = 1
// gives n = 0, a cosine-power lobe of the half vector with exponent 0), clamped to
// [0, AW_AS_MAX_EXPONENT]. Anisotropy acts on alpha first (anisotropic_alphas), so nu belongs
// to the u (x) axis, nv to v (y): a larger nu makes the lobe NARROWER along u.
//
// Legacy ("ashikhmin_shirley_legacy"). Redshift documents only that this variant keeps the
// non-linear glossiness fall-off of version-1.0 materials; it publishes no formula. Our
// documented choice: the exponent doubles with every 1/21 of glossiness,
//     n_legacy(g) = 2^(21 g) - 1,
// so n = 0 at g = 0 (same as the current mapping) and n = 2^21 - 1 ~ 2.1e6 at g = 1, just past
// AW_AS_MAX_EXPONENT (~2e6), i.e. glossiness 1 is the mirror in both mappings. The highlight's
// angular width ~ 1/sqrt(n) then shrinks EXPONENTIALLY in g (by 2^(-10.5 g)), the classic
// "exponent slider" behaviour, whereas the current mapping (alpha = (1 - g)^2) narrows it
// polynomially. Mid glossiness is therefore much sharper in the legacy variant (g = 0.5:
// n ~ 1447 vs 30). The legacy exponent is converted to the equivalent alpha,
// alpha = sqrt(2 / (n + 2)), so anisotropy and the mirror threshold work as for every brdf.
//
// Delta. Exponents at or beyond AW_AS_MAX_EXPONENT (= the exponent of alpha =
// AW_MF_MIRROR_ALPHA) in BOTH axes make the lobe a perfect mirror (ashikhmin_is_delta); eval and pdf
// are 0 then and the reflection lobe samples the mirror direction. A single axis beyond it
// (strong anisotropy) is clamped to it.
#ifndef AW_LOBES_ASHIKHMIN_SHIRLEY_H
#define AW_LOBES_ASHIKHMIN_SHIRLEY_H

#include "common/compat.h"
#include "lobes/fresnel.h"
#include "lobes/lobe.h"
#include "lobes/microfacet.h"

// 2 / AW_MF_MIRROR_ALPHA^2 - 2: the exponent of the mirror threshold.
#define AW_AS_MAX_EXPONENT 1999998.0f

typedef struct {
  float3 tint;
  float nu;  // exponent along u (x)
  float nv;  // exponent along v (y)
  FresnelParams fresnel;
} AshikhminShirleyParams;

// n = 2 / alpha^2 - 2 (docs/material.md §3.3), clamped to [0, AW_AS_MAX_EXPONENT].
AW_FN float ashikhmin_exponent_from_alpha(float alpha) {
  float a = fmax(alpha, AW_MF_MIN_ALPHA);
  return clamp(2.0f / (a * a) - 2.0f, 0.0f, AW_AS_MAX_EXPONENT);
}

// The legacy glossiness mapping (see the top of this file), returned as the equivalent alpha
// sqrt(2 / (n + 2)) with n = 2^(21 g) - 1, i.e. alpha = sqrt(2 / (2^(21 g) + 1)).
AW_FN float ashikhmin_legacy_alpha(float glossiness) {
  float g = clamp(glossiness, 0.0f, 1.0f);
  float n1 = exp(21.0f * 0.69314718f * g);  // n + 1 = 2^(21 g)
  return sqrt(2.0f / (n1 + 1.0f));
}

// Exponents for roughness alpha and anisotropy amount; a mirror (alpha < AW_MF_MIRROR_ALPHA)
// gets AW_AS_MAX_EXPONENT in both axes, so ashikhmin_is_delta() holds exactly when alpha is below
// the threshold, as for GGX and Beckmann.
AW_FN void ashikhmin_exponents(float alpha, float aniso_amount, float* nu, float* nv) {
  if (alpha < AW_MF_MIRROR_ALPHA) {
    *nu = AW_AS_MAX_EXPONENT;
    *nv = AW_AS_MAX_EXPONENT;
    return;
  }
  float au, av;
  anisotropic_alphas(alpha, aniso_amount, &au, &av);
  *nu = ashikhmin_exponent_from_alpha(au);
  *nv = ashikhmin_exponent_from_alpha(av);
}

AW_FN int ashikhmin_is_delta(float nu, float nv) { return fmin(nu, nv) >= AW_AS_MAX_EXPONENT; }

// log(1 - s) / s for s in [0, 1): the series -(1 + s/2 + s^2/3 + s^3/4 + s^4/5) below 0.01
// (truncation < 2e-11), where 1 - s in float would lose the digits that matter for exponents
// up to 2e6.
AW_FN float ashikhmin_log1m_over(float s) {
  if (s < 0.01f) return -(1.0f + s * (0.5f + s * (1.0f / 3.0f + s * (0.25f + s * 0.2f))));
  return log(1.0f - s) / s;
}

// exp(x) - 1 without cancellation for small |x| (series below 1e-3, error < x^4 / 24).
AW_FN float ashikhmin_expm1(float x) {
  if (fabs(x) < 1e-3f) return x * (1.0f + x * (0.5f + x * (1.0f / 6.0f)));
  return exp(x) - 1.0f;
}

// p_h(h) = sqrt((nu+1)(nv+1)) / (2 pi) (n.h)^((nu hx^2 + nv hy^2) / (hx^2 + hy^2))  (Sec. 3).
// The power is evaluated as exp(0.5 (nu hx^2 + nv hy^2) log(1 - s) / s), s = hx^2 + hy^2
// = 1 - hz^2, which is exact to float precision even when hz rounds to 1 and n is 2e6.
AW_FN float ashikhmin_half_vector_pdf(float nu, float nv, float3 h) {
  if (!(h.z > 0.0f)) return 0.0f;
  float x2 = h.x * h.x;
  float y2 = h.y * h.y;
  float s = x2 + y2;
  if (!(s < 1.0f)) return 0.0f;
  float q = nu * x2 + nv * y2;
  float power = q > 0.0f ? exp(0.5f * q * ashikhmin_log1m_over(s)) : 1.0f;
  return sqrt((nu + 1.0f) * (nv + 1.0f)) * (0.5f / M_PI_F) * power;
}

// f * cos(theta_i) for a glossy (non-delta) lobe; 0 below the surface or for a delta lobe.
AW_FN float3 lobe_ashikhmin_shirley_eval(AshikhminShirleyParams p, float3 wo, float3 wi) {
  float3 zero = make_float3(0.0f, 0.0f, 0.0f);
  float3 h;
  if (ashikhmin_is_delta(p.nu, p.nv) || !reflection_half_vector(wo, wi, &h)) return zero;
  float oh = dot(wo, h);
  if (!(oh > 0.0f)) return zero;
  float ph = ashikhmin_half_vector_pdf(p.nu, p.nv, h);
  float F = fresnel_eval(p.fresnel, oh);
  float f = ph * F / (4.0f * oh * fmax(wo.z, wi.z));  // = rho_s (Eq. 4)
  float v = f * wi.z;
  if (!(v > 0.0f) || !isfinite(v)) return zero;
  return p.tint * v;
}

// Solid-angle density of lobe_ashikhmin_shirley_sample: p_h(h) / (4 wo.h) (Sec. 3, the
// half-vector to reflected-direction Jacobian). Integrates to less than 1 where sampled half
// vectors reflect wo below the horizon (those samples fail).
AW_FN float lobe_ashikhmin_shirley_pdf(AshikhminShirleyParams p, float3 wo, float3 wi) {
  float3 h;
  if (ashikhmin_is_delta(p.nu, p.nv) || !reflection_half_vector(wo, wi, &h)) return 0.0f;
  float oh = dot(wo, h);
  if (!(oh > 0.0f)) return 0.0f;
  float pdf = ashikhmin_half_vector_pdf(p.nu, p.nv, h) / (4.0f * oh);
  return (pdf > 0.0f && isfinite(pdf)) ? pdf : 0.0f;
}

// Half-vector sampling (Sec. 3): in the first quadrant
//   phi = atan(sqrt((nu + 1) / (nv + 1)) tan(pi u1' / 2)),
//   cos(theta_h) = (1 - u2)^(1 / (nu cos^2 phi + nv sin^2 phi + 1)),
// with u1 split into four quadrants (the paper's remapping: phi, pi - phi, pi + phi,
// 2 pi - phi; p_h is symmetric under both reflections). Written with atan2-free components:
// (cos phi, sin phi) ~ (sqrt(nv + 1) cos(pi u1'/2), sqrt(nu + 1) sin(pi u1'/2)) normalised,
// which is the same angle and never forms tan(pi / 2). u2 is used in place of 1 - u2 (same
// distribution), and sin^2(theta_h) = -expm1(2 log(u2) / (e + 1)) keeps sin(theta_h) accurate
// for the 1e6-scale exponents where cos(theta_h) rounds to 1. The sample fails when wo.h <= 0
// or the reflected direction is not above the surface.
AW_FN float3 ashikhmin_sample_half_vector(float nu, float nv, float2 u) {
  float q = floor(4.0f * u.x);
  q = clamp(q, 0.0f, 3.0f);
  float t = 4.0f * u.x - q;  // u1' in [0, 1)
  float ang = 0.5f * M_PI_F * t;
  float a = sqrt(nu + 1.0f) * sin(ang);
  float b = sqrt(nv + 1.0f) * cos(ang);
  float r = sqrt(a * a + b * b);
  float cp = b / r;
  float sp = a / r;
  if (q == 1.0f || q == 2.0f) cp = -cp;  // pi - phi, pi + phi
  if (q >= 2.0f) sp = -sp;               // pi + phi, 2 pi - phi
  float e = nu * cp * cp + nv * sp * sp;
  float lt = log(u.y) / (e + 1.0f);  // log cos(theta_h); -inf at u2 = 0 (h on the horizon)
  float cos_t = exp(lt);
  float sin_t = safe_sqrt(-ashikhmin_expm1(2.0f * lt));
  return make_float3(sin_t * cp, sin_t * sp, cos_t);
}

// One exit: every failure folds into `ok`. Written with early returns, Intel's CPU OpenCL
// compiler (2026.2) returned failed samples for valid ones in a probe of 1,728 records (436 of
// the 864 Ashikhmin–Shirley ones), with its optimiser only (-cl-opt-disable was right, as were
// PoCL and the host); this form is right on all three. Found by Reflection.HostMatchesDevice@intel
// (docs/devices.md#known-problems-of-intels-runtime).
AW_FN LobeSample lobe_ashikhmin_shirley_sample(AshikhminShirleyParams p, float3 wo, float2 u) {
  LobeSample s = lobe_no_sample();
  int ok = wo.z > 0.0f && !ashikhmin_is_delta(p.nu, p.nv);
  float3 hs = ashikhmin_sample_half_vector(p.nu, p.nv, u);
  float oh_s = dot(wo, hs);
  ok = ok && oh_s > 0.0f;
  float3 wi = normalize(2.0f * oh_s * hs - wo);
  ok = ok && wi.z > 0.0f;
  // pdf and weight from the half vector of (wo, wi), as eval and pdf compute it, so that
  // weight == eval / pdf and pdf == lobe_ashikhmin_shirley_pdf(wo, wi) to rounding.
  float3 h = make_float3(0.0f, 0.0f, 1.0f);
  ok = ok && reflection_half_vector(wo, wi, &h);
  float oh = dot(wo, h);
  float pdf = oh > 0.0f ? ashikhmin_half_vector_pdf(p.nu, p.nv, h) / (4.0f * oh) : 0.0f;
  ok = ok && pdf > 0.0f && isfinite(pdf);
  // weight = rho_s wi.z / pdf = F wi.z / max(wo.z, wi.z)
  // (a zero Fresnel factor gives a valid sample of weight 0, not a failure: the pdf is not 0)
  float w = fresnel_eval(p.fresnel, oh) * wi.z / fmax(wo.z, wi.z);
  ok = ok && w >= 0.0f && isfinite(w);
  if (ok) {
    s.wi = wi;
    s.weight = p.tint * w;
    s.pdf = pdf;
    s.flags = AW_LOBE_GLOSSY | AW_LOBE_REFLECTION;
  }
  return s;
}

#endif  // AW_LOBES_ASHIKHMIN_SHIRLEY_H
