// From: RAY / To: RAY (the same queue: classify_hit reads the hit this stage writes).
// The extension ray's closest hit: the nearest triangle, or an analytic area light in front
// of it (lights are not in the BVH, lights/lights.h).
#ifndef AW_INTEGRATOR_INTERSECT_CLOSEST_H
#define AW_INTEGRATOR_INTERSECT_CLOSEST_H

#include "integrator/path_state.h"
#include "integrator/ray_cast.h"
#include "integrator/light_select.h"

// On lanes (W > 1) the ray cast is the lane traversal (bvh/traverse_lanes.h) over the paths
// in the stage's queue; the host's scalar path and every W = 1 program cast through
// scene_intersect (ray_cast.h).
AW_FN void intersect_closest(PathRef ps, SceneRef sc, const RenderParams* rp) {
  lfloat3 o = ps_ray_origin(ps), d = ps_ray_dir(ps);
#if AW_LANES == 1
  TriangleHit h = scene_intersect(sc, o, d, 0.0f, FLT_MAX);
#else
  TriangleHit h = bvh_intersect_lanes(sc.nodes, sc.num_nodes, sc.tris, o, d, (lfloat)(0.0f), (lfloat)(FLT_MAX), 0,
                                      PS_LIVE(ps));
#endif
  lfloat t = h.t;
  // Camera rays see only visible lights (light.visible); every later ray sees all of them.
  lint light = scene_lights_intersect(sc, rp, o, d, (lfloat)(0.0f), &t, PS_LU(ps, bounce) == 0u, (lint)(-1));
  lmask lit = light >= 0, tri = h.prim >= 0;
  const luint none = (luint)(AW_NONE);
  ps_set_hit(ps, L_SEL(lit, t, h.t), L_SEL(lit, (lfloat)(0.0f), h.u), L_SEL(lit, (lfloat)(0.0f), h.v),
             L_SEL(lit, none, L_SEL(tri, L_TO_UINT(h.prim), none)), L_SEL(lit, none, L_SEL(tri, h.inst, none)),
             L_SEL(lit, L_TO_UINT(light), none));
}

#endif
