// The Architectural material at a shading point: how much of the incoming energy each lobe
// gets (MATERIAL.md §2: reflection first, then refraction, then diffuse) and which lobe a
// path takes. The lobes themselves live in kernels/lobes/, one file each.
#ifndef AW_MATERIAL_ARCHITECTURAL_H
#define AW_MATERIAL_ARCHITECTURAL_H

#include "common/compat.h"
#include "common/features.h"
#include "lobes/fresnel.h"
#include "lobes/thin_walled.h"
#include "types/material.h"

// Per-lobe factors at one shading point. `scale` multiplies the lobe's own value (its eval
// and sample weight already contain the lobe's colour and, for reflection, Fresnel at the
// microfacet). `prob` is the probability that classify_hit sends the path to that lobe.
typedef struct {
  float3 scale[AW_LID_COUNT];
  float prob[AW_LID_COUNT];
  float albedo[AW_LID_COUNT];  // luminance of each lobe's estimated contribution
} LobeWeights;

// Relative IOR n_far / n_near for a ray arriving from the `entering` side. Thin walls look
// the same from both sides.
AW_FN float material_eta(float ior, int entering, int thin) {
  return (entering || thin) ? ior : 1.0f / ior;
}

AW_FN FresnelParams material_fresnel(const AW_GLOBAL ReflectionGpu* r, int entering, int thin) {
  FresnelParams f;
  f.mode = r->fresnel_mode;
  f.eta = r->fresnel_mode == AW_FRESNEL_CONDUCTOR ? r->fresnel_ior : material_eta(r->fresnel_ior, entering, thin);
  f.k = r->fresnel_k;
  f.facing = r->facing;
  f.perpendicular = r->perpendicular;
  f.curve = r->curve;
  return f;
}

// Fresnel reflectance at the view angle, as the energy split sees it. Thin walls reflect
// from both faces: R' = R + T^2 R / (1 - R^2) (MATERIAL.md §3, "Thin walled").
AW_FN float material_view_fresnel(const AW_GLOBAL ReflectionGpu* r, float cos_o, int entering, int thin) {
  float f = fresnel_eval(material_fresnel(r, entering, thin), cos_o);
  if (thin && r->fresnel_mode != AW_FRESNEL_CURVE) f = thin_wall_reflectance(f);
  return clamp(f, 0.0f, 1.0f);
}

// MATERIAL.md §2 at view cosine cos_o; `entering` = the ray arrives on the outside of the
// surface (a ray arriving from inside a refractive object is subject to
// skip_weak_internal_reflections).
AW_FN LobeWeights material_lobe_weights(const AW_GLOBAL MaterialGpu* m, float cos_o, int entering) {
  LobeWeights lw;
  int thin = (m->flags & AW_MAT_THIN_WALLED) != 0u;
  int metal = (m->flags & AW_MAT_METAL) != 0u;
  float3 diffuse = load_f3(m->diffuse_color);
  float3 zero = make_float3(0.0f, 0.0f, 0.0f);

  // Reflection: rho1 = weight * color * F1(theta_o) (x diffuse colour when metal).
  float3 rho1 = zero, rho2 = zero;
  float f1 = 0.0f, f2 = 0.0f, lum1 = 0.0f, lum2 = 0.0f, keep2 = 1.0f;
#if AW_FEAT_REFLECTION
  float3 tint1 = load_f3(m->refl[0].color);
  if (metal) tint1 = tint1 * diffuse;
  f1 = m->refl[0].weight > 0.0f ? material_view_fresnel(&m->refl[0], cos_o, entering, thin) : 0.0f;
  rho1 = m->refl[0].weight * f1 * tint1;
  lum1 = fmin(1.0f, luminance(rho1));
  // Reflection 2 gets what reflection 1 leaves.
  f2 = m->refl[1].weight > 0.0f ? material_view_fresnel(&m->refl[1], cos_o, entering, thin) : 0.0f;
  keep2 = 1.0f - lum1;
  rho2 = m->refl[1].weight * f2 * keep2 * load_f3(m->refl[1].color);
  lum2 = luminance(rho2);
#endif
  // Whatever reflection leaves is transmitted (refraction, translucency) or diffuse.
  float rest = 1.0f - fmin(1.0f, lum1 + lum2);
  float w_t = m->refr_weight * rest;
#if AW_FEAT_TRANSLUCENCY
  float w_transl = (m->flags & AW_MAT_TRANSLUCENCY) ? w_t * m->transl_weight : 0.0f;
#else
  float w_transl = 0.0f;
#endif
  float w_refr = w_t - w_transl;
  float w_d = rest;
#if AW_FEAT_REFRACTION || AW_FEAT_TRANSLUCENCY
  w_d *= (1.0f - m->refr_weight * luminance(load_f3(m->refr_color)));
#else
  w_refr = 0.0f;
#endif
  if (metal) w_d *= (1.0f - lum1);

  // Skip weak internal reflections: inside a refractive object, partial reflections are not
  // traced (total internal reflection, f = 1, still is). Biased by design: an optimisation.
  int inside_refr = !entering && !thin && m->refr_weight > 0.0f;
  if (inside_refr && (m->flags & AW_MAT_SKIP_WEAK_INTERNAL)) {
    if (f1 < 1.0f) rho1 = zero;
    if (f2 < 1.0f) rho2 = zero;
  }

  lw.scale[AW_LID_DIFFUSE] = make_float3(w_d, w_d, w_d);
  lw.scale[AW_LID_TRANSLUCENCY] = make_float3(w_transl, w_transl, w_transl);
  // The reflection lobes carry tint and Fresnel themselves; scale is the rest of rho.
  float s1 = luminance(rho1) > 0.0f ? m->refl[0].weight : 0.0f;
  float s2 = luminance(rho2) > 0.0f ? m->refl[1].weight * keep2 : 0.0f;
  lw.scale[AW_LID_REFLECTION] = make_float3(s1, s1, s1);
  lw.scale[AW_LID_REFLECTION2] = make_float3(s2, s2, s2);
  lw.scale[AW_LID_REFRACTION] = w_refr * load_f3(m->refr_color);

  // Selection in proportion to each lobe's estimated contribution.
  lw.albedo[AW_LID_DIFFUSE] = w_d * luminance(diffuse);
  lw.albedo[AW_LID_TRANSLUCENCY] = w_transl * luminance(load_f3(m->transl_color));
  lw.albedo[AW_LID_REFLECTION] = luminance(rho1);
  lw.albedo[AW_LID_REFLECTION2] = luminance(rho2);
  lw.albedo[AW_LID_REFRACTION] = luminance(lw.scale[AW_LID_REFRACTION]);
  float total = 0.0f;
  for (uint i = 0; i < AW_LID_COUNT; ++i) {
    lw.albedo[i] = fmax(lw.albedo[i], 0.0f);
    total += lw.albedo[i];
  }
  for (uint i = 0; i < AW_LID_COUNT; ++i) lw.prob[i] = total > 0.0f ? lw.albedo[i] / total : 0.0f;
  return lw;
}

