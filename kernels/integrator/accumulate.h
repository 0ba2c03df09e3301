// From: DONE / To: FREE. The path's final sample value: NaN/Inf samples are discarded
// (counted, contribute zero) so they never reach the film; optional clamping (biased).
#ifndef AW_INTEGRATOR_ACCUMULATE_H
#define AW_INTEGRATOR_ACCUMULATE_H

#include "integrator/path_state.h"
#include "types/scene.h"

AW_FN float3 path_result(PathRef ps, const RenderParams* rp, int* bad) {
  float3 l = ps_radiance(ps);
  *bad = 0;
  if (!finite3(l) || l.x < 0.0f || l.y < 0.0f || l.z < 0.0f) {
    *bad = 1;
    return make_float3(0.0f, 0.0f, 0.0f);
  }
  if (rp->clamp > 0.0f) {
    float m = max3(l);
    if (m > rp->clamp) l = l * (rp->clamp / m);
  }
  return l;
}

#endif
