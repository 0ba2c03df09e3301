// The wavefront's OpenCL entry points. Each is a thin wrapper: index -> bounds check ->
// shared stage function (kernels/integrator/*.h, the same code the host scalar path runs)
// -> aggregated queue appends. The scheduling rule is in integrator/queues.h.
//
// Queues live in one buffer: queue q occupies queues[q * pool .. q * pool + pool).
// Launch contract (host/render/wavefront.cpp): an explicit local size AW_WG (>= AW_Q_COUNT)
// and a global size padded up to a multiple of it; `count` is the real number of items.
// Every work-item of a group reaches the appends (they contain barriers), so the bounds
// check only masks work.
#ifdef cl_khr_fp64
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#endif

#include "bvh/traverse.h"
#include "integrator/accumulate.h"
#include "integrator/classify_hit.h"
#include "integrator/generate_camera_ray.h"
#include "integrator/path_state.h"
#include "integrator/queues.h"
#include "integrator/shade_shadow.h"
#include "integrator/shade_surface.h"
#include "integrator/split.h"

#ifndef AW_WG
#define AW_WG 256
#endif

// Queue append aggregated per work-group: local counters give each item its offset in its
// queue, then one global atomic per non-empty queue reserves the group's range (~6x faster
// than a global atomic per item on PoCL, DESIGN.md). `q` is the item's queue, or AW_Q_COUNT
// for none. Must be reached by every work-item of the group.
// It also records the queue in the slot's tag (tags[slot]), which is what a dense launch of
// the queue's consumer tests (see AW_DENSE_ITEM below). SHADOW is not a tag: a path in it is
// also in a main queue, and the consumer tests AW_PATH_HAS_SHADOW instead.
static inline void wg_append(__global uint* counters, __global uint* queues, __global uint* tags, uint pool,
                             uint q, uint slot, __local uint* l_n, __local uint* l_base) {
  uint lid = get_local_id(0);
  if (lid < AW_Q_COUNT) l_n[lid] = 0u;
  barrier(CLK_LOCAL_MEM_FENCE);
  uint off = q < AW_Q_COUNT ? atomic_inc(&l_n[q]) : 0u;
  barrier(CLK_LOCAL_MEM_FENCE);
  if (lid < AW_Q_COUNT) l_base[lid] = l_n[lid] > 0u ? atomic_add(&counters[lid], l_n[lid]) : 0u;
  barrier(CLK_LOCAL_MEM_FENCE);
  if (q < AW_Q_COUNT) {
    queues[q * pool + l_base[q] + off] = slot;
    if (q != AW_Q_SHADOW) tags[slot] = q;
  }
  barrier(CLK_LOCAL_MEM_FENCE);  // l_n / l_base are reused by the next append
}

// Which slot work-item i works on, and whether it has one. A queue launch (dense == 0) runs
// `count` work-items over the queue's entries. A dense launch (dense != 0) runs one work-item
// per pool slot, in slot order, and works on the slots whose tag is `qid`: the same set of
// paths, since every append also sets the tag (wg_append). The host launches dense when a
// queue holds most of the pool: neighbouring work-items then touch neighbouring words of
// the SoA state instead of slots scattered by earlier appends (docs/performance.md has the
// measurement).
#define AW_DENSE_ITEM(qid, slot_out, active_out)                        \
  if (dense) {                                                         \
    slot_out = i;                                                      \
    active_out = i < rp.pool_size && tags[i] == (uint)(qid);           \
  } else {                                                             \
    slot_out = i < count ? AW_QUEUE(qid)[i] : 0u;                      \
    active_out = i < count;                                            \
  }

#define AW_PATH_REF(slot_index) \
  PathRef ps;                   \
  ps.sf = sf;                   \
  ps.su = su;                   \
  ps.snap_f = 0;                \
  ps.snap_u = 0;                \
  ps.pool = rp.pool_size;       \
  ps.slot = (slot_index)

