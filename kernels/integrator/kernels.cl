// The wavefront's OpenCL entry points. Each is a thin wrapper: index -> bounds check ->
// shared stage function (kernels/integrator/*.h, the same code the host scalar path runs)
// -> aggregated queue appends. The scheduling rule is in integrator/queues.h.
//
// Launch contract (host/render/wavefront.cpp): an explicit local size AW_WG and a global size
// padded up to a multiple of it; `count` is the real number of items. Every work-item of a
// group reaches the appends (they contain barriers), so the bounds check only masks work.
#ifdef cl_khr_fp64
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#endif

#include "bvh/traverse.h"
#include "integrator/accumulate.h"
#include "integrator/classify_hit.h"
#include "integrator/generate_camera_ray.h"
#include "integrator/path_state.h"
#include "integrator/queues.h"
#include "integrator/shade_diffuse.h"
#include "integrator/shade_shadow.h"

#ifndef AW_WG
#define AW_WG 64
#endif

// Queue append aggregated per work-group: a local counter gives each item its offset, then
// one global atomic per group reserves the range (~6x faster than a global atomic per item
// on PoCL, DESIGN.md). Must be reached by every work-item of the group.
static inline void wg_append(__global uint* counters, uint q, __global uint* queue, uint slot, int want,
                             __local uint* l_n, __local uint* l_base) {
  if (get_local_id(0) == 0) *l_n = 0u;
  barrier(CLK_LOCAL_MEM_FENCE);
  uint off = want ? atomic_inc(l_n) : 0u;
  barrier(CLK_LOCAL_MEM_FENCE);
  if (get_local_id(0) == 0) *l_base = (*l_n > 0u) ? atomic_add(&counters[q], *l_n) : 0u;
  barrier(CLK_LOCAL_MEM_FENCE);
  if (want) queue[*l_base + off] = slot;
  barrier(CLK_LOCAL_MEM_FENCE);  // l_n/l_base are reused by the next append
}

#define AW_PATH_REF(slot_index) \
  PathRef ps;             \
  ps.sf = sf;             \
  ps.su = su;             \
  ps.pool = rp.pool_size; \
  ps.slot = (slot_index)

#define AW_SCENE_REF          \
  SceneRef sc;                \
  sc.tri_info = tri_info;     \
  sc.verts = verts;           \
  sc.materials = materials;   \
  sc.lights = lights

__kernel __attribute__((reqd_work_group_size(AW_WG, 1, 1)))
void regenerate(const RenderParams rp, __global float* sf, __global uint* su, __global const uint* free_q,
                uint count, uint job_start, __global uint* ray_q, __global uint* counters) {
  __local uint l_n, l_base;
  uint i = get_global_id(0);
  int active = i < count;
  uint slot = active ? free_q[i] : 0u;
  if (active) {
    AW_PATH_REF(slot);
    generate_camera_ray(ps, &rp, job_start + i);
  }
  wg_append(counters, AW_Q_RAY, ray_q, slot, active, &l_n, &l_base);
}

__kernel __attribute__((reqd_work_group_size(AW_WG, 1, 1)))
void intersect_closest(const RenderParams rp, __global float* sf, __global uint* su, __global const uint* ray_q,
                       uint count, __global const float4* nodes, __global const float4* tris,
                       __global const LightGpu* lights) {
  uint i = get_global_id(0);
  if (i >= count) return;
  AW_PATH_REF(ray_q[i]);
  float3 o = ps_ray_origin(ps), d = ps_ray_dir(ps);
  TriangleHit h = bvh_intersect(nodes, rp.num_nodes, tris, o, d, 0.0f, FLT_MAX, 0);
  float t = h.t;
  int light = lights_intersect(lights, rp.num_lights, o, d, 0.0f, &t, PS_U(ps, bounce) == 0u, -1);
  if (light >= 0) ps_set_hit(ps, t, 0.0f, 0.0f, AW_NONE, (uint)light);
  else ps_set_hit(ps, h.t, h.u, h.v, h.prim >= 0 ? (uint)h.prim : AW_NONE, AW_NONE);
}

