// From: SHADOW / To: nowhere (the path's next queue was set by its lobe stage; a path in
// SHADOW is also in that queue). An unoccluded shadow ray adds its light sample to the path.
#ifndef AW_INTEGRATOR_INTERSECT_SHADOW_H
#define AW_INTEGRATOR_INTERSECT_SHADOW_H

#include "common/features.h"
#include "integrator/path_state.h"
#include "integrator/ray_cast.h"
#include "integrator/light_select.h"

AW_FN lfloat3 ps_shadow_origin(PathRef ps) { return make_lfloat3(PS_LF(ps, sh_ox), PS_LF(ps, sh_oy), PS_LF(ps, sh_oz)); }
AW_FN lfloat3 ps_shadow_dir(PathRef ps) { return make_lfloat3(PS_LF(ps, sh_dx), PS_LF(ps, sh_dy), PS_LF(ps, sh_dz)); }

// On lanes (W > 1) the occlusion test is the lane traversal (bvh/traverse_lanes.h), as in
// intersect_closest.h.
AW_FN void intersect_shadow(PathRef ps, SceneRef sc, const RenderParams* rp) {
#if AW_LANES == 1
  AW_KERNEL_ASSERT((PS_U(ps, flags) & AW_PATH_HAS_SHADOW) != 0u);
#endif
  lfloat3 o = ps_shadow_origin(ps), d = ps_shadow_dir(ps);
  lfloat tmax = PS_LF(ps, sh_tmax);
  // Cutout holes let shadow rays through: the ray caster does not report them (ray_cast.h).
#if AW_LANES == 1
  lmask occluded = scene_occluded(sc, o, d, 0.0f, tmax);
#else
  lmask occluded = bvh_intersect_lanes(sc.nodes, sc.num_nodes, sc.tris, o, d, (lfloat)(0.0f), tmax, 1, PS_LIVE(ps)).prim >= 0;
#endif
  if (!L_ALL(occluded)) {
    // Lights occlude shadow rays aimed at other lights (not the one aimed at: sh_light).
    lfloat t = tmax;
    occluded = occluded || scene_lights_intersect(sc, rp, o, d, (lfloat)(0.0f), &t, (lmask)(0),
                                                  L_TO_INT(PS_LU(ps, sh_light))) >= 0;
  }
  PathRef lit = ps;
  PS_KEEP(lit, !occluded);
  if (!L_ALL(occluded)) ps_add_radiance(lit, make_lfloat3(PS_LF(ps, sh_r), PS_LF(ps, sh_g), PS_LF(ps, sh_b)));
  PS_SET_U(ps, flags, PS_LU(ps, flags) & ~AW_PATH_HAS_SHADOW);
}

#endif
