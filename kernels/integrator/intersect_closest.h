// From: RAY / To: RAY (the same queue: classify_hit reads the hit this stage writes).
// The extension ray's closest hit: the nearest triangle, or an analytic area light in front
// of it (lights are not in the BVH, lights/lights.h).
#ifndef AW_INTEGRATOR_INTERSECT_CLOSEST_H
#define AW_INTEGRATOR_INTERSECT_CLOSEST_H

#include "integrator/path_state.h"
#include "integrator/ray_cast.h"
#include "integrator/light_select.h"

AW_FN void intersect_closest(PathRef ps, SceneRef sc, const RenderParams* rp) {
  float3 o = ps_ray_origin(ps), d = ps_ray_dir(ps);
  TriangleHit h = scene_intersect(sc, o, d, 0.0f, FLT_MAX);
  float t = h.t;
  // Camera rays see only visible lights (light.visible); every later ray sees all of them.
  int light = scene_lights_intersect(sc, rp, o, d, 0.0f, &t, PS_U(ps, bounce) == 0u, -1);
  if (light >= 0) ps_set_hit(ps, t, 0.0f, 0.0f, AW_NONE, AW_NONE, (uint)light);
  else ps_set_hit(ps, h.t, h.u, h.v, h.prim >= 0 ? (uint)h.prim : AW_NONE, h.prim >= 0 ? h.inst : AW_NONE, AW_NONE);
}

#endif
