// One path from its camera ray to its sample value, through the SAME stage functions the
// wavefront's kernels call, in the wavefront's order (Cycles' kernel/integrator/megakernel.h
// is the model): each stage returns the next queue (integrator/queues.h), and the loop below
// runs that queue's stage instead of appending to it. The host scalar path runs it one path
// at a time with Embree as the ray caster (integrator/ray_cast.h), so the only code it does
// not share with the wavefront is the traversal and the wavefront's scheduling (queues,
// slots, dense launches): exactly what the per-pixel kernel-vs-scalar tests check.
#ifndef AW_INTEGRATOR_MEGAKERNEL_H
#define AW_INTEGRATOR_MEGAKERNEL_H

#include "integrator/accumulate.h"
#include "integrator/ambient_occlusion.h"
#include "integrator/classify_hit.h"
#include "integrator/generate_camera_ray.h"
#include "integrator/intersect_closest.h"
#include "integrator/intersect_shadow.h"
#include "integrator/shade_surface.h"

// What the megakernel did, for the render statistics.
typedef struct {
  ulong closest;  // closest-hit rays (extension rays)
  ulong shadow;   // shadow rays
  ulong bad;      // discarded samples (accumulate.h)
  ulong missing;  // paths that met a feature the build lacks
} MegakernelCounts;

// Runs job `job` of the batch ring (RenderParams: pixel and sample) to its end and returns its
// sample value, which is what the wavefront's accumulate stage writes to samples[job], and
// with AOVs its report in aov[0, AW_AOV_FLOATS) (aov_samples[job] there).
AW_FN float3 megakernel_path(PathRef ps, SceneRef sc, const RenderParams* rp, uint job, MegakernelCounts* c, AW_GLOBAL float* aov) {
  generate_camera_ray(ps, rp, job);
  float3 value = make_float3(0.0f, 0.0f, 0.0f);
  int q = AW_Q_RAY;
  for (;;) {
    AW_KERNEL_ASSERT(q >= 0 && q < AW_Q_COUNT && q != AW_Q_SHADOW);
    if (q == AW_Q_RAY) {
      intersect_closest(ps, sc, rp);
      ++c->closest;
      q = classify_hit(ps, sc, rp);
    } else if (q == AW_Q_AO) {
      q = ambient_occlusion(ps, sc, rp);
    } else if (q >= AW_Q_LOBE) {
      q = shade_surface(ps, sc, rp, (uint)(q - AW_Q_LOBE));
      if (PS_U(ps, flags) & AW_PATH_HAS_SHADOW) {
        ++c->shadow;
        intersect_shadow(ps, sc, rp);
      }
    } else if (q == AW_Q_DONE) {
      uint events;
      q = accumulate_path(ps, rp, &value, &events, aov);
      if (events & AW_ACC_BAD) ++c->bad;
      if (events & AW_ACC_MISSING) ++c->missing;
    } else {
      AW_KERNEL_ASSERT(q == AW_Q_FREE);
      return value;
    }
  }
}

#endif
