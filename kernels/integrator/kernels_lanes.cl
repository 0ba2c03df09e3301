// The wavefront's entry points built on lanes (common/lanes.h): a program built with
// -DAW_LANES=16 for CPU devices, beside the one-path program of kernels.cl, with the same
// parameter list (integrator/stage_kernel.h). Each work-item takes 16 consecutive slots, the
// lanes of every vector, and the paths among them that are in the stage's queue (their tag,
// as a dense launch of kernels.cl tests it) are its live lanes; every state field is one
// vector load, every store a masked read-modify-write (integrator/path_state.h). Why: OpenCL's
// vector types run at the full SIMD width on PoCL, which runs a work-item's scalar code one
// path at a time (docs/performance.md, "Paths in explicit lanes").
//
// Only what is written on lanes is here: regenerate, the ray stages (the lane traversal of
// bvh/traverse_lanes.h), classify_hit, and the shading stages of the lobes of
// AW_LOBE_LIST_ON_LANES (material/lobe_list.h). The host (host/render/wavefront.cpp) builds
// this program only on a CPU device and for a scene that needs nothing still one path per
// call (textures and bump maps, the light tree, an environment map, AOVs, zsobol), uses its
// classify_hit only for scenes that also need none of what that stage leaves out on lanes
// (integrator/classify_hit.h: reflection, fog, instances), its ray stages only for scenes
// without instances and cutouts (bvh/traverse_lanes.h), and launches a lane kernel only
// for a dense launch; a queue launch runs kernels.cl's.
#ifdef cl_khr_fp64
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#endif

#if !defined(AW_LANES) || AW_LANES == 1
#error "kernels_lanes.cl is built with -DAW_LANES=8 or 16"
#endif

#include "integrator/classify_hit.h"
#include "integrator/generate_camera_ray.h"
#include "integrator/intersect_closest.h"
#include "integrator/intersect_shadow.h"
#include "integrator/shade_surface.h"
#include "integrator/stage_kernel.h"
#include "material/lobe_list.h"

// The appends of a work-item's W paths: lane k goes to queue q.sk (none when AW_Q_COUNT),
// slot slot0 + k. Aggregated per work-item, not per work-group as wg_append
// (stage_kernel.h): one global atomic per queue its lanes name, so at most W paths per atomic
// and usually several. As a histogram: count the lanes per queue, one atomic per queue that
// has any, then one pass over the lanes writing each where its queue's cursor is; the tags
// are one masked vector store. Within a queue the lanes keep their order, so the queues are
// the same as the earlier nested loops' (queue by queue, lane by lane) wrote.
//
// No barrier: a lane kernel with wg_append's barriers corrupted paths when PoCL 3.1 ran
// work-groups on two threads, and was right on one (Cornell box, 128x128; with the lanes'
// queues in local memory too), and without barriers it is right and deterministic. Where
// inside PoCL it goes wrong was not isolated; what differs from the one-path kernels is the
// size of what each work-item holds around the barriers (PoCL keeps a work-item's values
// that live across a barrier in context arrays of the work-group function), 16 lanes of
// every value.
static inline void append_lanes(__global uint* counters, __global uint* queues, __global uint* tags, uint pool,
                                luint q, uint slot0) {
  lmask listed = q < (luint)(AW_Q_COUNT);
  if (!L_ANY(listed)) return;
  uint qk[AW_LANES];
  L_STORE(L_SEL(listed, q, (luint)(AW_Q_COUNT)), qk, 0);
  uint at[AW_Q_COUNT + 1];  // per queue: lanes, then the next free entry; [AW_Q_COUNT]: none
  for (uint i = 0u; i <= (uint)AW_Q_COUNT; ++i) at[i] = 0u;
  for (uint k = 0u; k < AW_LANES; ++k) ++at[qk[k]];
  for (uint i = 0u; i < (uint)AW_Q_COUNT; ++i)
    if (at[i] != 0u) at[i] = i * pool + atomic_add(&counters[i], at[i]);
  for (uint k = 0u; k < AW_LANES; ++k) {
    uint qq = qk[k];
    if (qq < (uint)AW_Q_COUNT) queues[at[qq]++] = slot0 + k;
  }
  lmask tagged = listed && q != (luint)(AW_Q_SHADOW);
  L_STORE(L_SEL(tagged, q, L_LOAD(tags + slot0, 0)), tags + slot0, 0);
}
#define AW_APPEND_LANES(q, slot0) append_lanes(counters, queues, tags, rp.pool_size, (q), (slot0))

// What every lane kernel starts with: its block of W slots (slot0, ps) and, as ps.live, the
// lanes that are the stage's paths (`lanes`, an expression that may read slot0 and ps); it
// returns when the block lies past the pool or has no such lane. `lanes` may read any state
// field: path_ref_make leaves all W lanes live until then.
#define AW_LANES_BLOCK(lanes)                           \
  uint slot0 = get_global_id(0) * AW_LANES;             \
  if (slot0 + AW_LANES > rp.pool_size) return;          \
  PathRef ps = AW_STAGE_PATH(slot0);                    \
  ps.live = (lanes);                                    \
  if (!L_ANY(ps.live)) return

