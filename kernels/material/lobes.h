// Each lobe of the Architectural material as the shading stage uses it: what it reads from the
// material (its binding), and the dispatch from a lobe id to the lobe, generated from the one
// lobe list (material/lobe_list.h). The lobes' physics lives in kernels/lobes/, one file each,
// written against the lobe contract (lobes/lobe.h); the bindings here only translate the
// material's parameters into each lobe's own.
//
// A binding is six functions, named after the list's `name`:
//   material_<name>_setup(LobeSetup* l, m, front)   fills the lobe's fields of l
//   material_<name>_eval(l, wo, wi)                 the lobe's eval (lobe contract)
//   material_<name>_pdf(l, wo, wi)                  its pdf
//   material_<name>_sample(l, wo, u)                its sample
//   material_<name>_samples(m)                      its per-lobe `samples` (0: none), docs/material.md §6
//   material_<name>_present(m)                      whether material m can choose it at all
#ifndef AW_MATERIAL_LOBES_H
#define AW_MATERIAL_LOBES_H

#include "lobes/diffuse.h"
#include "material/architectural.h"
#include "material/lobe_list.h"
#if AW_LANES == 1
#include "lobes/reflection.h"
#include "lobes/refraction.h"
#include "lobes/thin_walled.h"
#include "lobes/translucency.h"
#endif

// Written on lanes (common/lanes.h) for the lobes of AW_LOBE_LIST_ON_LANES (material/
// lobe_list.h): at W > 1 the dispatch below has only those, and the other lobes' bindings are
// left out.
#if AW_LANES == 1
#define AW_LOBE_LIST_HERE AW_LOBE_LIST
#else
#define AW_LOBE_LIST_HERE AW_LOBE_LIST_ON_LANES
#endif

// Everything a lobe needs at this shading point, built once per stage invocation.
typedef struct {
  uint lid;
  uint traits;       // AW_LT_* (material/lobe_list.h)
  lfloat3 color;     // diffuse albedo / translucency colour
  lfloat roughness;  // diffuse
#if AW_LANES == 1
  ReflectionParams refl;
  RefractionParams refr;
#endif
  lmask thin;         // thin-walled refraction: straight through, blurred when frosted
  lfloat glossiness;  // of the thin wall
  lfloat hvr;         // highlight_vs_reflection: scales light reached through the lobe (1 = none)
  lfloat cutoff;      // the lobe's own cut-off threshold (docs/material.md §5), 0 = none
} LobeSetup;

/* ------------------------------------ diffuse ------------------------------------------- */

AW_FN void material_diffuse_setup(LobeSetup* l, MatL m, lmask front) {
  l->color = material_diffuse_color(m);
  if (AW_FEAT_ROUGH_DIFFUSE) l->roughness = MAT_F(m, diffuse_roughness);
}
AW_FN lfloat3 material_diffuse_eval(const LobeSetup* l, lfloat3 wo, lfloat3 wi) {
  return lobe_diffuse_eval(l->color, l->roughness, wo, wi);
}
AW_FN lfloat material_diffuse_pdf(const LobeSetup* l, lfloat3 wo, lfloat3 wi) { return lobe_diffuse_pdf(l->roughness, wo, wi); }
AW_FN LobeSample material_diffuse_sample(const LobeSetup* l, lfloat3 wo, lfloat2 u) {
  return lobe_diffuse_sample(l->color, l->roughness, wo, u);
}
#if AW_LANES == 1
AW_FN uint material_diffuse_samples(const AW_GLOBAL MaterialGpu* m) { return 0u; }
AW_FN int material_diffuse_present(const AW_GLOBAL MaterialGpu* m) { return 1; }

/* ---------------------------------- translucency ---------------------------------------- */

AW_FN void material_translucency_setup(LobeSetup* l, const AW_GLOBAL MaterialGpu* m, int front) {
  l->color = load_f3(m->transl_color);
}
AW_FN float3 material_translucency_eval(const LobeSetup* l, float3 wo, float3 wi) {
  return lobe_translucency_eval(l->color, wo, wi);
}
AW_FN float material_translucency_pdf(const LobeSetup* l, float3 wo, float3 wi) { return lobe_translucency_pdf(wo, wi); }
AW_FN LobeSample material_translucency_sample(const LobeSetup* l, float3 wo, float2 u) {
  return lobe_translucency_sample(l->color, wo, u);
}
AW_FN uint material_translucency_samples(const AW_GLOBAL MaterialGpu* m) { return 0u; }
AW_FN int material_translucency_present(const AW_GLOBAL MaterialGpu* m) {
  return (material_features(m) & (uint)AW_FEATBIT_TRANSLUCENCY) != 0u;
}

