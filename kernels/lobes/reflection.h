// The reflection lobe of the Architectural material (docs/material.md §3.3 "Reflection"), used by
// both `reflection` and `reflection2`: a microfacet BRDF with the chosen distribution
// (Beckmann, GGX) or the Ashikhmin–Shirley model (current and legacy glossiness mapping),
// anisotropic, with Fresnel evaluated at the microfacet angle. Contract: kernels/lobes/lobe.h
// (local frame, +z = normal, x = u, y = v; eval = f |cos theta_i|; solid-angle pdf; sample
// weight = eval / pdf).
//
// Beckmann / GGX: the Cook–Torrance form of Walter et al. 2007, Eq. 20,
//   f(wo, wi) = F(wo.h) D(h) G2(wo, wi, h) / (4 wo.z wi.z),   h = normalize(wo + wi),
// with the height-correlated G2 = 1 / (1 + Lambda(wo) + Lambda(wi)) (Heitz 2014, Eq. 99) and
// sampling of the visible normals of wo (Heitz 2018 for GGX, Jakob 2014 for Beckmann; see
// microfacet.h). With the projected areas P(w) = w.z + E(w), E(w) = w.z Lambda(w)
// (mf_proj_excess), the terms are rewritten so that nothing divides by a cosine:
//   eval   = f wi.z = F D wi.z / (4 (wo.z wi.z + E(wo) wi.z + E(wi) wo.z))
//   pdf    = D_wo(h) / (4 wo.h) = D(h) / (4 P(wo))      (Jacobian: Walter 2007, Eq. 14)
//   weight = eval / pdf = F wi.z P(wo) / (wo.z wi.z + E(wo) wi.z + E(wi) wo.z) = F G2 / G1(wo)
// so grazing directions (wo.z -> 0+) give finite values and D's 1e7 range never reaches the
// sample weight. Both wo.z > 0 and wi.z > 0 are required; otherwise eval = pdf = 0.
//
// Delta: roughness below AW_MF_MIRROR_ALPHA (or Ashikhmin–Shirley exponents at the matching
// maximum, see ashikhmin_shirley.h) is a perfect mirror: eval = pdf = 0, sample returns
// wi = (-wo.x, -wo.y, wo.z) with weight tint F(wo.z) and pdf 1 (a convention: integrators
// recognise delta samples by AW_LOBE_SPECULAR, never by the pdf value).
#ifndef AW_LOBES_REFLECTION_H
#define AW_LOBES_REFLECTION_H

#include "common/compat.h"
#include "lobes/ashikhmin_shirley.h"
#include "lobes/fresnel.h"
#include "lobes/lobe.h"
#include "lobes/microfacet.h"

// The BRDFs (AW_BRDF_*) are the values of ReflectionGpu.brdf: types/material.h.
#include "types/material.h"

// Density reported for a delta sample (the probability mass of the only direction).
#define AW_REFLECTION_DELTA_PDF 1.0f

typedef struct {
  float3 tint;         // reflection colour (times weight/metal tint as the material decides)
  Microfacet mf;       // Beckmann / GGX roughness (also filled for Ashikhmin–Shirley)
  uint brdf;           // AW_BRDF_*
  float as_nu;         // Ashikhmin–Shirley exponent along u (x); only for the AS brdfs
  float as_nv;         // ... along v (y)
  FresnelParams fresnel;
} ReflectionParams;

