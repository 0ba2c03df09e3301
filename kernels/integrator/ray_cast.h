// The one hook between the stages and a ray caster: closest hit and occlusion in the open
// interval (t_min, t_max), of surfaces that are there: a cutout hole (opacity below 0.5,
// texture/material_textures.h) is not hit by any ray, tested inside the traversal. On the device these are the flattened-BVH traversal (bvh/traverse.h);
// the host scalar path defines them over Embree's rtcIntersect1/rtcOccluded1
// (host/scalar/ray_cast_embree.cpp), an independent traversal that the per-pixel
// kernel-vs-scalar tests compare against the device's.
#ifndef AW_INTEGRATOR_RAY_CAST_H
#define AW_INTEGRATOR_RAY_CAST_H

#include "bvh/traverse.h"
#include "integrator/scene_ref.h"

#if AW_DEVICE && AW_LANES > 1
// (A lane program's ray stages call the lane traversal, bvh/traverse_lanes.h, directly.)
#elif AW_DEVICE
AW_FN TriangleHit scene_intersect(SceneRef sc, float3 o, float3 d, float t_min, float t_max) {
  TextureScene ts = scene_texture_ref(sc);
  return bvh_intersect_cut(sc.nodes, sc.num_nodes, sc.tris, sc.insts, o, d, t_min, t_max, 0, AW_FEAT_CUTOUT ? &ts : 0);
}
AW_FN int scene_occluded(SceneRef sc, float3 o, float3 d, float t_min, float t_max) {
  TextureScene ts = scene_texture_ref(sc);
  return bvh_intersect_cut(sc.nodes, sc.num_nodes, sc.tris, sc.insts, o, d, t_min, t_max, 1, AW_FEAT_CUTOUT ? &ts : 0).prim >= 0;
}
#else
TriangleHit scene_intersect(SceneRef sc, float3 o, float3 d, float t_min, float t_max);
int scene_occluded(SceneRef sc, float3 o, float3 d, float t_min, float t_max);
#endif

#endif