/* ------------------------ reflection (i = 0) and reflection2 (i = 1) --------------------- */

AW_FN void material_reflection_i_setup(LobeSetup* l, const AW_GLOBAL MaterialGpu* m, uint i, int front) {
  l->refl = material_reflection_params(m, i, front);
  l->hvr = m->highlight_vs_reflection;
  l->cutoff = m->refl[i].cutoff;
}
AW_FN float3 material_reflection_i_eval(const LobeSetup* l, float3 wo, float3 wi) { return lobe_reflection_eval(l->refl, wo, wi); }
AW_FN float material_reflection_i_pdf(const LobeSetup* l, float3 wo, float3 wi) { return lobe_reflection_pdf(l->refl, wo, wi); }
AW_FN LobeSample material_reflection_i_sample(const LobeSetup* l, float3 wo, float2 u) {
  return lobe_reflection_sample(l->refl, wo, u);
}

// The two reflection lobes' bindings differ only in the lobe index i.
#define AW_REFLECTION_BINDING(name, i)                                                                  \
  AW_FN void material_##name##_setup(LobeSetup* l, const AW_GLOBAL MaterialGpu* m, int front) {        \
    material_reflection_i_setup(l, m, (i), front);                                                     \
  }                                                                                                    \
  AW_FN float3 material_##name##_eval(const LobeSetup* l, float3 wo, float3 wi) {                      \
    return material_reflection_i_eval(l, wo, wi);                                                      \
  }                                                                                                    \
  AW_FN float material_##name##_pdf(const LobeSetup* l, float3 wo, float3 wi) {                        \
    return material_reflection_i_pdf(l, wo, wi);                                                       \
  }                                                                                                    \
  AW_FN LobeSample material_##name##_sample(const LobeSetup* l, float3 wo, float2 u) {                 \
    return material_reflection_i_sample(l, wo, u);                                                     \
  }                                                                                                    \
  AW_FN uint material_##name##_samples(const AW_GLOBAL MaterialGpu* m) { return m->refl[(i)].samples; } \
  AW_FN int material_##name##_present(const AW_GLOBAL MaterialGpu* m) { return material_reflection_used(m, (i)); }
AW_REFLECTION_BINDING(reflection, 0u)
AW_REFLECTION_BINDING(reflection2, 1u)
#undef AW_REFLECTION_BINDING

/* ----------------------------------- refraction ----------------------------------------- */

AW_FN void material_refraction_setup(LobeSetup* l, const AW_GLOBAL MaterialGpu* m, int front) {
  // A rough dielectric interface (GGX), or a thin wall (no bending).
  l->refr = refraction_params(m->refr_glossiness, AW_MF_GGX, material_eta(m->refr_ior, front, 0));
  l->thin = material_is_thin(m);
  // docs/material.md §1: glossiness has no effect when IOR = 1 (a frosted pane of IOR 1 is clear).
  l->glossiness = refraction_is_pass_through(m->refr_ior) ? 1.0f : m->refr_glossiness;
  l->cutoff = m->refr_cutoff;
}
AW_FN float3 material_refraction_eval(const LobeSetup* l, float3 wo, float3 wi) {
  return l->thin ? lobe_thin_transmission_eval(l->glossiness, wo, wi) : lobe_refraction_eval(l->refr, wo, wi);
}
AW_FN float material_refraction_pdf(const LobeSetup* l, float3 wo, float3 wi) {
  return l->thin ? lobe_thin_transmission_pdf(l->glossiness, wo, wi) : lobe_refraction_pdf(l->refr, wo, wi);
}
AW_FN LobeSample material_refraction_sample(const LobeSetup* l, float3 wo, float2 u) {
  if (l->thin) return lobe_thin_transmission_sample(l->glossiness, wo, u);
  LobeSample s = lobe_refraction_sample(l->refr, wo, u);
  // Total internal reflection: no refracted direction exists, so the energy the split gave
  // to refraction is reflected, specularly (docs/material.md §3.5: "total internal reflection
  // is handled"). Rough interfaces lose the share of microfacets that reflect totally (the
  // furnace stays <= 1, kernels/lobes/refraction.h).
  if (s.flags == 0u && refraction_is_delta(l->refr) && refraction_cos_t(wo.z, l->refr.eta) < 0.0f) {
    s.wi = make_float3(-wo.x, -wo.y, wo.z);
    s.weight = make_float3(1.0f, 1.0f, 1.0f);
    s.pdf = 1.0f;
    s.flags = AW_LOBE_SPECULAR | AW_LOBE_REFLECTION;
  }
  return s;
}
AW_FN uint material_refraction_samples(const AW_GLOBAL MaterialGpu* m) { return m->refr_samples; }
AW_FN int material_refraction_present(const AW_GLOBAL MaterialGpu* m) {
  return (material_features(m) & (uint)AW_FEATBIT_REFRACTION) != 0u;
}