// Glossiness -> roughness (docs/material.md §3.3: alpha = (1 - g)^2, >= 1e-4; the legacy AS
// mapping of ashikhmin_shirley.h for AW_BRDF_ASHIKHMIN_SHIRLEY_LEGACY), then anisotropy
// (anisotropic_alphas: amount < 0 stretches along u, > 0 along v), then for the AS brdfs the
// exponents n = 2 / alpha^2 - 2. Roughness below AW_MF_MIRROR_ALPHA makes a mirror for every
// brdf (anisotropy has no effect on a mirror). An unknown brdf id is treated as GGX.
AW_FN ReflectionParams reflection_params_make(float3 tint, uint brdf, float glossiness, float aniso_amount,
                                              FresnelParams f) {
  ReflectionParams p;
  p.tint = tint;
  p.brdf = brdf;
  p.fresnel = f;
  float alpha = (AW_FEAT_BRDF_AS && brdf == AW_BRDF_ASHIKHMIN_SHIRLEY_LEGACY) ? ashikhmin_legacy_alpha(glossiness)
                                                                              : glossiness_to_alpha(glossiness);
  p.mf.dist = brdf == AW_BRDF_BECKMANN ? AW_MF_BECKMANN : AW_MF_GGX;
  if (alpha < AW_MF_MIRROR_ALPHA) {
    p.mf.ax = alpha;
    p.mf.ay = alpha;
  } else {
    anisotropic_alphas(alpha, aniso_amount, &p.mf.ax, &p.mf.ay);
  }
  ashikhmin_exponents(alpha, aniso_amount, &p.as_nu, &p.as_nv);
  return p;
}

// Builds without an Ashikhmin–Shirley lobe (common/features.h) compile its code out here.
AW_FN int reflection_is_as(ReflectionParams p) {
  return AW_FEAT_BRDF_AS && (p.brdf == AW_BRDF_ASHIKHMIN_SHIRLEY || p.brdf == AW_BRDF_ASHIKHMIN_SHIRLEY_LEGACY);
}

AW_FN int reflection_is_delta(ReflectionParams p) {
  if (reflection_is_as(p)) return ashikhmin_is_delta(p.as_nu, p.as_nv);
  return fmax(p.mf.ax, p.mf.ay) < AW_MF_MIRROR_ALPHA;
}

AW_FN AshikhminShirleyParams reflection_as_params(ReflectionParams p) {
  AshikhminShirleyParams a;
  a.tint = p.tint;
  a.nu = p.as_nu;
  a.nv = p.as_nv;
  a.fresnel = p.fresnel;
  return a;
}

AW_FN uint reflection_flags(ReflectionParams p) {
  return reflection_is_delta(p) ? (AW_LOBE_SPECULAR | AW_LOBE_REFLECTION) : (AW_LOBE_GLOSSY | AW_LOBE_REFLECTION);
}

/* ------------------------------- Beckmann / GGX ------------------------------------------ */

// wo.z wi.z (1 + Lambda(wo) + Lambda(wi)) = wo.z wi.z / G2, from the projected-area excesses.
AW_FN float reflection_mf_g2_denominator(Microfacet m, float3 wo, float3 wi) {
  return wo.z * wi.z + mf_proj_excess(m, wo) * wi.z + mf_proj_excess(m, wi) * wo.z;
}

AW_FN float reflection_mf_eval(ReflectionParams p, float3 wo, float3 wi) {
  float3 h;
  if (!reflection_half_vector(wo, wi, &h)) return 0.0f;
  float oh = dot(wo, h);
  if (!(oh > 0.0f)) return 0.0f;
  float den = 4.0f * reflection_mf_g2_denominator(p.mf, wo, wi);
  if (!(den > 0.0f)) return 0.0f;
  float v = fresnel_eval(p.fresnel, oh) * mf_D(p.mf, h) * wi.z / den;
  return (v > 0.0f && isfinite(v)) ? v : 0.0f;
}

// pdf = D_wo(h) / (4 wo.h) = D(h) / (4 P(wo))  (mf_pdf_visible with Walter 2007, Eq. 14).
AW_FN float reflection_mf_pdf(ReflectionParams p, float3 wo, float3 wi) {
  float3 h;
  if (!reflection_half_vector(wo, wi, &h)) return 0.0f;
  if (!(dot(wo, h) > 0.0f)) return 0.0f;
  float pa = mf_proj_area(p.mf, wo);
  if (!(pa > 0.0f)) return 0.0f;
  float pdf = mf_D(p.mf, h) / (4.0f * pa);
  return (pdf > 0.0f && isfinite(pdf)) ? pdf : 0.0f;
}