AW_FN int positive3(const AW_GLOBAL float* c) { return c[0] > 0.0f || c[1] > 0.0f || c[2] > 0.0f; }

// The features material m uses, as AW_FEATBIT_* bits. The one definition of "uses": the host
// ORs it over the scene's materials to choose what to compile (host/render/features.cpp) and
// every hit checks it against the build, so a specialised build can never silently render a
// material differently.
AW_FN uint material_features(const AW_GLOBAL MaterialGpu* m) {
  int refl = (m->refl[0].weight > 0.0f && positive3(m->refl[0].color)) ||
             (m->refl[1].weight > 0.0f && positive3(m->refl[1].color));
  int transmit = m->refr_weight > 0.0f;
  int transl = transmit && (m->flags & AW_MAT_TRANSLUCENCY) && m->transl_weight > 0.0f;
  int refr = transmit && !(transl && m->transl_weight >= 1.0f);
  uint f = 0u;
  if (transl) f |= AW_FEATBIT_TRANSLUCENCY;
  if (refl) f |= AW_FEATBIT_REFLECTION;
  if (refr) f |= AW_FEATBIT_REFRACTION;
  if (m->diffuse_roughness > 0.0f) f |= AW_FEATBIT_ROUGH_DIFFUSE;
  if (refl && m->aniso_amount != 0.0f) f |= AW_FEATBIT_ANISOTROPY;
  if (refr && m->fog_distance > 0.0f) f |= AW_FEATBIT_FOG;
  if (m->cutout_opacity < 0.5f) f |= AW_FEATBIT_CUTOUT;
  if (positive3(m->incandescent)) f |= AW_FEATBIT_INCANDESCENCE;
  return f;
}

AW_FN int material_uses_missing_feature(const AW_GLOBAL MaterialGpu* m) {
  return (material_features(m) & ~(uint)(AW_FEAT_COMPILED_MATERIAL_MASK)) != 0u;
}

// Whether this build contains the shading kernel of lobe `lid` (kernels/common/features.h).
AW_FN int lobe_compiled(uint lid) {
  if (lid == AW_LID_TRANSLUCENCY) return AW_FEAT_TRANSLUCENCY;
  if (lid == AW_LID_REFLECTION || lid == AW_LID_REFLECTION2) return AW_FEAT_REFLECTION;
  if (lid == AW_LID_REFRACTION) return AW_FEAT_REFRACTION;
  return 1;
}

// Picks a lobe with probability prob[]; returns AW_LID_COUNT when no lobe has weight.
AW_FN uint material_pick_lobe(const LobeWeights* lw, float u) {
  float acc = 0.0f;
  uint last = AW_LID_COUNT;
  for (uint i = 0; i < AW_LID_COUNT; ++i) {
    if (!(lw->prob[i] > 0.0f)) continue;
    acc += lw->prob[i];
    last = i;
    if (u < acc) return i;
  }
  return last;  // round-off: the last lobe with weight
}

#endif
