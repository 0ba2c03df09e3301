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

#include "integrator/accumulate.h"
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

// accumulate on lanes: the paths that ended (tag DONE), W per block. Each lane's sample value
// (path_result, the queue launch's own function) goes to samples[job], its slot to FREE; the
// counters the queue launch adds one to per path (finished jobs per half of the batch ring,
// discarded samples, missing features) take one atomic each per work-item. Why: the queue
// launch of kernels.cl reads the radiance, job and flags of each path from a cache line of its
// own and aggregates its appends per work-group behind barriers, 106 cycles a path on
// Intel's runtime; a block's 16 paths share each line (docs/performance.md, "State fields,
// sorted hits in slot order, accumulate on lanes"). Built only for renders without per-lobe
// splits and AOVs (accumulate_path's W = 1 parts), which the lane program already excludes or
// the host checks (wavefront.cpp).
AW_STAGE_KERNEL_SCALAR(kernel_accumulate_lanes) {
  AW_LANES_WORK_ITEM;
  uint finished_lo = 0u, finished_hi = 0u, bad = 0u, missing = 0u;
  for (uint b = 0u; b < AW_LANE_BLOCKS; ++b) {
    AW_LANES_BLOCK(b, L_LOAD(tags + slot0, 0) == (uint)(AW_Q_DONE));
    lmask bad_m;
    lfloat k;
    lfloat3 l = path_result(ps, &rp, &bad_m, &k);
    luint job = PS_LU(ps, job);
    lmask hi = job >= (luint)(job_start);
    bad += popcount(lane_bits(ps.live && bad_m));
    missing += popcount(lane_bits(ps.live && (PS_LU(ps, flags) & AW_PATH_MISSING_FEATURE) != 0u));
    uint live = lane_bits(ps.live);
    uint up = lane_bits(ps.live && hi);
    finished_hi += popcount(up);
    finished_lo += popcount(live & ~up);
    float lx[AW_LANES], ly[AW_LANES], lz[AW_LANES];
    uint jobs[AW_LANES];
    L_STORE(l.x, lx, 0);
    L_STORE(l.y, ly, 0);
    L_STORE(l.z, lz, 0);
    L_STORE(job, jobs, 0);
    for (uint m = live; m != 0u; m &= m - 1u) {
      const uint i = popcount((m & (0u - m)) - 1u);
      samples[jobs[i] * 3u + 0u] = lx[i];
      samples[jobs[i] * 3u + 1u] = ly[i];
      samples[jobs[i] * 3u + 2u] = lz[i];
    }
    AW_RECORD_LANES(b, L_SEL(ps.live, (luint)(AW_Q_FREE), (luint)(AW_Q_COUNT)), slot0);
  }
  AW_FLUSH_APPENDS();
  if (finished_lo != 0u) atomic_add(&counters[AW_C_FINISHED], finished_lo);
  if (finished_hi != 0u) atomic_add(&counters[AW_C_FINISHED + 1], finished_hi);
  if (bad != 0u) atomic_add(&stats[AW_STAT_BAD_SAMPLES], bad);
  if (missing != 0u) atomic_add(&stats[AW_STAT_MISSING_FEATURE], missing);
}

// The ray stages on lanes: W rays at a time through bvh/traverse_lanes.h. The closest hit's
// paths are those tagged RAY; a shadow ray's are those with AW_PATH_HAS_SHADOW (SHADOW is not a
// tag: stage_kernel.h, stage_slot). This form traces the W slots of each block as they lie;
// the host uses the sorted form below on scenes of more than a few primitives.
AW_STAGE_KERNEL_SCALAR(kernel_intersect_closest_lanes) {
  AW_LANES_WORK_ITEM;
  for (uint b = 0u; b < AW_LANE_BLOCKS; ++b) {
    AW_LANES_BLOCK(b, L_LOAD(tags + slot0, 0) == (uint)(AW_Q_RAY));
    intersect_closest(ps, AW_STAGE_SCENE, &rp);
  }
}

