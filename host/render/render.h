// What both renderers (wavefront on OpenCL, scalar on the host) take and return.
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "host/cl/cl_runtime.h"
#include "host/film/image_io.h"
#include "host/scene/scene.h"

namespace aw {

struct RenderOptions {
  int device = kDefaultDevice;  // OpenCL device index (wavefront only); kDefaultDevice: see cl_runtime.h
  uint32_t pool_size = 0;     // path states in flight; 0 = default (2^18, or $ARCHWAVE_POOL)
  uint32_t max_batch = 0;     // jobs per film batch; 0 = default (4 × pool)
  // Queues holding at least this share of the pool run as dense launches (slot order, see
  // host/render/wavefront.cpp); negative = the default. 0 = always dense, > 1 = never.
  double dense_fraction = -1.0;
  int threads = 0;            // scalar path threads; 0 = hardware concurrency
  bool progress = false;      // progress line on stderr
  std::string kernel_dir;     // "" = embedded kernels
  std::string build_options;  // extra OpenCL build options (never fast-math in tests)
  bool generic_kernels = false;  // build every feature in, not just what the scene uses
  std::vector<std::string> force_off;  // feature names to compile out anyway (tests of the guard)
  const std::atomic<bool>* cancel = nullptr;  // set asynchronously (SIGINT): stop, keep what is done
};

struct RenderStats {
  std::string renderer;  // "wavefront" or "scalar"
  std::string device;
  std::string device_choice;  // why this device, when the CLI chose it (host/render/device_choice.h)
  double total_seconds = 0.0;
  double bvh_seconds = 0.0;
  double compile_seconds = 0.0;
  std::string kernel_build;  // how the program was had (ClRuntime::last_build), "" for the scalar path
  std::string kernel_features;  // "generic" or the specialised feature list
  std::vector<std::pair<std::string, double>> stage_seconds;  // in pipeline order
  std::vector<uint64_t> stage_items;  // paths (or pixels) each stage processed, same order
  uint64_t closest_rays = 0;
  uint64_t shadow_rays = 0;
  uint64_t samples = 0;  // completed (pixel, sample) pairs
  uint64_t bad_samples = 0;  // NaN/Inf/negative samples discarded (counted as zero)
  uint64_t iterations = 0;
  size_t state_bytes = 0;  // path pool memory
  uint32_t pool_size = 0;  // path states in flight (wavefront)
  uint64_t triangles = 0;  // triangles in the scene (BVH input)
  uint64_t spheres = 0;    // analytic spheres (BVH input beside the triangles)
  uint64_t instances = 0;  // placements of shared meshes (a two-level BVH)
  uint64_t instanced_triangles = 0;  // triangles as rendered: each instance counts its mesh's
  // Scene data the renderer reads: BVH nodes, leaf triangles, triangle info, vertices,
  // materials, lights (device buffers for the wavefront; the same arrays on the host plus
  // Embree's own BVH, which is not counted, for the scalar path).
  size_t scene_bytes = 0;
  size_t film_bytes = 0;    // film, per-pixel sample counts and the batch's sample buffer
  size_t device_bytes = 0;  // every device buffer of the render (wavefront)
  bool interrupted = false;
  std::vector<std::string> warnings;
  std::string summary() const;  // multi-line human-readable stats
};

struct RenderResult {
  int width = 0, height = 0;
  std::vector<float> sum;        // per pixel RGB sums, summed in sample order
  std::vector<uint32_t> count;   // samples per pixel
  RenderStats stats;
  uint32_t min_spp() const;
  // The averaged image with spp/seed/device in its header attributes.
  Image image(const Scene& scene) const;
};

RenderResult render_wavefront(const Scene& scene, const RenderOptions& opts);
RenderResult render_scalar(const Scene& scene, const RenderOptions& opts);

}  // namespace aw