#endif  // AW_LANES == 1: the lobes not yet on lanes

/* ------------------------- the dispatch, generated from the list ------------------------ */
// In each shading kernel lid is a constant, so every branch but its own folds away; a lobe
// that the build lacks (AW_FEAT_<FEATURE> = 0) is never reached (classify_hit checks) and
// compiles out everywhere.

// (lid is the stage's, the same in every lane.)
AW_FN LobeSetup lobe_setup(MatL m, uint lid, lmask front) {
  LobeSetup l;
  l.lid = lid;
  l.traits = lobe_traits(lid);
  l.color = l3_splat((lfloat)(0.0f));
  l.roughness = (lfloat)(0.0f);
  l.thin = (lmask)(0);
  l.glossiness = (lfloat)(1.0f);
  l.hvr = (lfloat)(1.0f);
  l.cutoff = (lfloat)(0.0f);
#define AW_LOBE_SETUP(ID, name, FEATURE, TRAITS) \
  if (AW_FEAT_##FEATURE && lid == (uint)AW_LID_##ID) material_##name##_setup(&l, m, front);
  AW_LOBE_LIST_HERE(AW_LOBE_SETUP)
#undef AW_LOBE_SETUP
  return l;
}

AW_FN lfloat3 lobe_eval(const LobeSetup* l, lfloat3 wo, lfloat3 wi) {
#define AW_LOBE_EVAL(ID, name, FEATURE, TRAITS) \
  if (AW_FEAT_##FEATURE && l->lid == (uint)AW_LID_##ID) return material_##name##_eval(l, wo, wi);
  AW_LOBE_LIST_HERE(AW_LOBE_EVAL)
#undef AW_LOBE_EVAL
  return l3_splat((lfloat)(0.0f));
}

AW_FN lfloat lobe_pdf(const LobeSetup* l, lfloat3 wo, lfloat3 wi) {
#define AW_LOBE_PDF(ID, name, FEATURE, TRAITS) \
  if (AW_FEAT_##FEATURE && l->lid == (uint)AW_LID_##ID) return material_##name##_pdf(l, wo, wi);
  AW_LOBE_LIST_HERE(AW_LOBE_PDF)
#undef AW_LOBE_PDF
  return (lfloat)(0.0f);
}

AW_FN LobeSample lobe_sample(const LobeSetup* l, lfloat3 wo, lfloat2 u) {
#define AW_LOBE_SAMPLE(ID, name, FEATURE, TRAITS) \
  if (AW_FEAT_##FEATURE && l->lid == (uint)AW_LID_##ID) return material_##name##_sample(l, wo, u);
  AW_LOBE_LIST_HERE(AW_LOBE_SAMPLE)
#undef AW_LOBE_SAMPLE
  return lobe_no_sample();
}

#if AW_LANES == 1

// The per-lobe `samples` of lobe `lid` of material m (0 for lobes without the parameter).
AW_FN uint lobe_samples(const AW_GLOBAL MaterialGpu* m, uint lid) {
#define AW_LOBE_SAMPLES(ID, name, FEATURE, TRAITS) \
  if (lid == (uint)AW_LID_##ID) return material_##name##_samples(m);
  AW_LOBE_LIST(AW_LOBE_SAMPLES)
#undef AW_LOBE_SAMPLES
  return 0u;
}

// Whether material m can choose lobe `lid` (it carries energy there).
AW_FN int lobe_present(const AW_GLOBAL MaterialGpu* m, uint lid) {
#define AW_LOBE_PRESENT(ID, name, FEATURE, TRAITS) \
  if (lid == (uint)AW_LID_##ID) return material_##name##_present(m);
  AW_LOBE_LIST(AW_LOBE_PRESENT)
#undef AW_LOBE_PRESENT
  return 0;
}

#endif  // AW_LANES == 1: lobe_samples, lobe_present

#endif
