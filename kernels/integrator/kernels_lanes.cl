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

// A work-item runs AW_LANE_BLOCKS blocks of W consecutive slots, one after the other, and
// appends their paths to the queues at once. Why: an append is one atomic per queue its lanes
// name on a counter that both cores' work-items hit; one block per work-item paid 9% of the
// lane program's time there (perf on Intel's runtime, Cornell box: 16% of shade_diffuse, 12%
// of classify_hit, two thirds of regenerate in the instruction after each `lock xadd`, the
// counters' cache line moving between the cores), four blocks still 7% on an AVX-512 Xeon;
// docs/performance.md, "Appends per four blocks" and "Appends per sixteen blocks". The host
// sets it (wavefront.cpp, kLaneSpan): 256 paths per work-item, 16 blocks of 16 or 32 of 8.
#ifndef AW_LANE_BLOCKS
#define AW_LANE_BLOCKS 16
#endif
#define AW_LANE_SPAN (AW_LANES * AW_LANE_BLOCKS)

// The appends of a work-item's blocks: lane k of block b goes to queue q[b * W + k] (none
// when AW_Q_COUNT), slot slot_first + b * W + k. Recorded per block (appends_record), written
// at the end (appends_flush) with one global atomic per queue that any of its lanes names, so
// at most AW_LANE_SPAN paths per atomic and usually several. Within a queue the lanes keep
// their slot order.
//
// No barrier (no aggregation per work-group, as wg_append in stage_kernel.h does): a lane
// kernel with wg_append's barriers corrupted paths when PoCL 3.1 ran work-groups on two
// threads, and was right on one (Cornell box, 128x128; with the lanes' queues in local memory
// too), and without barriers it is right and deterministic. Where inside PoCL it goes wrong
// was not isolated; what differs from the one-path kernels is the size of what each
// work-item holds around the barriers (PoCL keeps a work-item's values that live across a
// barrier in context arrays of the work-group function), 16 lanes of every value.
typedef struct {
  uint q[AW_LANE_SPAN];
} LaneAppends;

static inline void appends_clear(LaneAppends* a) {
  for (uint b = 0u; b < AW_LANE_BLOCKS; ++b) L_STORE((luint)(AW_Q_COUNT), a->q, b);
}

// Block b's lanes to queue q (lanes with q = AW_Q_COUNT to none), and their tags to q as one
// masked vector store, except for SHADOW, which is not a tag (stage_kernel.h, stage_slot).
static inline void appends_record(LaneAppends* a, __global uint* tags, uint b, uint slot0, luint q) {
  lmask listed = q < (luint)(AW_Q_COUNT);
  if (!L_ANY(listed)) return;
  L_STORE(L_SEL(listed, q, L_LOAD(a->q, b)), a->q, b);
  lmask tagged = listed && q != (luint)(AW_Q_SHADOW);
  L_STORE(L_SEL(tagged, q, L_LOAD(tags + slot0, 0)), tags + slot0, 0);
}

// The OR of a vector's lanes, by halves.
static inline uint lanes_or(luint v) {
#if AW_LANES == 16
  uint8 h = v.lo | v.hi;
#else
  uint8 h = v;
#endif
  uint4 f = h.lo | h.hi;
  uint2 t = f.lo | f.hi;
  return t.x | t.y;
}

// The lanes of m as the bits of a uint (lane k: bit k).
static inline uint lane_bits(lmask m) {
#if AW_LANES == 16
  return lanes_or(as_uint16(m) & (uint16)(1u, 2u, 4u, 8u, 16u, 32u, 64u, 128u, 256u, 512u, 1024u, 2048u, 4096u,
                                          8192u, 16384u, 32768u));
#else
  return lanes_or(as_uint8(m) & (uint8)(1u, 2u, 4u, 8u, 16u, 32u, 64u, 128u));
#endif
}

// The queues a block's lanes name (listed: q < AW_Q_COUNT) as the bits of a uint.
typedef char aw_queues_fit_a_uint[AW_Q_COUNT <= 32 ? 1 : -1];
static inline uint queues_named(luint q) {
  return lanes_or(L_SEL(q < (luint)(AW_Q_COUNT), (luint)(1u) << (q & (luint)(31u)), (luint)(0u)));
}

