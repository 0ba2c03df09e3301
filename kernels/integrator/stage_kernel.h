// What every wavefront entry point shares (integrator/kernels.cl, one path per work-item;
// integrator/kernels_lanes.cl, 16 paths per work-item): the one parameter list, the path and
// scene handles built from it, the aggregated queue appends and the slot a work-item works on.
// OpenCL C only: included by the .cl files after the stage headers they use.
#ifndef AW_INTEGRATOR_STAGE_KERNEL_H
#define AW_INTEGRATOR_STAGE_KERNEL_H

#include "integrator/path_state.h"
#include "integrator/queues.h"
#include "integrator/scene_ref.h"
#include "integrator/stage_args.h"

#ifndef AW_WG
#define AW_WG 256
#endif

// Every stage kernel: the same attributes and the same parameters (stage_args.h).
#define AW_STAGE_PARAM_VALUE(type, name) , const type name
#define AW_STAGE_PARAM_BUFFER(type, name) , __global type* name

// Every stage runs one work-item at a time on a compiler that would vectorise across
// work-items (Intel's CPU runtime: AW_SCALAR_KERNEL, common/compat.h; nothing changes on PoCL or
// a GPU). Measured on Intel's runtime 2026.2 (docs/performance.md, "Per-stage vectorisation on
// Intel's runtime" and "Vector width on an AVX-512 Xeon"):
// - the ray stages: vectorised traversal gathers 8-16 rays' nodes per lane and ran at 0.4x its
//   scalar speed (AVX2 EPYC, Cornell box: closest 3.5-3.9 vs 8.1-9.0 M rays/s, shadow 3.2-3.9
//   vs 11.6-12.8); the bookkeeping stages gained a little from scalar code too;
// - the shading stages: level vectorised and scalar on the AVX2 EPYC (-9% and +8% on two
//   scenes); on an AVX-512 Xeon the runtime's own cost model keeps them scalar, and forced to 8
//   or 16 lanes they took 1.7-5x their scalar time (bench/vector_width.py). Vectorised, the
//   refraction sampler is also miscompiled (docs/devices.md#known-problems-of-intels-runtime),
//   so scalar shading costs nothing measured and keeps renders clear of it.
// bench/vector_width.py replaces AW_SHADE_KERNEL_ATTR to measure other widths.
#define AW_SHADE_KERNEL_ATTR AW_SCALAR_KERNEL
#define AW_STAGE_KERNEL_WITH(attr, name)                                       \
  __kernel attr __attribute__((reqd_work_group_size(AW_WG, 1, 1))) void name( \
      const RenderParams rp AW_STAGE_ARGS(AW_STAGE_PARAM_VALUE, AW_STAGE_PARAM_BUFFER))
#define AW_STAGE_KERNEL(name) AW_STAGE_KERNEL_WITH(AW_SHADE_KERNEL_ATTR, name)
#define AW_STAGE_KERNEL_SCALAR(name) AW_STAGE_KERNEL_WITH(AW_SCALAR_KERNEL, name)

// The path in slot `slot` and the scene, from the stage arguments.
#define AW_STAGE_PATH(slot) path_ref_make(sf, su, snap_f, snap_u, aov_state, rp.pool_size, (slot))
#define AW_STAGE_SCENE                                                                                          \
  scene_ref_make(tri_info, verts, materials, lights, env, light_tree, tri_light, textures, tex_bindings, texels, \
                 mat_resolved, nodes, tris, insts, rp.num_nodes)
#define AW_QUEUE(q) (queues + (uint)(q) * rp.pool_size)

static inline PathRef path_ref_make(__global float* sf, __global uint* su, __global float* snap_f,
                                    __global uint* snap_u, __global float* aov, uint pool, uint slot) {
  PathRef ps;
  ps.sf = sf;
  ps.su = su;
  ps.snap_f = snap_f;
  ps.snap_u = snap_u;
  ps.aov = aov;
  ps.pool = pool;
  ps.slot = slot;
#if AW_LANES > 1
  PS_SET_LIVE(ps, (lmask)(-1));  // the slots slot .. slot + W - 1; the stage narrows it
#endif
  return ps;
}

