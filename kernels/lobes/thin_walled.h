// Thin walls (docs/material.md §3.6 "Thin walled"): a pane with two parallel faces and no
// thickness. Light is not bent (it leaves the pane parallel to how it entered) and the
// reflectance counts the inter-reflections between the two faces.
//
// Reflectance and transmittance of the pane. With R the single-interface Fresnel reflectance
// and T = 1 - R (no absorption inside), the rays bouncing between the faces form geometric
// series (pbrt-v4, Sec. 9.5.1 "Thin Dielectric BSDF"; Stokes' relations for a plate):
//   R' = R + T^2 R (1 + R^2 + R^4 + ...) = R + T^2 R / (1 - R^2)
//   T' = T^2 (1 + R^2 + R^4 + ...)       = T^2 / (1 - R^2)
// With T = 1 - R these simplify (divide by 1 - R^2 = (1 - R)(1 + R)) to
//   R' = 2R / (1 + R),   T' = (1 - R) / (1 + R),   R' + T' = 1,   R' >= R,
// which are the forms evaluated below: finite at R = 1 where the series form is 0/0.
// The material gives R' to the reflection lobe (in place of F) and T' to this lobe.
//
// Transmission lobe. Clear (glossiness effectively 1): a delta lobe wi = -wo, weight 1 (no
// radiance scaling: the ray leaves into the medium it came from). Frosted: the straight-
// through direction is blurred by a GGX microfacet lobe. A microfacet reflection about a
// visible normal h of wo (Heitz 2018, "Sampling the GGX Distribution of Visible Normals",
// JCGT 7(4)) gives w_r in the upper hemisphere; mirroring it through the tangent plane,
// wi = (w_r.x, w_r.y, -w_r.z), gives a lobe around -wo (for a smooth surface w_r is the
// mirror direction of wo, and its mirror image is exactly -wo). eval and pdf are those of
// the Fresnel-free GGX reflection lobe at w_r = flip(wi) (Walter et al. 2007, Eq. 20 without
// F, and Eq. 14 for the reflection Jacobian 1 / (4 |wo.h|)):
//   eval = D(h) G2(wo, w_r) / (4 wo.z)          (= f |cos theta_i|, |wi.z| = w_r.z)
//   pdf  = pdf_visible(wo, h) / (4 (wo.h)),     h = normalize(wo + w_r)
// and the weight eval/pdf = G2 / G1(wo) <= 1. The mirror map is an isometry of the sphere, so
// the density is carried over unchanged and chi-square holds. Caller's frame: wo.z > 0 (+z on
// the side of wo); the transmitted wi has wi.z < 0.
#ifndef AW_LOBES_THIN_WALLED_H
#define AW_LOBES_THIN_WALLED_H

#include "common/compat.h"
#include "lobes/fresnel.h"  // thin_wall_reflectance
#include "lobes/lobe.h"
#include "lobes/microfacet.h"

// T' = 1 - R' of the pane (no absorption): T^2 / (1 - R^2) = (1 - R) / (1 + R).
AW_FN float thin_wall_transmittance(float R) {
  R = clamp(R, 0.0f, 1.0f);
  return (1.0f - R) / (1.0f + R);
}

// The blur of a frosted pane: isotropic GGX with the material's glossiness mapping.
AW_FN Microfacet thin_wall_microfacet(float glossiness) {
  Microfacet m;
  float a = glossiness_to_alpha(glossiness);
  m.ax = a;
  m.ay = a;
  m.dist = AW_MF_GGX;
  return m;
}

AW_FN int thin_wall_is_delta(float glossiness) {
  Microfacet m = thin_wall_microfacet(glossiness);
  return m.ax < AW_MF_MIRROR_ALPHA;
}

// Mirror image through the tangent plane (z -> -z): the map between the reflection lobe and
// the transmitted one.
AW_FN float3 thin_wall_flip(float3 w) { return make_float3(w.x, w.y, -w.z); }

AW_FN float3 lobe_thin_transmission_eval(float glossiness, float3 wo, float3 wi) {
  float3 zero = make_float3(0.0f, 0.0f, 0.0f);
  if (thin_wall_is_delta(glossiness)) return zero;
  if (!(wo.z > 0.0f) || !(wi.z < 0.0f)) return zero;
  Microfacet m = thin_wall_microfacet(glossiness);
  float3 wr = thin_wall_flip(wi);
  float3 hv = wo + wr;
  float len = length(hv);
  if (!(len > 0.0f)) return zero;
  float3 h = hv / len;
  // G2 / wo.z = 1 / (P(wo) + wo.z Lambda(w_r)) with the projected area P(wo) = wo.z (1 +
  // Lambda(wo)): finite as wo.z -> 0 (see refraction_g2_over_cos_o in refraction.h).
  float den = mf_proj_area(m, wo) + wo.z * mf_lambda(m, wr);
  if (!(den > 0.0f)) return zero;
  float f = mf_D(m, h) / (4.0f * den);
  if (!(f > 0.0f) || !isfinite(f)) return zero;
  return make_float3(f, f, f);
}

AW_FN float lobe_thin_transmission_pdf(float glossiness, float3 wo, float3 wi) {
  if (thin_wall_is_delta(glossiness)) return 0.0f;
  if (!(wo.z > 0.0f) || !(wi.z < 0.0f)) return 0.0f;
  Microfacet m = thin_wall_microfacet(glossiness);
  float3 wr = thin_wall_flip(wi);
  float3 hv = wo + wr;
  float len = length(hv);
  if (!(len > 0.0f)) return 0.0f;
  float3 h = hv / len;
  float cos_oh = dot(wo, h);
  if (!(cos_oh > 0.0f)) return 0.0f;
  float pdf = mf_pdf_visible(m, wo, h) / (4.0f * cos_oh);
  return (pdf > 0.0f && isfinite(pdf)) ? pdf : 0.0f;
}

AW_FN LobeSample lobe_thin_transmission_sample(float glossiness, float3 wo, float2 u) {
  LobeSample s = lobe_no_sample();
  s.wi = make_float3(0.0f, 0.0f, -1.0f);
  s.weight = make_float3(0.0f, 0.0f, 0.0f);
  s.pdf = 0.0f;
  s.flags = 0u;
  if (!(wo.z > 0.0f)) return s;
  if (thin_wall_is_delta(glossiness)) {
    s.wi = -wo;
    s.weight = make_float3(1.0f, 1.0f, 1.0f);
    s.pdf = 1.0f;  // probability mass of the only direction; delta is told by the flag
    s.flags = AW_LOBE_SPECULAR | AW_LOBE_TRANSMISSION;
    return s;
  }
  Microfacet m = thin_wall_microfacet(glossiness);
  float3 h = mf_sample_visible(m, wo, u);
  float cos_oh = dot(wo, h);
  if (!(cos_oh > 0.0f)) return s;
  float3 wr = 2.0f * cos_oh * h - wo;  // reflection about h
  if (!(wr.z > 0.0f)) return s;        // reflected below the surface: shadowed, no sample
  float3 wi = thin_wall_flip(wr);
  float pdf = lobe_thin_transmission_pdf(glossiness, wo, wi);
  float3 f = lobe_thin_transmission_eval(glossiness, wo, wi);
  if (!(pdf > 0.0f) || !(f.x > 0.0f)) return s;
  float w = f.x / pdf;
  if (!isfinite(w)) return s;
  s.wi = wi;
  s.weight = make_float3(w, w, w);
  s.pdf = pdf;
  s.flags = AW_LOBE_GLOSSY | AW_LOBE_TRANSMISSION;
  return s;
}

#endif