__kernel __attribute__((reqd_work_group_size(AW_WG, 1, 1)))
void classify_hit_stage(const RenderParams rp, __global float* sf, __global uint* su, __global const uint* ray_q,
                        uint count, __global const TriangleInfo* tri_info, __global const VertexData* verts,
                        __global const MaterialGpu* materials, __global const LightGpu* lights,
                        __global uint* diffuse_q, __global uint* done_q, __global uint* counters) {
  __local uint l_n, l_base;
  uint i = get_global_id(0);
  int active = i < count;
  uint slot = active ? ray_q[i] : 0u;
  int next = AW_Q_DONE;
  if (active) {
    AW_PATH_REF(slot);
    AW_SCENE_REF;
    next = classify_hit(ps, sc, &rp);
  }
  wg_append(counters, AW_Q_DIFFUSE, diffuse_q, slot, active && next == AW_Q_DIFFUSE, &l_n, &l_base);
  wg_append(counters, AW_Q_DONE, done_q, slot, active && next == AW_Q_DONE, &l_n, &l_base);
}

__kernel __attribute__((reqd_work_group_size(AW_WG, 1, 1)))
void shade_diffuse_stage(const RenderParams rp, __global float* sf, __global uint* su, __global const uint* diffuse_q,
                         uint count, __global const TriangleInfo* tri_info, __global const VertexData* verts,
                         __global const MaterialGpu* materials, __global const LightGpu* lights,
                         __global uint* ray_q, __global uint* shadow_q, __global uint* done_q,
                         __global uint* counters) {
  __local uint l_n, l_base;
  uint i = get_global_id(0);
  int active = i < count;
  uint slot = active ? diffuse_q[i] : 0u;
  int next = AW_Q_DONE, shadow = 0;
  if (active) {
    AW_PATH_REF(slot);
    AW_SCENE_REF;
    next = shade_diffuse(ps, sc, &rp);
    shadow = (PS_U(ps, flags) & AW_PATH_HAS_SHADOW) != 0u;
  }
  wg_append(counters, AW_Q_SHADOW, shadow_q, slot, active && shadow, &l_n, &l_base);
  wg_append(counters, AW_Q_RAY, ray_q, slot, active && next == AW_Q_RAY, &l_n, &l_base);
  wg_append(counters, AW_Q_DONE, done_q, slot, active && next == AW_Q_DONE, &l_n, &l_base);
}

__kernel __attribute__((reqd_work_group_size(AW_WG, 1, 1)))
void intersect_shadow(const RenderParams rp, __global float* sf, __global uint* su, __global const uint* shadow_q,
                      uint count, __global const float4* nodes, __global const float4* tris,
                      __global const LightGpu* lights) {
  uint i = get_global_id(0);
  if (i >= count) return;
  AW_PATH_REF(shadow_q[i]);
  float3 o = ps_shadow_origin(ps), d = ps_shadow_dir(ps);
  float tmax = PS_F(ps, sh_tmax);
  int occluded = bvh_intersect(nodes, rp.num_nodes, tris, o, d, 0.0f, tmax, 1).prim >= 0;
  if (!occluded) {
    float t = tmax;
    occluded = lights_intersect(lights, rp.num_lights, o, d, 0.0f, &t, 0, (int)PS_U(ps, sh_light)) >= 0;
  }
  shade_shadow(ps, occluded);
}

__kernel __attribute__((reqd_work_group_size(AW_WG, 1, 1)))
void accumulate(const RenderParams rp, __global float* sf, __global uint* su, __global const uint* done_q,
                uint count, __global float* samples, __global uint* free_q, __global uint* counters,
                __global uint* stats) {
  __local uint l_n, l_base;
  uint i = get_global_id(0);
  int active = i < count;
  uint slot = active ? done_q[i] : 0u;
  if (active) {
    AW_PATH_REF(slot);
    int bad;
    float3 l = path_result(ps, &rp, &bad);
    if (bad) atomic_inc(&stats[AW_STAT_BAD_SAMPLES]);
    uint job = PS_U(ps, job);
    samples[job * 3u + 0u] = l.x;
    samples[job * 3u + 1u] = l.y;
    samples[job * 3u + 2u] = l.z;
  }
  wg_append(counters, AW_Q_FREE, free_q, slot, active, &l_n, &l_base);
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