#define AW_SCENE_REF          \
  SceneRef sc;                \
  sc.tri_info = tri_info;     \
  sc.verts = verts;           \
  sc.materials = materials;   \
  sc.lights = lights

#define AW_QUEUE(q) (queues + (q) * rp.pool_size)

__kernel __attribute__((reqd_work_group_size(AW_WG, 1, 1)))
void regenerate(const RenderParams rp, __global float* sf, __global uint* su, __global uint* queues,
                __global uint* counters, uint count, uint job_start, __global uint* tags) {
  __local uint l_n[AW_Q_COUNT], l_base[AW_Q_COUNT];
  uint i = get_global_id(0);
  uint q = AW_Q_COUNT;
  uint slot = 0u;
  if (i < count) {
    slot = AW_QUEUE(AW_Q_FREE)[i];
    AW_PATH_REF(slot);
    generate_camera_ray(ps, &rp, job_start + i);
    q = AW_Q_RAY;
  }
  wg_append(counters, queues, tags, rp.pool_size, q, slot, l_n, l_base);
}

__kernel __attribute__((reqd_work_group_size(AW_WG, 1, 1)))
void intersect_closest(const RenderParams rp, __global float* sf, __global uint* su, __global const uint* queues,
                       uint count, __global const float4* nodes, __global const float4* tris,
                       __global const LightGpu* lights, uint dense, __global const uint* tags) {
  uint i = get_global_id(0);
  uint slot;
  int active;
  AW_DENSE_ITEM(AW_Q_RAY, slot, active);
  if (!active) return;
  AW_PATH_REF(slot);
  float3 o = ps_ray_origin(ps), d = ps_ray_dir(ps);
  float tmin = PS_F(ps, ray_tmin);
  TriangleHit h = bvh_intersect(nodes, rp.num_nodes, tris, o, d, tmin, FLT_MAX, 0);
  float t = h.t;
  int light = lights_intersect(lights, rp.num_lights, o, d, tmin, &t, PS_U(ps, bounce) == 0u, -1);
  if (light >= 0) ps_set_hit(ps, t, 0.0f, 0.0f, AW_NONE, (uint)light);
  else ps_set_hit(ps, h.t, h.u, h.v, h.prim >= 0 ? (uint)h.prim : AW_NONE, AW_NONE);
}

__kernel __attribute__((reqd_work_group_size(AW_WG, 1, 1)))
void classify_hit_stage(const RenderParams rp, __global float* sf, __global uint* su, __global uint* queues,
                        __global uint* counters, uint count, __global const TriangleInfo* tri_info,
                        __global const VertexData* verts, __global const MaterialGpu* materials,
                        __global const LightGpu* lights, uint dense, __global uint* tags) {
  __local uint l_n[AW_Q_COUNT], l_base[AW_Q_COUNT];
  uint i = get_global_id(0);
  uint q = AW_Q_COUNT;
  uint slot;
  int active;
  AW_DENSE_ITEM(AW_Q_RAY, slot, active);
  if (active) {
    AW_PATH_REF(slot);
    AW_SCENE_REF;
    q = (uint)classify_hit(ps, sc, &rp);
  }
  wg_append(counters, queues, tags, rp.pool_size, q, slot, l_n, l_base);
}

// Cutout pass-through: classify_hit consumed the RAY queue, so these wait in PASS until the
// RAY queue can take new rays.
__kernel __attribute__((reqd_work_group_size(AW_WG, 1, 1)))
void pass_through(const RenderParams rp, __global uint* queues, __global uint* counters, uint count,
                  __global uint* tags) {
  __local uint l_n[AW_Q_COUNT], l_base[AW_Q_COUNT];
  uint i = get_global_id(0);
  uint slot = i < count ? AW_QUEUE(AW_Q_PASS)[i] : 0u;
  wg_append(counters, queues, tags, rp.pool_size, i < count ? AW_Q_RAY : AW_Q_COUNT, slot, l_n, l_base);
}

