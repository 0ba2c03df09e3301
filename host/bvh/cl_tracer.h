// Traces batches of rays through the flattened BVH with the OpenCL kernel
// (kernels/bvh/trace_rays.cl): the BVH tests compare it with Embree, bench/ times it.
#pragma once

#include <vector>

#include "host/bvh/flat_bvh.h"
#include "host/cl/cl_runtime.h"
#include "kernels/bvh/traverse.h"

namespace aw {

struct RayIn {
  glm::vec3 org;
  float t_min;
  glm::vec3 dir;
  float t_max;
};
static_assert(sizeof(RayIn) == 32, "RayIn is two float4 on the device");

class ClTracer {
 public:
  // lanes 1: the one-ray traversal (kernel trace_rays); 16: the lane traversal, 16 rays per
  // work-item (trace_rays_lanes, kernels/bvh/traverse_lanes.h; no instances).
  ClTracer(ClRuntime& rt, const FlatBvh& bvh, const std::string& kernel_dir = "", int lanes = 1);
  // Traces all rays; returns one hit per ray (prim = -1 for a miss, inst = AW_NONE outside instances). *seconds gets the
  // kernel time only (upload and download excluded), when given.
  std::vector<TriangleHit> trace(const std::vector<RayIn>& rays, bool any_hit, double* seconds = nullptr);

 private:
  ClRuntime& rt_;
  cl::Program program_;
  cl::Kernel kernel_;
  cl::Buffer nodes_, tris_, insts_;
  uint32_t num_nodes_;
  int lanes_;
};

}  // namespace aw
