// From: SHADOW (after intersect_shadow) / To: nowhere (the path's queue was set by its lobe
// stage). An unoccluded shadow ray adds its light sample to the path.
#ifndef AW_INTEGRATOR_SHADE_SHADOW_H
#define AW_INTEGRATOR_SHADE_SHADOW_H

#include "integrator/path_state.h"

AW_FN void shade_shadow(PathRef ps, int occluded) {
  if (!occluded) ps_add_radiance(ps, make_float3(PS_F(ps, sh_r), PS_F(ps, sh_g), PS_F(ps, sh_b)));
  PS_U(ps, flags) &= ~AW_PATH_HAS_SHADOW;
}

AW_FN float3 ps_shadow_origin(PathRef ps) { return make_float3(PS_F(ps, sh_ox), PS_F(ps, sh_oy), PS_F(ps, sh_oz)); }
AW_FN float3 ps_shadow_dir(PathRef ps) { return make_float3(PS_F(ps, sh_dx), PS_F(ps, sh_dy), PS_F(ps, sh_dz)); }

#endif