// One shading kernel per lobe queue (kernels/integrator/shade_surface.h).
#define AW_SHADE_KERNEL(name, lid)                                                                       \
  __kernel __attribute__((reqd_work_group_size(AW_WG, 1, 1))) void name(                                 \
      const RenderParams rp, __global float* sf, __global uint* su, __global uint* queues,               \
      __global uint* counters, uint count, __global const TriangleInfo* tri_info,                       \
      __global const VertexData* verts, __global const MaterialGpu* materials,                          \
      __global const LightGpu* lights, __global float* snap_f, __global uint* snap_u, uint dense,        \
      __global uint* tags) {                                                                             \
    __local uint l_n[AW_Q_COUNT], l_base[AW_Q_COUNT];                                                    \
    uint i = get_global_id(0);                                                                           \
    uint q = AW_Q_COUNT, qs = AW_Q_COUNT;                                                                \
    uint slot;                                                                                           \
    int active;                                                                                          \
    AW_DENSE_ITEM(AW_Q_LOBE + (lid), slot, active);                                                      \
    if (active) {                                                                                        \
      AW_PATH_REF(slot);                                                                                 \
      ps.snap_f = snap_f;                                                                                \
      ps.snap_u = snap_u;                                                                                \
      AW_SCENE_REF;                                                                                      \
      q = (uint)shade_surface(ps, sc, &rp, (lid));                                                       \
      if (PS_U(ps, flags) & AW_PATH_HAS_SHADOW) qs = AW_Q_SHADOW;                                         \
    }                                                                                                    \
    wg_append(counters, queues, tags, rp.pool_size, qs, slot, l_n, l_base);                                    \
    wg_append(counters, queues, tags, rp.pool_size, q, slot, l_n, l_base);                                     \
  }

// Only the lobes this build has (kernels/common/features.h); the host launches only these.
AW_SHADE_KERNEL(shade_diffuse, AW_LID_DIFFUSE)
#if AW_FEAT_TRANSLUCENCY
AW_SHADE_KERNEL(shade_translucency, AW_LID_TRANSLUCENCY)
#endif
#if AW_FEAT_REFLECTION
AW_SHADE_KERNEL(shade_reflection, AW_LID_REFLECTION)
AW_SHADE_KERNEL(shade_reflection2, AW_LID_REFLECTION2)
#endif
#if AW_FEAT_REFRACTION
AW_SHADE_KERNEL(shade_refraction, AW_LID_REFRACTION)
#endif

__kernel __attribute__((reqd_work_group_size(AW_WG, 1, 1)))
void intersect_shadow(const RenderParams rp, __global float* sf, __global uint* su, __global const uint* queues,
                      uint count, __global const float4* nodes, __global const float4* tris,
                      __global const LightGpu* lights, __global const TriangleInfo* tri_info,
                      __global const MaterialGpu* materials, uint dense) {
  uint i = get_global_id(0);
  uint slot;
  int active;
  if (dense) {  // SHADOW is not a tag (wg_append): the path's flag says it has a shadow ray
    slot = i;
    active = i < rp.pool_size && (su[(uint)AW_SU_flags * rp.pool_size + i] & AW_PATH_HAS_SHADOW) != 0u;
  } else {
    slot = i < count ? AW_QUEUE(AW_Q_SHADOW)[i] : 0u;
    active = i < count;
  }
  if (!active) return;
  AW_PATH_REF(slot);
  float3 o = ps_shadow_origin(ps), d = ps_shadow_dir(ps);
  float tmax = PS_F(ps, sh_tmax);
#if AW_FEAT_CUTOUT
  // Step through cutout surfaces with closest hits (the traversal accepts t > t_min only, so
  // each step starts strictly beyond the surface it passed).
  SceneRef sc;
  sc.tri_info = tri_info;
  sc.materials = materials;
  int occluded = 0;
  float t0 = 0.0f;
  for (int k = 0; k < AW_SHADOW_CUTOUT_STEPS; ++k) {
    TriangleHit h = bvh_intersect(nodes, rp.num_nodes, tris, o, d, t0, tmax, 0);
    if (h.prim < 0) break;
    if (!surface_is_cutout(sc, (uint)h.prim) || k == AW_SHADOW_CUTOUT_STEPS - 1) {
      occluded = 1;
      break;
    }
    t0 = h.t;
  }
#else
  int occluded = bvh_intersect(nodes, rp.num_nodes, tris, o, d, 0.0f, tmax, 1).prim >= 0;
#endif
  if (!occluded) {
    float t = tmax;
    occluded = lights_intersect(lights, rp.num_lights, o, d, 0.0f, &t, 0, (int)PS_U(ps, sh_light)) >= 0;
  }
  shade_shadow(ps, occluded);
}

