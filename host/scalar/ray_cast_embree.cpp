// kernels/integrator/ray_cast.h's hook on the host: Embree casts the scalar path's rays, an
// traversal independent of the kernels' flattened BVH. Embree's t_near is inclusive and the
// kernels' t_min exclusive (a ray that passed a cutout at t must not find it again), hence
// the next float above a positive t_min.
#include "host/scalar/ray_cast_embree.h"

#include <cmath>

#include "kernels/integrator/ray_cast.h"

namespace {
float embree_t_near(float t_min) { return t_min > 0.0f ? std::nextafter(t_min, FLT_MAX) : 0.0f; }
}  // namespace

TriangleHit scene_intersect(SceneRef sc, float3 o, float3 d, float t_min, float t_max) {
  aw::EmbreeScene::Hit e = sc.caster->scene->intersect(o, d, embree_t_near(t_min), t_max);
  TriangleHit h;
  h.t = e.t;
  h.u = e.u;
  h.v = e.v;
  h.prim = e.prim;
  h.inst = e.inst;
  return h;
}

int scene_occluded(SceneRef sc, float3 o, float3 d, float t_min, float t_max) {
  return sc.caster->scene->occluded(o, d, embree_t_near(t_min), t_max) ? 1 : 0;
}
