// Queue ids and the scheduling rule: every stage hands a path to exactly one next queue or
// ends it (AW_Q_DONE). Shadow rays ride alongside: a lobe stage may also put the path in
// AW_Q_SHADOW, which only adds light and never changes where the path goes next.
//
//   FREE --regenerate--> RAY --intersect_closest--> (same RAY queue) --classify_hit--> DIFFUSE | DONE
//   DIFFUSE --shade_diffuse--> RAY | DONE   (+ SHADOW)
//   SHADOW --intersect_shadow--> (adds radiance)
//   DONE --accumulate--> FREE
#ifndef AW_INTEGRATOR_QUEUES_H
#define AW_INTEGRATOR_QUEUES_H

#define AW_Q_RAY 0
#define AW_Q_DIFFUSE 1
#define AW_Q_SHADOW 2
#define AW_Q_DONE 3
#define AW_Q_FREE 4
#define AW_Q_COUNT 5

// Slots of the stats counters buffer (integers only: nothing float is accumulated atomically).
#define AW_STAT_BAD_SAMPLES 0
#define AW_STAT_COUNT 4

#endif
