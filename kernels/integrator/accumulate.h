// From: DONE / To: FREE (the job's sample value is final), or LOBE + lid (the path was one
// split of its first-hit lobe and the next split starts there, integrator/split.h).
// The path's sample value: NaN/Inf/negative samples (and any above the film's 2^60) are discarded (counted, contribute zero)
// so they never reach the film; optional clamping (biased).
#ifndef AW_INTEGRATOR_ACCUMULATE_H
#define AW_INTEGRATOR_ACCUMULATE_H

#include "common/features.h"
#include "integrator/aov.h"
#include "integrator/film.h"
#include "integrator/path_state.h"
#include "integrator/queues.h"
#include "integrator/split.h"
#include "types/scene.h"

// *k: the factor the path's radiance was scaled by (1; the clamp's; 0 when discarded), which
// the AOVs' light groups apply too (integrator/aov.h).
AW_FN float3 path_result(PathRef ps, const RenderParams* rp, int* bad, float* k) {
  float3 l = ps_radiance(ps);
  *bad = 0;
  *k = 1.0f;
  if (!finite3(l) || l.x < 0.0f || l.y < 0.0f || l.z < 0.0f) {
    *bad = 1;
    *k = 0.0f;
    return make_float3(0.0f, 0.0f, 0.0f);
  }
  if (rp->clamp > 0.0f) {
    float m = max3(l);
    if (m > rp->clamp) {
      *k = rp->clamp / m;
      l = l * *k;
    }
  }
  // The film's exact sums take samples below 2^60 (integrator/film.h); a larger value is a
  // numerical blow-up, as Inf is, and is discarded the same way.
  if (!(max3(l) < AW_FILM_MAX_SAMPLE)) {
    *bad = 1;
    *k = 0.0f;
    return make_float3(0.0f, 0.0f, 0.0f);
  }
  return l;
}

// What accumulate_path reports for the stats counters (queues.h, AW_STAT_*).
#define AW_ACC_BAD 1u      // the sample was discarded
#define AW_ACC_MISSING 2u  // the path met a feature this build lacks

// Ends a path (or one split of it). Returns AW_Q_FREE with the job's sample value in *value
// and, when the render asks for AOVs, its AOV report in aov[0, AW_AOV_FLOATS); or the lobe
// queue of the next split (*value untouched). *events: AW_ACC_* of this path.
AW_FN int accumulate_path(PathRef ps, const RenderParams* rp, float3* value, uint* events, AW_GLOBAL float* aov) {
  int bad;
  float k;
  float3 l = path_result(ps, rp, &bad, &k);
  // Read before split_next: it restores the first-hit state, flags included.
  *events = (bad ? AW_ACC_BAD : 0u) | ((PS_U(ps, flags) & AW_PATH_MISSING_FEATURE) ? AW_ACC_MISSING : 0u);
  if (AW_FEAT_SPLIT && (PS_U(ps, flags) & AW_PATH_SPLIT) && split_next(ps, rp, l, k, &l, &k)) {
    AW_KERNEL_ASSERT(PS_U(ps, lobe) < (uint)AW_LID_COUNT);
    return AW_Q_LOBE + (int)PS_U(ps, lobe);
  }
  *value = l;
  if (aov_on(rp)) aov_report(ps, l, k, aov);
  return AW_Q_FREE;
}

#endif
