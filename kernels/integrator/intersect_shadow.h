// From: SHADOW / To: nowhere (the path's next queue was set by its lobe stage; a path in
// SHADOW is also in that queue). An unoccluded shadow ray adds its light sample to the path.
#ifndef AW_INTEGRATOR_INTERSECT_SHADOW_H
#define AW_INTEGRATOR_INTERSECT_SHADOW_H

#include "common/features.h"
#include "integrator/path_state.h"
#include "integrator/ray_cast.h"
#include "integrator/light_select.h"

AW_FN float3 ps_shadow_origin(PathRef ps) { return make_float3(PS_F(ps, sh_ox), PS_F(ps, sh_oy), PS_F(ps, sh_oz)); }
AW_FN float3 ps_shadow_dir(PathRef ps) { return make_float3(PS_F(ps, sh_dx), PS_F(ps, sh_dy), PS_F(ps, sh_dz)); }


AW_FN void intersect_shadow(PathRef ps, SceneRef sc, const RenderParams* rp) {
  AW_KERNEL_ASSERT((PS_U(ps, flags) & AW_PATH_HAS_SHADOW) != 0u);
  float3 o = ps_shadow_origin(ps), d = ps_shadow_dir(ps);
  float tmax = PS_F(ps, sh_tmax);
  // Cutout holes let shadow rays through: the ray caster does not report them (ray_cast.h).
  int occluded = scene_occluded(sc, o, d, 0.0f, tmax);
  if (!occluded) {
    // Lights occlude shadow rays aimed at other lights (not the one aimed at: sh_light).
    float t = tmax;
    occluded = scene_lights_intersect(sc, rp, o, d, 0.0f, &t, 0, (int)PS_U(ps, sh_light)) >= 0;
  }
  if (!occluded) ps_add_radiance(ps, make_float3(PS_F(ps, sh_r), PS_F(ps, sh_g), PS_F(ps, sh_b)));
  PS_U(ps, flags) &= ~AW_PATH_HAS_SHADOW;
}

#endif
