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
// the AOVs' light groups apply too (integrator/aov.h). Written on lanes (common/lanes.h): at
// W = 1 one path, as the queue launch, the megakernel and the host scalar path run it; at W > 1
// the W paths of a lane kernel (kernels_lanes.cl, kernel_accumulate_lanes), each lane the same
// operations, so the same sample bit for bit. *bad: the lanes whose sample is discarded.
AW_FN lfloat3 path_result(PathRef ps, const RenderParams* rp, lmask* bad, lfloat* k) {
  lfloat3 l = ps_radiance(ps);
  const lfloat3 zero = l3_splat((lfloat)(0.0f));
  lmask b = !(isfinite(l.x) && isfinite(l.y) && isfinite(l.z)) || l.x < 0.0f || l.y < 0.0f || l.z < 0.0f;
  lfloat kk = (lfloat)(1.0f);
  if (rp->clamp > 0.0f) {
    lfloat m = l3_max3(l);
    lmask clamped = !b && m > rp->clamp;
    if (L_ANY(clamped)) {
      kk = L_SEL(clamped, rp->clamp / m, kk);
      l = l3_sel(clamped, l3_scale(l, kk), l);
    }
  }
  // The film's exact sums take samples below 2^60 (integrator/film.h); a larger value is a
  // numerical blow-up, as Inf is, and is discarded the same way.
  b = b || !(l3_max3(l) < AW_FILM_MAX_SAMPLE);
  *bad = b;
  *k = L_SEL(b, (lfloat)(0.0f), kk);
  return l3_sel(b, zero, l);
}

// What accumulate_path reports for the stats counters (queues.h, AW_STAT_*).
#define AW_ACC_BAD 1u      // the sample was discarded
#define AW_ACC_MISSING 2u  // the path met a feature this build lacks

// Ends a path (or one split of it). Returns AW_Q_FREE with the job's sample value in *value
// and, when the render asks for AOVs, its AOV report in aov[0, AW_AOV_FLOATS); or the lobe
// queue of the next split (*value untouched). *events: AW_ACC_* of this path. One path per call:
// the lane kernel calls path_result itself (it is built only for scenes without splits and
// AOVs: host/render/wavefront.cpp).
#if AW_LANES == 1
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

#endif
