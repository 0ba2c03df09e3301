// From: LOBE + lid / To: RAY or DONE (and SHADOW when a light sample can contribute).
// One shading kernel per lobe queue; they share this function, each calling it with its own
// constant lobe id so the compiler keeps only that lobe's code (the switch folds away).
// Next-event estimation with MIS against the lobe's own sampling, then the lobe's bounce.
#ifndef AW_INTEGRATOR_SHADE_SURFACE_H
#define AW_INTEGRATOR_SHADE_SURFACE_H

#include "integrator/shade_common.h"
#include "integrator/split.h"
#include "lobes/diffuse.h"
#include "lobes/reflection.h"
#include "lobes/refraction.h"
#include "lobes/thin_walled.h"
#include "lobes/translucency.h"
#include "material/architectural.h"

// Everything a lobe needs at this shading point, built once per stage invocation.
typedef struct {
  uint lid;
  float3 color;     // diffuse albedo / translucency colour
  float roughness;  // diffuse
  ReflectionParams refl;
  RefractionParams refr;
  int thin;         // thin-walled refraction: straight through, blurred when frosted
  float glossiness; // of the thin wall
} LobeSetup;

AW_FN LobeSetup lobe_setup(const AW_GLOBAL MaterialGpu* m, uint lid, int front) {
  LobeSetup l;
  l.lid = lid;
  l.color = make_float3(0.0f, 0.0f, 0.0f);
  l.roughness = 0.0f;
  l.thin = 0;
  l.glossiness = 1.0f;
  int thin = material_is_thin(m);
  if (lid == AW_LID_DIFFUSE) {
    l.color = load_f3(m->diffuse_color);
#if AW_FEAT_ROUGH_DIFFUSE
    l.roughness = m->diffuse_roughness;
#endif
  } else if (lid == AW_LID_TRANSLUCENCY) {
    l.color = load_f3(m->transl_color);
  }
#if AW_FEAT_REFLECTION
  else if (lid == AW_LID_REFLECTION || lid == AW_LID_REFLECTION2) {
    l.refl = material_reflection_params(m, lid == AW_LID_REFLECTION ? 0u : 1u, front);
  }
#endif
#if AW_FEAT_REFRACTION
  else if (lid == AW_LID_REFRACTION) {
    // Refraction: a rough dielectric interface (GGX), or a thin wall (no bending).
    l.refr = refraction_params(m->refr_glossiness, AW_MF_GGX, material_eta(m->refr_ior, front, 0));
    l.thin = thin;
    // MATERIAL.md §1: glossiness has no effect when IOR = 1 (a frosted pane of IOR 1 is clear).
    l.glossiness = refraction_is_pass_through(m->refr_ior) ? 1.0f : m->refr_glossiness;
  }
#endif
  return l;
}

// Dispatch on the lobe id (a constant in each shading kernel, so the branches fold away);
// lobes compiled out of a specialised build are never dispatched to (classify_hit checks).
AW_FN float3 lobe_eval(const LobeSetup* l, float3 wo, float3 wi) {
#if AW_FEAT_TRANSLUCENCY
  if (l->lid == AW_LID_TRANSLUCENCY) return lobe_translucency_eval(l->color, wo, wi);
#endif
#if AW_FEAT_REFRACTION
  if (l->lid == AW_LID_REFRACTION)
    return l->thin ? lobe_thin_transmission_eval(l->glossiness, wo, wi) : lobe_refraction_eval(l->refr, wo, wi);
#endif
#if AW_FEAT_REFLECTION
  if (l->lid == AW_LID_REFLECTION || l->lid == AW_LID_REFLECTION2) return lobe_reflection_eval(l->refl, wo, wi);
#endif
  return lobe_diffuse_eval(l->color, l->roughness, wo, wi);
}

AW_FN float lobe_pdf(const LobeSetup* l, float3 wo, float3 wi) {
#if AW_FEAT_TRANSLUCENCY
  if (l->lid == AW_LID_TRANSLUCENCY) return lobe_translucency_pdf(wo, wi);
#endif
#if AW_FEAT_REFRACTION
  if (l->lid == AW_LID_REFRACTION)
    return l->thin ? lobe_thin_transmission_pdf(l->glossiness, wo, wi) : lobe_refraction_pdf(l->refr, wo, wi);
#endif
#if AW_FEAT_REFLECTION
  if (l->lid == AW_LID_REFLECTION || l->lid == AW_LID_REFLECTION2) return lobe_reflection_pdf(l->refl, wo, wi);
#endif
  return lobe_diffuse_pdf(l->roughness, wo, wi);
}

AW_FN LobeSample lobe_sample(const LobeSetup* l, float3 wo, float2 u) {
#if AW_FEAT_TRANSLUCENCY
  if (l->lid == AW_LID_TRANSLUCENCY) return lobe_translucency_sample(l->color, wo, u);
#endif
#if AW_FEAT_REFRACTION
  if (l->lid == AW_LID_REFRACTION) {
    if (l->thin) return lobe_thin_transmission_sample(l->glossiness, wo, u);
    LobeSample s = lobe_refraction_sample(l->refr, wo, u);
    // Total internal reflection: no refracted direction exists, so the energy the split gave
    // to refraction is reflected, specularly (MATERIAL.md §3: "total internal reflection is
    // handled"). Rough interfaces lose the share of microfacets that reflect totally (the
    // furnace stays <= 1, kernels/lobes/refraction.h).
    if (s.flags == 0u && refraction_is_delta(l->refr) && refraction_cos_t(wo.z, l->refr.eta) < 0.0f) {
      s.wi = make_float3(-wo.x, -wo.y, wo.z);
      s.weight = make_float3(1.0f, 1.0f, 1.0f);
      s.pdf = 1.0f;
      s.flags = AW_LOBE_SPECULAR | AW_LOBE_REFLECTION;
    }
    return s;
  }
#endif
#if AW_FEAT_REFLECTION
  if (l->lid == AW_LID_REFLECTION || l->lid == AW_LID_REFLECTION2) return lobe_reflection_sample(l->refl, wo, u);
#endif
  return lobe_diffuse_sample(l->color, l->roughness, wo, u);
}

