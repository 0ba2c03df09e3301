// Rays and robust origins.
#ifndef AW_COMMON_RAY_H
#define AW_COMMON_RAY_H

#include "common/compat.h"

// Offsets a surface point along the geometric normal by a few ULPs so the next ray cannot
// re-hit the surface it leaves: Wächter & Binder 2019, "A Fast and Robust Method for
// Avoiding Self-Intersection", Ray Tracing Gems, Ch. 6, Listing 6-1. Integer ULP steps scale
// with the magnitude of the coordinate; near the origin (where ULPs vanish) a small fixed
// float offset is used instead. `n` must point to the side the new ray leaves towards.
AW_FN float offset_one(float p, float n) {
  const float origin = 1.0f / 32.0f;
  const float float_scale = 1.0f / 65536.0f;
  const float int_scale = 256.0f;
  int of_i = (int)(int_scale * n);
  float p_i = as_float_i(as_int(p) + ((p < 0.0f) ? -of_i : of_i));
  return fabs(p) < origin ? p + float_scale * n : p_i;
}

AW_FN float3 offset_ray_origin(float3 p, float3 n) {
  return make_float3(offset_one(p.x, n.x), offset_one(p.y, n.y), offset_one(p.z, n.z));
}

#endif