static inline SceneRef scene_ref_make(const __global TriangleInfo* tri_info, const __global VertexData* verts,
                                      const __global MaterialGpu* materials, const __global LightGpu* lights,
                                      const __global float* env, const __global LightTreeNode* light_tree,
                                      const __global uint* tri_light, const __global TextureGpu* textures,
                                      const __global TexBindingGpu* tex_bindings, const __global uchar* texels,
                                      __global MaterialGpu* mat_resolved,
                                      const __global float4* nodes, const __global float4* tris,
                                      const __global InstanceGpu* insts, uint num_nodes) {
  SceneRef sc;
  sc.tri_info = tri_info;
  sc.verts = verts;
  sc.materials = materials;
  sc.lights = lights;
  sc.env = env;
  sc.light_tree = light_tree;
  sc.tri_light = tri_light;
  sc.textures = textures;
  sc.tex_bindings = tex_bindings;
  sc.texels = texels;
  sc.mat_resolved = mat_resolved;
  sc.nodes = nodes;
  sc.tris = tris;
  sc.insts = insts;
  sc.num_nodes = num_nodes;
  return sc;
}

// Queue append aggregated per work-group: local counters give each item its offset in its
// queue, then one global atomic per non-empty queue reserves the group's range (~6x faster
// than a global atomic per item on PoCL: docs/design.md, fact F4). `q` is the item's queue,
// or AW_Q_COUNT for none. Must be reached by every work-item of the group.
// It also records the queue in the slot's tag (tags[slot]), which is what a dense launch of
// the queue's consumer tests (see stage_slot below). SHADOW is not a tag: a path in it is
// also in a main queue, and the consumer tests AW_PATH_HAS_SHADOW instead.
// `c` (AW_C_FINISHED + half, integrator/queues.h; AW_C_COUNT for none) is a counter without a
// queue that the item adds one to, in the same aggregation: accumulate's finished jobs.
static inline void wg_append(__global uint* counters, __global uint* queues, __global uint* tags, uint pool,
                             uint q, uint slot, uint c, __local uint* l_n, __local uint* l_base) {
  uint lid = get_local_id(0);
  if (lid < AW_C_COUNT) l_n[lid] = 0u;
  barrier(CLK_LOCAL_MEM_FENCE);
  uint off = q < AW_Q_COUNT ? atomic_inc(&l_n[q]) : 0u;
  if (c >= AW_Q_COUNT && c < AW_C_COUNT) atomic_inc(&l_n[c]);
  barrier(CLK_LOCAL_MEM_FENCE);
  if (lid < AW_C_COUNT) l_base[lid] = l_n[lid] > 0u ? atomic_add(&counters[lid], l_n[lid]) : 0u;
  barrier(CLK_LOCAL_MEM_FENCE);
  if (q < AW_Q_COUNT) {
    queues[q * pool + l_base[q] + off] = slot;
    if (q != AW_Q_SHADOW) tags[slot] = q;
  }
  barrier(CLK_LOCAL_MEM_FENCE);  // l_n / l_base are reused by the next append
}
#define AW_APPEND(q, slot) wg_append(counters, queues, tags, rp.pool_size, (q), (slot), AW_C_COUNT, l_n, l_base)
#define AW_APPEND_COUNTING(q, slot, c) \
  wg_append(counters, queues, tags, rp.pool_size, (q), (slot), (c), l_n, l_base)
#define AW_APPEND_LOCALS __local uint l_n[AW_C_COUNT], l_base[AW_C_COUNT]

// Which slot work-item i works on, and whether it has one. A queue launch (dense == 0) runs
// `count` work-items over the queue's entries. A dense launch (dense != 0) runs one work-item
// per pool slot, in slot order, and works on the slots whose tag is `qid`: the same set of
// paths, since every append also sets the tag (wg_append). The host launches dense when a
// queue holds most of the pool: neighbouring work-items then touch neighbouring words of
// the SoA state instead of slots scattered by earlier appends (docs/architecture.md, "Dense
// launches"). SHADOW is not a tag: a dense shadow launch tests the path's flag instead.
static inline int stage_slot(uint i, uint qid, uint count, uint dense, const __global uint* queues,
                             const __global uint* tags, const __global uint* su, uint pool, uint* slot) {
  if (dense) {
    *slot = i;
    if (i >= pool) return 0;
    if (qid == AW_Q_SHADOW) return (su[(uint)AW_SU_flags * pool + i] & AW_PATH_HAS_SHADOW) != 0u;
    return tags[i] == qid;
  }
  *slot = i < count ? queues[qid * pool + i] : 0u;
  return i < count;
}
#define AW_STAGE_SLOT(qid, slot) stage_slot(get_global_id(0), (qid), count, dense, queues, tags, su, rp.pool_size, &(slot))

#endif