// intersect_closest on lanes, its rays sorted first. A work-item takes AW_SORT_SPAN consecutive
// slots, orders their rays (the paths tagged RAY) by a key, and traces them W at a time in that
// order, each lane's ray gathered from its slot and its hit written back there.
//
// Why: the rays of a diffuse bounce are incoherent, and a block of W of them tested every
// triangle that any of them might hit. On the Cornell box a block of 16 consecutive slots ran
// 16.1 triangle tests and 5.6 nodes with 2.4 of its lanes active per test (the lane
// traversal's own counts, docs/performance.md, "Rays sorted before the closest hit"); rays in
// the same octant starting in the same cell of the scene's box share their near surfaces, so
// the nodes and leaves they enter overlap: sorted over 4,096 slots the same rays took 8.3
// triangle tests and 4.4 nodes a block. (Sorting packets by direction and origin: Garanzha &
// Loop 2010, "Fast Ray Sorting and Breadth-First Packet Traversal for GPU Ray Tracing",
// Sec. 3; the key here is coarser: an octant and a cell of a 4 x 4 x 4 grid, 512 bins, one
// counting sort.) The sort, the gathers and the scattered stores cost part of it back.
//
// The key only orders the rays: every lane's hit is closest_hit_of's for its ray, whatever the
// others in its block (bvh/traverse_lanes.h). The order is a function of the slots' contents
// (a stable counting sort), so a render stays deterministic.
#ifndef AW_SORT_SPAN
#define AW_SORT_SPAN 4096
#endif
#define AW_SORT_CELL_BITS 2u                                 // 4 cells a side
#define AW_SORT_BINS (8u << (3u * AW_SORT_CELL_BITS))       // octant x 64 cells
typedef char aw_sort_span_is_whole_blocks[AW_SORT_SPAN % AW_LANES == 0 ? 1 : -1];
#if AW_LANES == 16
#define AW_LANE_IDS ((luint)(0u, 1u, 2u, 3u, 4u, 5u, 6u, 7u, 8u, 9u, 10u, 11u, 12u, 13u, 14u, 15u))
#else
#define AW_LANE_IDS ((luint)(0u, 1u, 2u, 3u, 4u, 5u, 6u, 7u))
#endif

// The box the sort's cells divide: the union of the root's children (types/bvh.h; empty slots
// skipped by their id), as its low corner and the cells per unit length.
static inline void sort_grid(const __global float4* nodes, uint num_nodes, float4* lo, float4* per_unit) {
  *lo = (float4)(0.0f);
  *per_unit = (float4)(0.0f);  // no tree: every ray in cell 0
  if (num_nodes == 0u) return;
  int4 used = as_int4(nodes[6]) != (int4)(AW_BVH_EMPTY);
  float4 lx = select((float4)(INFINITY), nodes[0], used), hx = select((float4)(-INFINITY), nodes[1], used);
  float4 ly = select((float4)(INFINITY), nodes[2], used), hy = select((float4)(-INFINITY), nodes[3], used);
  float4 lz = select((float4)(INFINITY), nodes[4], used), hz = select((float4)(-INFINITY), nodes[5], used);
  float4 l = (float4)(fmin(fmin(lx.x, lx.y), fmin(lx.z, lx.w)), fmin(fmin(ly.x, ly.y), fmin(ly.z, ly.w)),
                      fmin(fmin(lz.x, lz.y), fmin(lz.z, lz.w)), 0.0f);
  float4 h = (float4)(fmax(fmax(hx.x, hx.y), fmax(hx.z, hx.w)), fmax(fmax(hy.x, hy.y), fmax(hy.z, hy.w)),
                      fmax(fmax(hz.x, hz.y), fmax(hz.z, hz.w)), 0.0f);
  float4 extent = h - l;
  *lo = l;
  // A flat box (a single quad) has one cell across its thin side.
  *per_unit = select((float4)(0.0f), (float)(1u << AW_SORT_CELL_BITS) / extent, extent > (float4)(0.0f));
}

