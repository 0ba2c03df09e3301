// From: SHADOW / To: nowhere (the path's next queue was set by its lobe stage; a path in
// SHADOW is also in that queue). An unoccluded shadow ray adds its light sample to the path.
#ifndef AW_INTEGRATOR_INTERSECT_SHADOW_H
#define AW_INTEGRATOR_INTERSECT_SHADOW_H

#include "common/features.h"
#include "integrator/path_state.h"
#include "integrator/ray_cast.h"
#include "integrator/light_select.h"

// Cutout surfaces (opacity < 0.5) are not there for shadow rays either (docs/material.md §1):
// shadow rays step through them with closest-hit queries, at most this many layers (beyond
// that the ray counts as blocked).
#define AW_SHADOW_CUTOUT_STEPS 32

AW_FN int surface_is_cutout(SceneRef sc, uint prim) {
  return sc.materials[sc.tri_info[prim].material].cutout_opacity < 0.5f;
}

AW_FN float3 ps_shadow_origin(PathRef ps) { return make_float3(PS_F(ps, sh_ox), PS_F(ps, sh_oy), PS_F(ps, sh_oz)); }
AW_FN float3 ps_shadow_dir(PathRef ps) { return make_float3(PS_F(ps, sh_dx), PS_F(ps, sh_dy), PS_F(ps, sh_dz)); }

// Distance to the first surface that is there (not a cutout) in (0, t_max) along d, or -1.
// With cutouts, each step is a closest hit that starts strictly beyond the surface it passed
// (t_min is exclusive). Shadow rays and ambient-occlusion rays (ambient_occlusion.h).
AW_FN float first_opaque_hit(SceneRef sc, float3 o, float3 d, float t_max) {
  float t0 = 0.0f;
  for (int k = 0; k < AW_SHADOW_CUTOUT_STEPS; ++k) {
    TriangleHit h = scene_intersect(sc, o, d, t0, t_max);
    if (h.prim < 0) return -1.0f;
    if (!(AW_FEAT_CUTOUT && sc.cutouts) || !surface_is_cutout(sc, (uint)h.prim) || k == AW_SHADOW_CUTOUT_STEPS - 1)
      return h.t;
    t0 = h.t;
  }
  return -1.0f;
}

// Whether a surface blocks the segment (0, t_max) along d: the cheaper any-hit query when the
// scene has no cutouts.
AW_FN int shadow_occluded(SceneRef sc, float3 o, float3 d, float t_max) {
  if (!(AW_FEAT_CUTOUT && sc.cutouts)) return scene_occluded(sc, o, d, 0.0f, t_max);
  return first_opaque_hit(sc, o, d, t_max) >= 0.0f;
}

AW_FN void intersect_shadow(PathRef ps, SceneRef sc, const RenderParams* rp) {
  AW_KERNEL_ASSERT((PS_U(ps, flags) & AW_PATH_HAS_SHADOW) != 0u);
  float3 o = ps_shadow_origin(ps), d = ps_shadow_dir(ps);
  float tmax = PS_F(ps, sh_tmax);
  int occluded = shadow_occluded(sc, o, d, tmax);
  if (!occluded) {
    // Lights occlude shadow rays aimed at other lights (not the one aimed at: sh_light).
    float t = tmax;
    occluded = scene_lights_intersect(sc, rp, o, d, 0.0f, &t, 0, (int)PS_U(ps, sh_light)) >= 0;
  }
  if (!occluded) ps_add_radiance(ps, make_float3(PS_F(ps, sh_r), PS_F(ps, sh_g), PS_F(ps, sh_b)));
  PS_U(ps, flags) &= ~AW_PATH_HAS_SHADOW;
}

#endif
