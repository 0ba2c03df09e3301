// Ray batches through the flattened BVH, for the BVH tests and the traversal benchmark.
// rays: 8 floats per ray (ox, oy, oz, t_min, dx, dy, dz, t_max); hits: (t, u, v, prim bits);
// hit_inst: the hit's instance (AW_NONE for world geometry, types/bvh.h).
#ifdef cl_khr_fp64
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#endif
#include "bvh/traverse.h"

#ifndef AW_WG
#define AW_WG 64
#endif

#if AW_LANES == 1
// Scalar on Intel's runtime, as the render's ray stages (common/compat.h).
__kernel AW_SCALAR_KERNEL __attribute__((reqd_work_group_size(AW_WG, 1, 1)))
void trace_rays(uint count, uint any_hit, __global const float4* rays, __global const float4* nodes, uint num_nodes,
                __global const float4* tris, __global const InstanceGpu* insts, __global float4* hits,
                __global uint* hit_inst) {
  uint i = get_global_id(0);
  if (i >= count) return;
  float4 a = rays[2 * i], b = rays[2 * i + 1];
  TriangleHit h = bvh_intersect(nodes, num_nodes, tris, insts, (float3)(a.x, a.y, a.z), (float3)(b.x, b.y, b.z),
                                a.w, b.w, (int)any_hit);
  hits[i] = (float4)(h.t, h.u, h.v, as_float(h.prim));
  hit_inst[i] = h.inst;
}

#else
// The lane traversal (bvh/traverse_lanes.h, a program built with -DAW_LANES=16): W rays per
// work-item, rays i0 .. i0 + W - 1; lanes past `count` take no part.
__kernel AW_SCALAR_KERNEL __attribute__((reqd_work_group_size(AW_WG, 1, 1)))
void trace_rays_lanes(uint count, uint any_hit, __global const float* rays, __global const float4* nodes,
                      uint num_nodes, __global const float4* tris, __global const InstanceGpu* insts,
                      __global float* hits, __global uint* hit_inst) {
  uint i0 = get_global_id(0) * AW_LANES;
  if (i0 >= count) return;
  // The rays' eight floats, lane by lane, into one vector per field (a lane past the end
  // repeats the last ray and is masked off).
  float f[8 * AW_LANES];
  for (uint k = 0u; k < AW_LANES; ++k) {
    uint i = min(i0 + k, count - 1u);
    for (uint j = 0u; j < 8u; ++j) f[j * AW_LANES + k] = rays[8u * i + j];
  }
  TriangleHit h;
  {
    uint idx[AW_LANES];
    for (uint k = 0u; k < AW_LANES; ++k) idx[k] = i0 + k;
    lmask active = L_LOAD(idx, 0) < (luint)(count);
    lfloat3 org = make_lfloat3(L_LOAD(f, 0), L_LOAD(f, 1), L_LOAD(f, 2));
    lfloat3 dir = make_lfloat3(L_LOAD(f, 4), L_LOAD(f, 5), L_LOAD(f, 6));
    h = bvh_intersect_lanes(nodes, num_nodes, tris, org, dir, L_LOAD(f, 3), L_LOAD(f, 7), (int)any_hit, active);
  }
  float t[AW_LANES], u[AW_LANES], v[AW_LANES];
  int prim[AW_LANES];
  uint inst[AW_LANES];
  L_STORE(h.t, t, 0);
  L_STORE(h.u, u, 0);
  L_STORE(h.v, v, 0);
  L_STORE(h.prim, prim, 0);
  L_STORE(h.inst, inst, 0);
  for (uint k = 0u; k < AW_LANES && i0 + k < count; ++k) {
    uint i = i0 + k;
    hits[4u * i + 0u] = t[k];
    hits[4u * i + 1u] = u[k];
    hits[4u * i + 2u] = v[k];
    hits[4u * i + 3u] = as_float(prim[k]);
    hit_inst[i] = inst[k];
  }
}
#endif
