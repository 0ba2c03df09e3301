// Queue ids and the scheduling rule: every stage hands a path to exactly one next queue or
// ends it (AW_Q_DONE). Shadow rays ride alongside: a lobe stage may also put the path in
// AW_Q_SHADOW, which only adds light and never changes where the path goes next.
//
//   FREE --regenerate--> RAY --intersect_closest--> (same RAY queue)
//   RAY --classify_hit--> one lobe queue (LOBE + AW_LID_*) | PASS (cutout) | DONE
//   PASS --pass_through--> RAY
//   LOBE + i --shade_surface<i>--> RAY | DONE   (+ SHADOW)
//   SHADOW --intersect_shadow--> (adds radiance)
//   DONE --accumulate--> FREE | LOBE + lid (the next split of a first-hit lobe, split.h)
#ifndef AW_INTEGRATOR_QUEUES_H
#define AW_INTEGRATOR_QUEUES_H

#define AW_Q_RAY 0
#define AW_Q_SHADOW 1
#define AW_Q_DONE 2
#define AW_Q_FREE 3
#define AW_Q_PASS 4  // cutout: the ray continues through the surface (pass_through -> RAY)
#define AW_Q_LOBE 5  // + AW_LID_*: diffuse, translucency, reflection, reflection2, refraction
#define AW_Q_COUNT 10

// Slots of the stats counters buffer (integers only: nothing float is accumulated atomically).
#define AW_STAT_BAD_SAMPLES 0
#define AW_STAT_MISSING_FEATURE 1  // paths that met a feature compiled out of this build
#define AW_STAT_COUNT 4

#endif
