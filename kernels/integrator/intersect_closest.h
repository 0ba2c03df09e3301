// From: RAY / To: RAY (the same queue: classify_hit reads the hit this stage writes).
// The extension ray's closest hit: the nearest triangle, or an analytic area light in front
// of it (lights are not in the BVH, lights/lights.h).
#ifndef AW_INTEGRATOR_INTERSECT_CLOSEST_H
#define AW_INTEGRATOR_INTERSECT_CLOSEST_H

#include "integrator/path_state.h"
#include "integrator/ray_cast.h"
#include "integrator/light_select.h"

// What the stage writes for one ray (per lane): the nearest triangle, or an analytic light in
// front of it.
typedef struct {
  lfloat t, u, v;
  luint prim, inst, light;  // AW_NONE where none
} ClosestHit;

// The closest hit of the rays (o, d) of the lanes in `live` (W > 1; one ray at W = 1, where
// `live` is not read); `camera`: the lanes whose ray leaves the camera. Shared by the stage on
// its paths' slots (intersect_closest, below) and by the lane program's sorted form, which
// hands it rays gathered from anywhere in its span (kernels_lanes.cl,
// kernel_intersect_closest_sorted). On lanes the ray cast is the lane traversal
// (bvh/traverse_lanes.h); the host's scalar path and every W = 1 program cast through
// scene_intersect (ray_cast.h).
AW_FN ClosestHit closest_hit_of(SceneRef sc, const RenderParams* rp, lfloat3 o, lfloat3 d, lmask camera, lmask live) {
#if AW_LANES == 1
  (void)live;
  TriangleHit h = scene_intersect(sc, o, d, 0.0f, FLT_MAX);
#else
  TriangleHit h = bvh_intersect_lanes(sc.nodes, sc.num_nodes, sc.tris, o, d, (lfloat)(0.0f), (lfloat)(FLT_MAX), 0, live);
#endif
  lfloat t = h.t;
  // Camera rays see only visible lights (light.visible); every later ray sees all of them.
  lint light = scene_lights_intersect(sc, rp, o, d, (lfloat)(0.0f), &t, camera, (lint)(-1));
  lmask lit = light >= 0, tri = h.prim >= 0;
  const luint none = (luint)(AW_NONE);
  ClosestHit c;
  c.t = L_SEL(lit, t, h.t);
  c.u = L_SEL(lit, (lfloat)(0.0f), h.u);
  c.v = L_SEL(lit, (lfloat)(0.0f), h.v);
  c.prim = L_SEL(lit, none, L_SEL(tri, L_TO_UINT(h.prim), none));
  c.inst = L_SEL(lit, none, L_SEL(tri, h.inst, none));
  c.light = L_SEL(lit, L_TO_UINT(light), none);
  return c;
}

AW_FN void intersect_closest(PathRef ps, SceneRef sc, const RenderParams* rp) {
  ClosestHit c = closest_hit_of(sc, rp, ps_ray_origin(ps), ps_ray_dir(ps), PS_LU(ps, bounce) == 0u, PS_LIVE(ps));
  ps_set_hit(ps, c.t, c.u, c.v, c.prim, c.inst, c.light);
}

#endif
