// From: SHADOW (after intersect_shadow) / To: nowhere (the path's queue was set by its lobe
// stage). An unoccluded shadow ray adds its light sample to the path.
#ifndef AW_INTEGRATOR_SHADE_SHADOW_H
#define AW_INTEGRATOR_SHADE_SHADOW_H

#include "integrator/path_state.h"
#include "integrator/scene_ref.h"

AW_FN void shade_shadow(PathRef ps, int occluded) {
  if (!occluded) ps_add_radiance(ps, make_float3(PS_F(ps, sh_r), PS_F(ps, sh_g), PS_F(ps, sh_b)));
  PS_U(ps, flags) &= ~AW_PATH_HAS_SHADOW;
}

// Cutout surfaces (opacity < 0.5) are not there for shadow rays either (MATERIAL.md §1):
// both intersectors step through them with closest-hit queries, at most this many layers
// (beyond that the ray counts as blocked).
#define AW_SHADOW_CUTOUT_STEPS 32

AW_FN int surface_is_cutout(SceneRef sc, uint prim) {
  return sc.materials[sc.tri_info[prim].material].cutout_opacity < 0.5f;
}

AW_FN float3 ps_shadow_origin(PathRef ps) { return make_float3(PS_F(ps, sh_ox), PS_F(ps, sh_oy), PS_F(ps, sh_oz)); }
AW_FN float3 ps_shadow_dir(PathRef ps) { return make_float3(PS_F(ps, sh_dx), PS_F(ps, sh_dy), PS_F(ps, sh_dz)); }

#endif
