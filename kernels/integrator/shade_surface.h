// From: LOBE + lid / To: RAY or DONE (and SHADOW when a light sample can contribute).
// One shading kernel per lobe queue; they share this function, each calling it with its own
// constant lobe id so the compiler keeps only that lobe's code (the dispatch of
// material/lobes.h folds away). Next-event estimation with MIS against the lobe's own
// sampling, then the lobe's bounce.
#ifndef AW_INTEGRATOR_SHADE_SURFACE_H
#define AW_INTEGRATOR_SHADE_SURFACE_H

#include "common/features.h"
#include "integrator/aov.h"
#include "integrator/light_select.h"
#include "integrator/scene_ref.h"
#include "integrator/shade_common.h"
#include "integrator/shading_material.h"
#include "integrator/split.h"
#include "material/lobes.h"

// Written on lanes (common/lanes.h): at W > 1 for the lobes of AW_LOBE_LIST_ON_LANES
// (material/lobe_list.h), none of which is a reflection or refraction lobe, in a program for
// scenes without AOVs; those parts are one path per call (AW_LANES == 1). Lobe splitting is
// left out at W > 1 too, and that is exact: a split starts only in the stage of a lobe with
// per-lobe `samples` (lobe_split_count is 1 for the others), and no lobe on lanes has them
// (the diffuse lobe's material_diffuse_samples is 0); a split path's later vertices shade as
// any path's.
AW_FN luint shade_surface(PathRef ps, SceneRef sc, const RenderParams* rp, uint lid) {
  lfloat3 p = ps_sp_position(ps);
  lfloat3 ng = ps_sp_geo_normal(ps);
  MatL m = shading_material(ps, sc, rp);
  lfloat3 n = shading_normal_for_lobe(ps, m, lid);
#if AW_LANES == 1
  aov_first_scatter(ps, rp, lid);  // the light groups: everything from here on is this lobe's
  // Per-lobe samples: split this lobe at the first scattering vertex (docs/material.md §6). The
  // snapshot is taken before this stage changes anything, so every split starts here.
  if (rp->split_spp != 0u && PS_U(ps, bounce) == 0u && !(PS_U(ps, flags) & AW_PATH_SPLIT)) {
    uint n_split = lobe_split_count(m, lid, rp->split_spp);
    if (n_split > 1u) {
      if (AW_FEAT_SPLIT) split_begin(ps, n_split);
      else PS_U(ps, flags) |= AW_PATH_MISSING_FEATURE;  // never silently unsplit
    }
  }
#endif
  lmask front = (PS_LU(ps, flags) & AW_PATH_FRONT) != 0u;
  LobeSetup l = lobe_setup(m, lid, front);
  int is_refl = (l.traits & AW_LT_REFLECTION) != 0u;  // the stage's lobe: the same in every lane
  lfloat3 t, b;
#if AW_LANES == 1
  if (is_refl) material_reflection_frame(m, n, ps_sp_tangent(ps), &t, &b);
  else make_frame(n, &t, &b);
#else
  make_frame(n, &t, &b);
#endif
  lfloat3 wo = frame_to_local(l3_neg(ps_ray_dir(ps)), t, b, n);
  lfloat3 lw = ps_lobe_weight(ps);
  // highlight_vs_reflection: scales light reached through a reflection lobe, in both
  // estimators (light sampling here, BSDF sampling via emit_scale), so MIS stays consistent.
  lfloat hvr = l.hvr;
  PS_SET_U(ps, flags, PS_LU(ps, flags) & ~AW_PATH_HAS_SHADOW);

  // Next-event estimation (not for delta lobes: their pdf is 0 for any light direction).
  if (rp->num_lights > 0u) {
    luint light;
    lfloat pdf_light;
    LightSample ls = shade_pick_light(ps, sc, rp, p, &light, &pdf_light);
    lfloat cg = l3_dot(ls.wi, ng);
    int transmit_lobe = (l.traits & AW_LT_TRANSMIT) != 0u;
    lmask toward = pdf_light > 0.0f && (transmit_lobe ? cg < 0.0f : cg > 0.0f);
    if (L_ANY(toward)) {
      lfloat3 wi = frame_to_local(ls.wi, t, b, n);
      lfloat3 f = lobe_eval(&l, wo, wi);
      lmask reach = toward && l3_max3(f) > 0.0f;
      if (L_ANY(reach)) {
        // One-sample estimate of this lobe's share: lw = scale / probability (see
        // classify_hit). Within the lobe, light sampling is MIS-weighted against the lobe's
        // own sampling; classify_hit weighs emission found by the lobe's ray the same way.
        lfloat w = L_SEL(ls.is_delta, (lfloat)(1.0f), mis_power(pdf_light, lobe_pdf(&l, wo, wi)));
        lfloat3 contrib = l3_scale(l3_mul(l3_mul(l3_mul(ps_throughput(ps), lw), f), ls.le), w * hvr / pdf_light);
        lmask emit = reach && l3_max3(contrib) > 0.0f;
        if (L_ANY(emit)) {
          PathRef pe = ps;
          PS_KEEP(pe, emit);
          shade_emit_shadow(pe, p, transmit_lobe ? l3_neg(ng) : ng, ls, light, contrib);
        }
      }
    }
  }

  lfloat2 u = rng_2d(rp_sampler(rp), PS_LU(ps, pixel), PS_LU(ps, sample), PS_LU(ps, bounce), AW_DIM_BSDF);
  LobeSample s = lobe_sample(&l, wo, u);
  s.weight = l3_mul(s.weight, lw);
  s.wi = frame_to_world(s.wi, t, b, n);
  PS_SET_F(ps, emit_scale, hvr);

  lfloat cutoff = (lfloat)(rp->cutoff);
#if AW_LANES == 1
  uint depths = PS_U(ps, depths);
  if (is_refl) {
    cutoff = fmax(cutoff, l.cutoff);
    // Past the reflection depth, or with specular_highlights_only, a reflection returns only
    // highlights: its ray looks for lights and stops at the first surface (docs/material.md §5).
    if ((depths & 0xffffu) >= m->refl_depth || (m->flags & AW_MAT_HIGHLIGHTS_ONLY))
      PS_U(ps, flags) |= AW_PATH_EMITTERS_ONLY;
    else
      PS_U(ps, depths) = depths + 1u;
  } else if (l.traits & AW_LT_REFRACTION) {
    cutoff = fmax(cutoff, l.cutoff);
    PS_U(ps, depths) = depths + 0x10000u;
    // Crossing a foggy object's surface: the path is inside its fog until it leaves. (A
    // totally internally reflected path does not cross.)
    if (!material_is_thin(m) && m->fog_distance > 0.0f && (s.flags & AW_LOBE_TRANSMISSION))
      PS_U(ps, medium) = front ? PS_U(ps, material) : AW_NONE;
  } else
#endif
  if (!rp->gi) {
    // gi off (the documentation's "no GI" examples): no indirect diffuse. The bounce is still
    // traced, but only to find lights (the MIS partner of the light sample above).
    PS_SET_U(ps, flags, PS_LU(ps, flags) | AW_PATH_EMITTERS_ONLY);
  }
  return shade_continue(ps, rp, p, ng, s, cutoff);
}

#endif