// A ray's bin: its direction's octant, then its origin's cell (clamped: an origin on the box's
// far face, or rounded outside it, takes the last cell; a NaN takes the first).
static inline luint sort_key(lfloat3 o, lfloat3 d, float4 lo, float4 per_unit) {
  const float last = (float)((1u << AW_SORT_CELL_BITS) - 1u);
  luint oct = L_SEL(d.x < 0.0f, (luint)(1u), (luint)(0u)) | L_SEL(d.y < 0.0f, (luint)(2u), (luint)(0u)) |
              L_SEL(d.z < 0.0f, (luint)(4u), (luint)(0u));
  luint cx = L_TO_UINT(fmin(fmax((o.x - lo.x) * per_unit.x, (lfloat)(0.0f)), (lfloat)(last)));
  luint cy = L_TO_UINT(fmin(fmax((o.y - lo.y) * per_unit.y, (lfloat)(0.0f)), (lfloat)(last)));
  luint cz = L_TO_UINT(fmin(fmax((o.z - lo.z) * per_unit.z, (lfloat)(0.0f)), (lfloat)(last)));
  return (oct << (3u * AW_SORT_CELL_BITS)) | (cx << (2u * AW_SORT_CELL_BITS)) | (cy << AW_SORT_CELL_BITS) | cz;
}

// The extension rays of the slots [first, first + span) (the paths tagged RAY) in the order of
// their bins: their slots into order[0, n), then W - 1 copies of the last (the last block's idle
// lanes gather a real slot); and each slot's place in that order into rank[slot - first]
// (AW_SORT_NO_RANK for a slot with no ray). Returns n. A stable counting sort, so each bin keeps
// its slots in slot order.
#define AW_SORT_NO_RANK 0xffffu
typedef char aw_sort_rank_fits_a_ushort[AW_SORT_SPAN < AW_SORT_NO_RANK ? 1 : -1];
static inline uint sort_span(__global const uint* tags, __global const float* sf, uint P, uint first, uint span,
                             float4 lo, float4 per_unit, uint* order, ushort* rank) {
  ushort* key = rank;  // a slot's bin (AW_SORT_BINS: no ray to trace), then its rank
  for (uint i = 0u; i < span; i += AW_LANES) {
    const uint slot0 = first + i;
    lmask live = L_LOAD(tags + slot0, 0) == (uint)(AW_Q_RAY);
    lfloat3 o = make_lfloat3(L_LOAD(sf + (uint)AW_SF_ray_ox * P + slot0, 0), L_LOAD(sf + (uint)AW_SF_ray_oy * P + slot0, 0),
                             L_LOAD(sf + (uint)AW_SF_ray_oz * P + slot0, 0));
    lfloat3 d = make_lfloat3(L_LOAD(sf + (uint)AW_SF_ray_dx * P + slot0, 0), L_LOAD(sf + (uint)AW_SF_ray_dy * P + slot0, 0),
                             L_LOAD(sf + (uint)AW_SF_ray_dz * P + slot0, 0));
    AW_LCAT(vstore, AW_LANES)(AW_LCAT(convert_ushort, AW_LANES)(L_SEL(live, sort_key(o, d, lo, per_unit), (luint)(AW_SORT_BINS))), 0, key + i);
  }
  uint start[AW_SORT_BINS];
  for (uint b = 0u; b < AW_SORT_BINS; ++b) start[b] = 0u;
  for (uint i = 0u; i < span; ++i)
    if (key[i] < AW_SORT_BINS) ++start[key[i]];
  uint n = 0u;
  for (uint b = 0u; b < AW_SORT_BINS; ++b) {
    uint c = start[b];
    start[b] = n;
    n += c;
  }
  if (n == 0u) return 0u;
  for (uint i = 0u; i < span; ++i) {
    const uint b = key[i];
    if (b < AW_SORT_BINS) {
      const uint r = start[b]++;
      order[r] = first + i;
      key[i] = (ushort)r;
    } else {
      key[i] = (ushort)AW_SORT_NO_RANK;
    }
  }
  for (uint i = n; i < n + AW_LANES; ++i) order[i] = order[n - 1u];
  return n;
}

// The lanes' rays of a sorted block: field f (3 consecutive fields from f) of each lane's slot.
#define AW_GATHER_F(f, slot) L_GATHER_V(float, sf + (uint)(f) * P, slot)
#define AW_GATHER_F3(f, slot) make_lfloat3(AW_GATHER_F(f, slot), AW_GATHER_F((uint)(f) + 1u, slot), AW_GATHER_F((uint)(f) + 2u, slot))