// A split path (integrator/split.h) goes back to its first-hit lobe queue until its last
// split ends; only then does the job's value (the mean of the splits) reach `samples`.
__kernel __attribute__((reqd_work_group_size(AW_WG, 1, 1)))
void accumulate(const RenderParams rp, __global float* sf, __global uint* su, __global uint* queues,
                __global uint* counters, uint count, __global float* samples, __global uint* stats,
                __global float* snap_f, __global uint* snap_u, __global uint* tags) {
  __local uint l_n[AW_Q_COUNT], l_base[AW_Q_COUNT];
  uint i = get_global_id(0);
  uint slot = 0u;
  uint q = AW_Q_COUNT;
  if (i < count) {
    slot = AW_QUEUE(AW_Q_DONE)[i];
    AW_PATH_REF(slot);
    ps.snap_f = snap_f;
    ps.snap_u = snap_u;
    int bad;
    float3 l = path_result(ps, &rp, &bad);
    if (bad) atomic_inc(&stats[AW_STAT_BAD_SAMPLES]);
    if (PS_U(ps, flags) & AW_PATH_MISSING_FEATURE) atomic_inc(&stats[AW_STAT_MISSING_FEATURE]);
    q = AW_Q_FREE;
#if AW_FEAT_SPLIT
    if ((PS_U(ps, flags) & AW_PATH_SPLIT) && split_next(ps, &rp, l, &l)) q = AW_Q_LOBE + PS_U(ps, lobe);
#endif
    if (q == AW_Q_FREE) {
      uint job = PS_U(ps, job);
      samples[job * 3u + 0u] = l.x;
      samples[job * 3u + 1u] = l.y;
      samples[job * 3u + 2u] = l.z;
    }
  }
  wg_append(counters, queues, tags, rp.pool_size, q, slot, l_n, l_base);
}

// Adds a finished batch to the film, one work-item per pixel, samples in increasing sample
// order: the same summation order as the scalar path, so the two films match bit for bit
// when the sample values do, whatever the pool size or batch split.
__kernel __attribute__((reqd_work_group_size(AW_WG, 1, 1)))
void film_accumulate(const RenderParams rp, __global const float* samples, __global float* film,
                     __global uint* film_count) {
  uint p = get_global_id(0);
  uint npix = rp.width * rp.height;
  if (p >= npix) return;
  uint i = (p + npix - rp.batch_pixel) % npix;  // first batch-local job of pixel p
  float3 sum = make_float3(film[p * 3u + 0u], film[p * 3u + 1u], film[p * 3u + 2u]);
  uint n = 0u;
  for (; i < rp.job_count; i += npix) {
    sum.x += samples[i * 3u + 0u];
    sum.y += samples[i * 3u + 1u];
    sum.z += samples[i * 3u + 2u];
    ++n;
  }
  film[p * 3u + 0u] = sum.x;
  film[p * 3u + 1u] = sum.y;
  film[p * 3u + 2u] = sum.z;
  film_count[p] += n;
}