AW_FN LobeSample reflection_mf_sample(ReflectionParams p, float3 wo, float2 u) {
  LobeSample s = lobe_no_sample();
  if (!(wo.z > 0.0f)) return s;
  float3 hs = mf_sample_visible(p.mf, wo, u);
  float oh_s = dot(wo, hs);
  if (!(oh_s > 0.0f)) return s;
  float3 wi = normalize(2.0f * oh_s * hs - wo);  // mirror wo about the microfacet
  if (!(wi.z > 0.0f)) return s;                  // reflected below the surface: lost
  // pdf and weight from the half vector of (wo, wi), exactly as eval and pdf compute them, so
  // that sample.pdf == pdf(wo, wi) and weight == eval / pdf to rounding.
  float pdf = reflection_mf_pdf(p, wo, wi);
  if (!(pdf > 0.0f)) return s;
  float3 h = normalize(wo + wi);
  float den = reflection_mf_g2_denominator(p.mf, wo, wi);
  float w = fresnel_eval(p.fresnel, dot(wo, h)) * wi.z * mf_proj_area(p.mf, wo) / den;
  if (!(den > 0.0f) || !(w >= 0.0f) || !isfinite(w)) return s;
  s.wi = wi;
  s.weight = p.tint * w;
  s.pdf = pdf;
  s.flags = AW_LOBE_GLOSSY | AW_LOBE_REFLECTION;
  return s;
}

/* ------------------------------- the lobe ------------------------------------------------ */

// The microfacet normal that lobe_reflection_sample draws from random numbers u (its first
// step; the surface normal for the mirror): the material's energy split evaluates Fresnel at
// it, so that the split and the sampled lobe see the same reflectance (architectural.h).
AW_FN float3 reflection_sample_normal(ReflectionParams p, float3 wo, float2 u) {
  if (reflection_is_delta(p)) return make_float3(0.0f, 0.0f, 1.0f);
  if (reflection_is_as(p)) return ashikhmin_sample_half_vector(p.as_nu, p.as_nv, u);
  return mf_sample_visible(p.mf, wo, u);
}

AW_FN float3 lobe_reflection_eval(ReflectionParams p, float3 wo, float3 wi) {
  if (reflection_is_delta(p)) return make_float3(0.0f, 0.0f, 0.0f);
  if (reflection_is_as(p)) return lobe_ashikhmin_shirley_eval(reflection_as_params(p), wo, wi);
  return p.tint * reflection_mf_eval(p, wo, wi);
}

AW_FN float lobe_reflection_pdf(ReflectionParams p, float3 wo, float3 wi) {
  if (reflection_is_delta(p)) return 0.0f;
  if (reflection_is_as(p)) return lobe_ashikhmin_shirley_pdf(reflection_as_params(p), wo, wi);
  return reflection_mf_pdf(p, wo, wi);
}

AW_FN LobeSample lobe_reflection_sample(ReflectionParams p, float3 wo, float2 u) {
  if (reflection_is_delta(p)) {
    LobeSample s = lobe_no_sample();
    if (!(wo.z > 0.0f)) return s;
    s.wi = make_float3(-wo.x, -wo.y, wo.z);
    s.weight = p.tint * fresnel_eval(p.fresnel, wo.z);
    s.pdf = AW_REFLECTION_DELTA_PDF;
    s.flags = AW_LOBE_SPECULAR | AW_LOBE_REFLECTION;
    return s;
  }
  if (reflection_is_as(p)) return lobe_ashikhmin_shirley_sample(reflection_as_params(p), wo, u);
  return reflection_mf_sample(p, wo, u);
}

// An ESTIMATE of the directional albedo, for lobe-selection weights (docs/material.md §2):
// tint F(cos_o), the Fresnel reflectance at the VIEW angle times the tint. Exact for the mirror;
// for rough lobes it ignores the energy lost to masking and to reflections below the horizon
// and takes F at the view angle rather than at the microfacet angles, so it is typically an
// over-estimate at grazing angles. For choosing lobes, not for energy bookkeeping.
AW_FN float3 lobe_reflection_albedo_estimate(ReflectionParams p, float cos_o) {
  return p.tint * fresnel_eval(p.fresnel, clamp(cos_o, 0.0f, 1.0f));
}

#endif  // AW_LOBES_REFLECTION_H