// Why bit masks and not a histogram over the lanes in an array: the array's counters, read and
// written once per lane through memory, made one chain of store-to-load forwarding 64 lanes
// long, twice per flush (14% of shade_diffuse's samples on Intel's runtime sat in those two
// loops; docs/performance.md, "Appends per four blocks"). Here the queues named (usually one
// or two) are found first, then each queue's lanes are a mask per block, counted by popcount
// and written lowest lane first, so each queue keeps its lanes' slot order as before.
static inline void appends_flush(const LaneAppends* a, __global uint* counters, __global uint* queues, uint pool,
                                 uint slot_first) {
  uint named = 0u;
  for (uint b = 0u; b < AW_LANE_BLOCKS; ++b) named |= queues_named(L_LOAD(a->q, b));
  while (named != 0u) {
    uint i = popcount((named & (0u - named)) - 1u);  // the lowest queue named
    named &= named - 1u;
    uint bits[AW_LANE_BLOCKS];
    uint n = 0u;
    for (uint b = 0u; b < AW_LANE_BLOCKS; ++b) {
      bits[b] = lane_bits(L_LOAD(a->q, b) == (luint)(i));
      n += popcount(bits[b]);
    }
    uint at = i * pool + atomic_add(&counters[i], n);
    for (uint b = 0u; b < AW_LANE_BLOCKS; ++b)
      for (uint m = bits[b]; m != 0u; m &= m - 1u)
        queues[at++] = slot_first + b * AW_LANES + popcount((m & (0u - m)) - 1u);
  }
}

// What every lane kernel's work-item starts with: its first slot, its appends.
#define AW_LANES_WORK_ITEM                                         \
  const uint slot_first = get_global_id(0) * AW_LANE_SPAN;       \
  if (slot_first >= rp.pool_size) return;                          \
  LaneAppends ap;                                                  \
  appends_clear(&ap)
#define AW_RECORD_LANES(b, q, slot0) appends_record(&ap, tags, (b), (slot0), (q))
#define AW_FLUSH_APPENDS() appends_flush(&ap, counters, queues, rp.pool_size, slot_first)

// What every lane kernel does first in block b of its work-item (inside the loop over the
// blocks): the block's W slots (slot0, ps) and, as ps.live, the lanes that are the stage's
// paths (`lanes`, an expression that may read slot0 and ps); it leaves the loop past the pool
// and goes on to the next block when none is the stage's. `lanes` may read any state field:
// path_ref_make leaves all W lanes live until then.
#define AW_LANES_BLOCK(b, lanes)                              \
  uint slot0 = slot_first + (b) * AW_LANES;                   \
  if (slot0 + AW_LANES > rp.pool_size) break;                 \
  PathRef ps = AW_STAGE_PATH(slot0);                          \
  PS_SET_LIVE(ps, (lanes));                                   \
  if (!L_ANY(ps.live)) continue

// regenerate on lanes: the FREE slots (tag FREE) of a dense launch over the pool. A
// work-item's free lanes take the launch's next jobs in slot order, by one atomic per
// work-item on the FREE counter, which the host zeroes for this launch (wavefront.cpp,
// launch): the jobs job_start .. job_start + count - 1, each once; lanes past the last job stay
// FREE. Which slot runs which job depends on the order in which the work-items reach the
// atomic, and nothing that is computed does: a path's random numbers follow its (pixel,
// sample), and its value lands in samples[job]. Why: the queue launch (kernels.cl) writes the
// ~20 state words of a path in whatever slot order accumulate left in the FREE queue, a cache
// line per word per path; here 16 paths share each line.
AW_STAGE_KERNEL_SCALAR(kernel_regenerate_lanes) {
  AW_LANES_WORK_ITEM;
  uint rank[AW_LANE_SPAN];  // per lane: free lanes before it in the work-item
  uint n = 0u, blocks = 0u;
  for (uint b = 0u; b < AW_LANE_BLOCKS && slot_first + (b + 1u) * AW_LANES <= rp.pool_size; ++b, ++blocks) {
    uint one[AW_LANES];
    L_STORE(L_SEL(L_LOAD(tags + slot_first + b * AW_LANES, 0) == (uint)(AW_Q_FREE), (luint)(1u), (luint)(0u)), one, 0);
    for (uint k = 0u; k < AW_LANES; ++k) {
      rank[b * AW_LANES + k] = n;
      n += one[k];
    }
  }
  if (n == 0u) return;
  uint base = atomic_add(&counters[AW_Q_FREE], n);
  if (base >= count) return;
  for (uint b = 0u; b < blocks; ++b) {
    AW_LANES_BLOCK(b, L_LOAD(tags + slot0, 0) == (uint)(AW_Q_FREE));
    luint job = (luint)(base) + L_LOAD(rank, b);
    PS_KEEP(ps, job < (luint)(count));
    if (!L_ANY(ps.live)) break;
    generate_camera_ray(ps, &rp, (luint)(job_start) + job);
    AW_RECORD_LANES(b, L_SEL(ps.live, (luint)(AW_Q_RAY), (luint)(AW_Q_COUNT)), slot0);
  }
  AW_FLUSH_APPENDS();
}

