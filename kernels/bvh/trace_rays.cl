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