AW_FN int shade_surface(PathRef ps, SceneRef sc, const RenderParams* rp, uint lid) {
  float3 p = ps_sp_position(ps);
  float3 n = ps_sp_normal(ps);
  float3 ng = ps_sp_geo_normal(ps);
  const AW_GLOBAL MaterialGpu* m = &sc.materials[PS_U(ps, material)];
  // Per-lobe samples: split this lobe at the first scattering vertex (MATERIAL.md §6). The
  // snapshot is taken before this stage changes anything, so every split starts here.
  if (rp->split_spp != 0u && PS_U(ps, bounce) == 0u && !(PS_U(ps, flags) & AW_PATH_SPLIT)) {
    uint n_split = lobe_split_count(m, lid, rp->split_spp);
#if AW_FEAT_SPLIT
    if (n_split > 1u) split_begin(ps, n_split);
#else
    if (n_split > 1u) PS_U(ps, flags) |= AW_PATH_MISSING_FEATURE;  // never silently unsplit
#endif
  }
  int front = (PS_U(ps, flags) & AW_PATH_FRONT) != 0u;
  float3 t, b;
  if (lid == AW_LID_REFLECTION || lid == AW_LID_REFLECTION2) material_reflection_frame(m, n, ps_sp_tangent(ps), &t, &b);
  else make_frame(n, &t, &b);
  float3 wo = frame_to_local(-ps_ray_dir(ps), t, b, n);
  LobeSetup l = lobe_setup(m, lid, front);
  float3 lw = ps_lobe_weight(ps);
  int is_refl = lid == AW_LID_REFLECTION || lid == AW_LID_REFLECTION2;
  // highlight_vs_reflection: scales light reached through a reflection lobe, in both
  // estimators (light sampling here, BSDF sampling via emit_scale), so MIS stays consistent.
  float hvr = is_refl ? m->highlight_vs_reflection : 1.0f;
  PS_U(ps, flags) &= ~AW_PATH_HAS_SHADOW;

  // Next-event estimation (not for delta lobes: their pdf is 0 for any light direction).
  if (rp->num_lights > 0u) {
    uint light;
    float pdf_light;
    LightSample ls = shade_pick_light(ps, sc, rp, p, &light, &pdf_light);
    float cg = dot(ls.wi, ng);
    int transmit_lobe = lid == AW_LID_TRANSLUCENCY || lid == AW_LID_REFRACTION;
    if (pdf_light > 0.0f && (transmit_lobe ? cg < 0.0f : cg > 0.0f)) {
      float3 wi = frame_to_local(ls.wi, t, b, n);
      float3 f = lobe_eval(&l, wo, wi);
      if (max3(f) > 0.0f) {
        // One-sample estimate of this lobe's share: lw = scale / probability (see
        // classify_hit). Within the lobe, light sampling is MIS-weighted against the lobe's
        // own sampling; classify_hit weighs emission found by the lobe's ray the same way.
        float w = ls.is_delta ? 1.0f : mis_power(pdf_light, lobe_pdf(&l, wo, wi));
        float3 contrib = ps_throughput(ps) * lw * f * ls.le * (w * hvr / pdf_light);
        if (max3(contrib) > 0.0f) shade_emit_shadow(ps, p, transmit_lobe ? -ng : ng, ls, light, contrib);
      }
    }
  }

  float2 u = rng_2d(rp->seed, PS_U(ps, pixel), PS_U(ps, sample), PS_U(ps, bounce), AW_DIM_BSDF);
  LobeSample s = lobe_sample(&l, wo, u);
  s.weight = s.weight * lw;
  s.wi = frame_to_world(s.wi, t, b, n);
  PS_F(ps, emit_scale) = hvr;

  float cutoff = rp->cutoff;
  uint depths = PS_U(ps, depths);
  if (is_refl) {
    cutoff = fmax(cutoff, m->refl[lid == AW_LID_REFLECTION ? 0 : 1].cutoff);
    // Past the reflection depth, or with specular_highlights_only, a reflection returns only
    // highlights: its ray looks for lights and stops at the first surface (MATERIAL.md §5).
    if ((depths & 0xffffu) >= m->refl_depth || (m->flags & AW_MAT_HIGHLIGHTS_ONLY))
      PS_U(ps, flags) |= AW_PATH_EMITTERS_ONLY;
    else
      PS_U(ps, depths) = depths + 1u;
  } else if (lid == AW_LID_REFRACTION) {
    cutoff = fmax(cutoff, m->refr_cutoff);
    PS_U(ps, depths) = depths + 0x10000u;
    // Crossing a foggy object's surface: the path is inside its fog until it leaves. (A
    // totally internally reflected path does not cross.)
    if (!material_is_thin(m) && m->fog_distance > 0.0f && (s.flags & AW_LOBE_TRANSMISSION))
      PS_U(ps, medium) = front ? PS_U(ps, material) : AW_NONE;
  } else if (!rp->gi) {
    // gi off (the documentation's "no GI" examples): no indirect diffuse. The bounce is still
    // traced, but only to find lights (the MIS partner of the light sample above).
    PS_U(ps, flags) |= AW_PATH_EMITTERS_ONLY;
  }
  return shade_continue(ps, rp, p, ng, s, cutoff);
}

#endif