// One work-item per AW_SORT_SPAN slots, one work-item per group: the pool is a few dozen spans,
// and groups of one let the runtime share them out between the cores.
__kernel AW_SCALAR_KERNEL __attribute__((reqd_work_group_size(1, 1, 1))) void kernel_intersect_closest_sorted(
    const RenderParams rp AW_STAGE_ARGS(AW_STAGE_PARAM_VALUE, AW_STAGE_PARAM_BUFFER)) {
  const uint first = get_global_id(0) * AW_SORT_SPAN;
  if (first >= rp.pool_size) return;
  const uint P = rp.pool_size;
  const uint span = min((uint)AW_SORT_SPAN, P - first);  // whole blocks (the pool: whole groups of 256)
  SceneRef sc = AW_STAGE_SCENE;
  float4 lo, per_unit;
  sort_grid(nodes, rp.num_nodes, &lo, &per_unit);
  uint order[AW_SORT_SPAN + AW_LANES];
  ushort rank[AW_SORT_SPAN];
  const uint n = sort_span(tags, sf, P, first, span, lo, per_unit, order, rank);
  if (n == 0u) return;
  // The hits in the sorted order, then back to the slots in slot order. Why not stored straight
  // to each lane's slot: those stores go to 6 lines anywhere in the span's 96 KiB of hit fields,
  // one word each, and held 18% of the stage's samples (perf, Intel's runtime, Zen 4); loads
  // from these arrays by rank overlap where scattered stores queue (docs/performance.md,
  // "State fields, sorted hits in slot order, accumulate on lanes").
  float hs_t[AW_SORT_SPAN + AW_LANES], hs_u[AW_SORT_SPAN + AW_LANES], hs_v[AW_SORT_SPAN + AW_LANES];
  // (No instance: the lane traversal has none, bvh/traverse_lanes.h, so every hit's is AW_NONE.)
  uint hs_prim[AW_SORT_SPAN + AW_LANES], hs_light[AW_SORT_SPAN + AW_LANES];
  for (uint p = 0u; p < n; p += AW_LANES) {
    luint slot = L_LOAD(order + p, 0);
    lmask live = (luint)(p) + AW_LANE_IDS < (luint)(n);
    lmask camera = L_GATHER_V(uint, su + (uint)AW_SU_bounce * P, slot) == 0u;
    ClosestHit c = closest_hit_of(sc, &rp, AW_GATHER_F3(AW_SF_ray_ox, slot), AW_GATHER_F3(AW_SF_ray_dx, slot), camera, live);
    L_STORE(c.t, hs_t + p, 0);
    L_STORE(c.u, hs_u + p, 0);
    L_STORE(c.v, hs_v + p, 0);
    L_STORE(c.prim, hs_prim + p, 0);
    L_STORE(c.light, hs_light + p, 0);
  }
  for (uint i = 0u; i < span; i += AW_LANES) {
    PathRef ps = AW_STAGE_PATH(first + i);
    luint r = AW_LCAT(convert_uint, AW_LANES)(AW_LCAT(vload, AW_LANES)(0, rank + i));
    PS_SET_LIVE(ps, r != (luint)(AW_SORT_NO_RANK));
    if (!L_ANY(ps.live)) continue;
    r = L_SEL(ps.live, r, (luint)(0u));
    ps_set_hit(ps, L_GATHER_V(float, hs_t, r), L_GATHER_V(float, hs_u, r), L_GATHER_V(float, hs_v, r),
               L_GATHER_V(uint, hs_prim, r), (luint)(AW_NONE), L_GATHER_V(uint, hs_light, r));
  }
}

#undef AW_GATHER_F
#undef AW_GATHER_F3

AW_STAGE_KERNEL_SCALAR(kernel_intersect_shadow_lanes) {
  AW_LANES_WORK_ITEM;
  for (uint b = 0u; b < AW_LANE_BLOCKS; ++b) {
    AW_LANES_BLOCK(b, (PS_LU(ps, flags) & AW_PATH_HAS_SHADOW) != 0u);
    intersect_shadow(ps, AW_STAGE_SCENE, &rp);
  }
}
