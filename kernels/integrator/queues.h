// Queue ids and the scheduling rule: every stage hands a path to exactly one next queue or
// ends it (AW_Q_DONE). Shadow rays ride alongside: a lobe stage may also put the path in
// AW_Q_SHADOW, which only adds light and never changes where the path goes next.
//
//   FREE --regenerate--> RAY --intersect_closest--> (same RAY queue)
//   RAY --classify_hit--> one lobe queue (LOBE + AW_LID_*) | AO | DONE
//   AO --ambient_occlusion--> the lobe queue classify_hit chose | DONE
//   LOBE + lid --shade_<lobe>--> RAY | DONE   (+ SHADOW)
//   SHADOW --intersect_shadow--> (adds radiance)
//   DONE --accumulate--> FREE | LOBE + lid (the next split of a first-hit lobe, split.h)
//
// The wavefront (kernels.cl, host/render/wavefront.cpp) and the megakernel (megakernel.h)
// follow the same rule: the stage functions return the next queue.
#ifndef AW_INTEGRATOR_QUEUES_H
#define AW_INTEGRATOR_QUEUES_H

#include "material/lobe_list.h"

enum {
  AW_Q_RAY,
  AW_Q_SHADOW,
  AW_Q_DONE,
  AW_Q_FREE,
  AW_Q_AO,    // ambient occlusion before the lobe (ambient_occlusion.h -> LOBE + lid | DONE)
  AW_Q_LOBE,  // + AW_LID_*: one queue per lobe of the lobe list (material/lobe_list.h)
  AW_Q_COUNT = AW_Q_LOBE + AW_LID_COUNT
};

// The counters buffer holds the queues' entry counts, then the jobs finished per half of the
// batch ring (host/render/wavefront.cpp, "The batch ring"): accumulate adds a job whose sample
// is final to AW_C_FINISHED + (job >= the ring's half size), so the host knows when a batch's
// last path has ended and its samples can go to the film while the next batch's paths run.
enum {
  AW_C_FINISHED = AW_Q_COUNT,
  AW_C_COUNT = AW_C_FINISHED + 2
};

// Slots of the stats counters buffer (integers only: nothing float is accumulated atomically).
enum {
  AW_STAT_BAD_SAMPLES,
  AW_STAT_MISSING_FEATURE,  // paths that met a feature compiled out of this build
  AW_STAT_COUNT
};

#endif
