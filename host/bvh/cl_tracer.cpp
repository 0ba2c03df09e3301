#include "host/bvh/cl_tracer.h"

#include <chrono>
#include <cstring>
#include <stdexcept>
#include <string>

#include "host/cl/kernel_source.h"

namespace aw {

namespace {
constexpr size_t kWg = 64;
}

ClTracer::ClTracer(ClRuntime& rt, const FlatBvh& bvh, const std::string& kernel_dir, int lanes)
    : rt_(rt), lanes_(lanes) {
  if (lanes != 1 && lanes != 16) throw std::invalid_argument("ClTracer: lanes must be 1 or 16, not " + std::to_string(lanes));
  if (lanes > 1 && !bvh.instances.empty())
    throw std::invalid_argument("ClTracer: the lane traversal has no instances (kernels/bvh/traverse_lanes.h)");
  // Triangles only (AW_FEATURES 0: no analytic-sphere branch in the leaf loop), as the BVH
  // tests and the traversal benchmark measure the triangle traversal against Embree's; the
  // instance branch only for a two-level BVH.
  const unsigned features = bvh.instances.empty() ? 0u : unsigned(AW_FEATBIT_INSTANCE);
  program_ = rt.build(assemble_kernel_source("bvh/trace_rays.cl", kernel_dir),
                      "-cl-std=CL1.2 -DAW_FEATURES=" + std::to_string(features) + "u -DAW_WG=" + std::to_string(kWg) +
                          " -DAW_LANES=" + std::to_string(lanes));
  kernel_ = cl::Kernel(program_, lanes > 1 ? "trace_rays_lanes" : "trace_rays");
  nodes_ = rt.buffer("BVH nodes", bvh.nodes.size() * sizeof(BvhNode), CL_MEM_READ_ONLY,
                     bvh.nodes.empty() ? nullptr : bvh.nodes.data());
  tris_ = rt.buffer("BVH leaf triangles", bvh.leaf_tris.size() * sizeof(LeafTriangle), CL_MEM_READ_ONLY,
                    bvh.leaf_tris.empty() ? nullptr : bvh.leaf_tris.data());
  insts_ = bvh.instances.empty() ? rt.buffer("instances", sizeof(InstanceGpu))
                                 : rt.buffer("instances", bvh.instances.size() * sizeof(InstanceGpu), CL_MEM_READ_ONLY,
                                             bvh.instances.data());
  num_nodes_ = uint32_t(bvh.nodes.size());
}

std::vector<TriangleHit> ClTracer::trace(const std::vector<RayIn>& rays, bool any_hit, double* seconds) {
  std::vector<TriangleHit> out(rays.size());
  if (rays.empty()) return out;
  cl::Buffer in = rt_.buffer("rays", rays.size() * sizeof(RayIn), CL_MEM_READ_ONLY, rays.data());
  cl::Buffer hits = rt_.buffer("hits", rays.size() * 16, CL_MEM_WRITE_ONLY);
  cl::Buffer hit_inst = rt_.buffer("hit instances", rays.size() * 4, CL_MEM_WRITE_ONLY);
  uint32_t n = uint32_t(rays.size());
  kernel_.setArg(0, n);
  kernel_.setArg(1, uint32_t(any_hit ? 1 : 0));
  kernel_.setArg(2, in);
  kernel_.setArg(3, nodes_);
  kernel_.setArg(4, num_nodes_);
  kernel_.setArg(5, tris_);
  kernel_.setArg(6, insts_);
  kernel_.setArg(7, hits);
  kernel_.setArg(8, hit_inst);
  auto& q = rt_.queue();
  q.finish();
  auto t0 = std::chrono::steady_clock::now();
  const size_t items = (n + size_t(lanes_) - 1) / size_t(lanes_);  // one work-item per `lanes_` rays
  q.enqueueNDRangeKernel(kernel_, cl::NullRange, cl::NDRange((items + kWg - 1) / kWg * kWg), cl::NDRange(kWg));
  q.finish();
  if (seconds) *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::vector<float> raw(size_t(n) * 4);
  q.enqueueReadBuffer(hits, CL_TRUE, 0, raw.size() * 4, raw.data());
  std::vector<uint32_t> inst(n);
  q.enqueueReadBuffer(hit_inst, CL_TRUE, 0, size_t(n) * 4, inst.data());
  for (size_t i = 0; i < n; ++i) {
    out[i].t = raw[4 * i];
    out[i].u = raw[4 * i + 1];
    out[i].v = raw[4 * i + 2];
    std::memcpy(&out[i].prim, &raw[4 * i + 3], 4);
    out[i].inst = inst[i];
  }
  return out;
}

}  // namespace aw