// regenerate on lanes: the FREE slots (tag FREE) of a dense launch over the pool. A
// work-item's free lanes take the launch's next jobs in lane order, by one atomic per
// work-item on the FREE counter, which the host zeroes for this launch (wavefront.cpp,
// launch): the jobs job_start .. job_start + count - 1, each once; lanes past the last job stay
// FREE. Which slot runs which job depends on the order in which the work-items reach the
// atomic, and nothing that is computed does: a path's random numbers follow its (pixel,
// sample), and its value lands in samples[job]. Why: the queue launch (kernels.cl) writes the
// ~20 state words of a path in whatever slot order accumulate left in the FREE queue, a cache
// line per word per path; here 16 paths share each line.
AW_STAGE_KERNEL_SCALAR(kernel_regenerate_lanes) {
  AW_LANES_BLOCK(L_LOAD(tags + slot0, 0) == (uint)(AW_Q_FREE));
  uint one[AW_LANES], rank[AW_LANES];
  L_STORE(L_SEL(ps.live, (luint)(1u), (luint)(0u)), one, 0);
  uint n = 0u;
  for (uint k = 0u; k < AW_LANES; ++k) {
    rank[k] = n;
    n += one[k];
  }
  uint base = atomic_add(&counters[AW_Q_FREE], n);
  if (base >= count) return;
  luint job = (luint)(base) + L_LOAD(rank, 0);
  ps.live = ps.live && job < (luint)(count);
  generate_camera_ray(ps, &rp, (luint)(job_start) + job);
  AW_APPEND_LANES(L_SEL(ps.live, (luint)(AW_Q_RAY), (luint)(AW_Q_COUNT)), slot0);
}

// One shading kernel per lobe on lanes: kernel_shade_<name>_lanes, shade_surface on W paths.
// Launched over pool / W work-items (padded to the group); `count` and `dense` are not read.
// Built one work-item at a time on Intel's runtime too (AW_SCALAR_KERNEL): the lanes are the
// vectorisation; the runtime's own, across work-items, would gather 16 blocks per vector.
#define AW_SHADE_LANES_KERNEL(ID, name, FEATURE, TRAITS)                                        \
  AW_STAGE_KERNEL_SCALAR(kernel_shade_##name##_lanes) {                                         \
    if (!AW_FEAT_##FEATURE) return;                                                             \
    AW_LANES_BLOCK(L_LOAD(tags + slot0, 0) == (uint)(AW_Q_LOBE + AW_LID_##ID));                 \
    luint q = shade_surface(ps, AW_STAGE_SCENE, &rp, (uint)AW_LID_##ID);                        \
    lmask shadow = ps.live && (PS_LU(ps, flags) & AW_PATH_HAS_SHADOW) != 0u;                    \
    AW_APPEND_LANES(L_SEL(shadow, (luint)(AW_Q_SHADOW), (luint)(AW_Q_COUNT)), slot0);           \
    AW_APPEND_LANES(L_SEL(ps.live, q, (luint)(AW_Q_COUNT)), slot0);                             \
  }
AW_LOBE_LIST_ON_LANES(AW_SHADE_LANES_KERNEL)
#undef AW_SHADE_LANES_KERNEL

// classify_hit on lanes: the paths whose ray was traced (tag RAY), W per work-item.
AW_STAGE_KERNEL_SCALAR(kernel_classify_hit_lanes) {
  AW_LANES_BLOCK(L_LOAD(tags + slot0, 0) == (uint)(AW_Q_RAY));
  luint q = classify_hit(ps, AW_STAGE_SCENE, &rp);
  AW_APPEND_LANES(L_SEL(ps.live, q, (luint)(AW_Q_COUNT)), slot0);
}

// The ray stages on lanes: W rays per work-item through bvh/traverse_lanes.h. The closest
// hit's paths are those tagged RAY; a shadow ray's are those with AW_PATH_HAS_SHADOW (SHADOW
// is not a tag: stage_kernel.h, stage_slot).
AW_STAGE_KERNEL_SCALAR(kernel_intersect_closest_lanes) {
  AW_LANES_BLOCK(L_LOAD(tags + slot0, 0) == (uint)(AW_Q_RAY));
  intersect_closest(ps, AW_STAGE_SCENE, &rp);
}

AW_STAGE_KERNEL_SCALAR(kernel_intersect_shadow_lanes) {
  AW_LANES_BLOCK((PS_LU(ps, flags) & AW_PATH_HAS_SHADOW) != 0u);
  intersect_shadow(ps, AW_STAGE_SCENE, &rp);
}
