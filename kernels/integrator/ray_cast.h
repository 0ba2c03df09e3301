// The one hook between the stages and a ray caster: closest hit and occlusion in the open
// interval (t_min, t_max) (t_min is exclusive: a ray that passed a cutout at t goes on beyond
// it, classify_hit.h). On the device these are the flattened-BVH traversal (bvh/traverse.h);
// the host scalar path defines them over Embree's rtcIntersect1/rtcOccluded1
// (host/scalar/ray_cast_embree.cpp), an independent traversal that the per-pixel
// kernel-vs-scalar tests compare against the device's.
#ifndef AW_INTEGRATOR_RAY_CAST_H
#define AW_INTEGRATOR_RAY_CAST_H

#include "bvh/traverse.h"
#include "integrator/scene_ref.h"

#if AW_DEVICE
AW_FN TriangleHit scene_intersect(SceneRef sc, float3 o, float3 d, float t_min, float t_max) {
  return bvh_intersect(sc.nodes, sc.num_nodes, sc.tris, o, d, t_min, t_max, 0);
}
AW_FN int scene_occluded(SceneRef sc, float3 o, float3 d, float t_min, float t_max) {
  return bvh_intersect(sc.nodes, sc.num_nodes, sc.tris, o, d, t_min, t_max, 1).prim >= 0;
}
#else
TriangleHit scene_intersect(SceneRef sc, float3 o, float3 d, float t_min, float t_max);
int scene_occluded(SceneRef sc, float3 o, float3 d, float t_min, float t_max);
#endif

#endif