// One shading kernel per lobe on lanes: kernel_shade_<name>_lanes, shade_surface on W paths.
// Launched over pool / W work-items (padded to the group); `count` and `dense` are not read.
// Built one work-item at a time on Intel's runtime too (AW_SCALAR_KERNEL): the lanes are the
// vectorisation; the runtime's own, across work-items, would gather 16 blocks per vector.
#define AW_SHADE_LANES_KERNEL(ID, name, FEATURE, TRAITS)                                        \
  AW_STAGE_KERNEL_SCALAR(kernel_shade_##name##_lanes) {                                         \
    if (!AW_FEAT_##FEATURE) return;                                                             \
    AW_LANES_WORK_ITEM;                                                                         \
    LaneAppends shadows;                                                                        \
    appends_clear(&shadows);                                                                    \
    for (uint b = 0u; b < AW_LANE_BLOCKS; ++b) {                                                \
      AW_LANES_BLOCK(b, L_LOAD(tags + slot0, 0) == (uint)(AW_Q_LOBE + AW_LID_##ID));            \
      luint q = shade_surface(ps, AW_STAGE_SCENE, &rp, (uint)AW_LID_##ID);                      \
      lmask shadow = ps.live && (PS_LU(ps, flags) & AW_PATH_HAS_SHADOW) != 0u;                  \
      appends_record(&shadows, tags, b, slot0, L_SEL(shadow, (luint)(AW_Q_SHADOW), (luint)(AW_Q_COUNT))); \
      AW_RECORD_LANES(b, L_SEL(ps.live, q, (luint)(AW_Q_COUNT)), slot0);                        \
    }                                                                                           \
    appends_flush(&shadows, counters, queues, rp.pool_size, slot_first);                        \
    AW_FLUSH_APPENDS();                                                                         \
  }
AW_LOBE_LIST_ON_LANES(AW_SHADE_LANES_KERNEL)
#undef AW_SHADE_LANES_KERNEL

// classify_hit on lanes: the paths whose ray was traced (tag RAY), W per work-item.
AW_STAGE_KERNEL_SCALAR(kernel_classify_hit_lanes) {
  AW_LANES_WORK_ITEM;
  for (uint b = 0u; b < AW_LANE_BLOCKS; ++b) {
    AW_LANES_BLOCK(b, L_LOAD(tags + slot0, 0) == (uint)(AW_Q_RAY));
    luint q = classify_hit(ps, AW_STAGE_SCENE, &rp);
    AW_RECORD_LANES(b, L_SEL(ps.live, q, (luint)(AW_Q_COUNT)), slot0);
  }
  AW_FLUSH_APPENDS();
}

// The ray stages on lanes: W rays per work-item through bvh/traverse_lanes.h. The closest
// hit's paths are those tagged RAY; a shadow ray's are those with AW_PATH_HAS_SHADOW (SHADOW
// is not a tag: stage_kernel.h, stage_slot).
AW_STAGE_KERNEL_SCALAR(kernel_intersect_closest_lanes) {
  AW_LANES_WORK_ITEM;
  for (uint b = 0u; b < AW_LANE_BLOCKS; ++b) {
    AW_LANES_BLOCK(b, L_LOAD(tags + slot0, 0) == (uint)(AW_Q_RAY));
    intersect_closest(ps, AW_STAGE_SCENE, &rp);
  }
}

AW_STAGE_KERNEL_SCALAR(kernel_intersect_shadow_lanes) {
  AW_LANES_WORK_ITEM;
  for (uint b = 0u; b < AW_LANE_BLOCKS; ++b) {
    AW_LANES_BLOCK(b, (PS_LU(ps, flags) & AW_PATH_HAS_SHADOW) != 0u);
    intersect_shadow(ps, AW_STAGE_SCENE, &rp);
  }
}
