// What both renderers (wavefront on OpenCL, scalar on the host) take and return.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "host/cl/cl_runtime.h"
#include "host/film/image_io.h"
#include "host/render/scene_pack.h"
#include "host/scene/scene.h"

namespace aw {

struct RenderResult;

// A rectangle of frame pixels, [x0, x1) x [y0, y1), as pbrt's --pixelbounds; empty (the
// default) = the whole frame.
struct PixelBounds {
  int x0 = 0, x1 = 0, y0 = 0, y1 = 0;
  bool empty() const { return x1 <= x0 || y1 <= y0; }
};

struct RenderOptions {
  int device = kDefaultDevice;  // OpenCL device index (wavefront only); kDefaultDevice: see cl_runtime.h
  uint32_t pool_size = 0;     // path states in flight; 0 = default (2^16 on Intel's CPU runtime, 2^18 on other CPU devices, 2^20 on a GPU, or $ARCHWAVE_POOL)
  uint32_t max_batch = 0;     // jobs per film batch; 0 = default (4 × pool)
  // Queues holding at least this share of the pool run as dense launches (slot order, see
  // host/render/wavefront.cpp); negative = the default. 0 = always dense, > 1 = never.
  double dense_fraction = -1.0;
  int threads = 0;            // scalar path threads; 0 = hardware concurrency
  bool progress = false;      // progress line on stderr
  std::string progress_label;  // its label ("" = "rendering"), e.g. naming the part
  std::string kernel_dir;     // "" = embedded kernels
  std::string build_options;  // extra OpenCL build options (never fast-math in tests)
  // Film snapshots on the host (wavefront): at most every this many seconds, and at most ~1%
  // of the render's time (RenderDeviceError keeps the last); 0 = after every batch; < 0 = none.
  double snapshot_seconds = 2.0;
  bool generic_kernels = false;  // build every feature in, not just what the scene uses
  // On a CPU device, run the stages written on lanes 16 paths per work-item when the scene
  // allows it (kernels/integrator/kernels_lanes.cl); false: every stage one path per work-item.
  bool lanes = true;
  // With lanes: the ray stages too (the lane traversal, kernels/bvh/traverse_lanes.h)?
  // -1: where it was measured to pay on this device for a scene of this size (wavefront.cpp,
  // lane_traversal_limit); 1: whenever the scene allows it; 0: never.
  int lane_traversal = -1;
  // With lanes: paths per work-item of the ray stages and classification (8 or 16); 0: the
  // device's choice (wavefront.cpp, narrow_lane_width). The other lane stages run 16.
  int narrow_lanes = 0;
  std::vector<std::string> force_off;  // feature names to compile out anyway (tests of the guard)
  const std::atomic<bool>* cancel = nullptr;  // set asynchronously (SIGINT): stop, keep what is done
  // Parts of a frame (docs/production.md). The film covers `window` (empty: the whole frame)
  // and each of its pixels the samples [sample_start, sample_end) (sample_end 0: render.spp).
  PixelBounds window;
  uint32_t sample_start = 0, sample_end = 0;
  // > 0: once this many seconds have passed since the render began, finish the sample pass
  // under way (every pixel one more sample) and stop there (stats.time_limited).
  double time_limit = 0.0;
  // > 0: call `checkpoint` with the film so far (acc, count; stats so far) this often, at
  // batch ends (the wavefront) or pass ends (the scalar path).
  double checkpoint_seconds = 0.0;
  std::function<void(const RenderResult&)> checkpoint;
  // Continue this film (its acc and count) instead of an empty one: same scene (scene_hash),
  // window and sample_start; samples up to sample_end (which may exceed the film's).
  const RenderResult* resume = nullptr;
};

struct RenderStats {
  std::string renderer;  // "wavefront" or "scalar"
  std::string device;
  std::string device_choice;  // why this device, when the CLI chose it (host/render/device_choice.h)
  double total_seconds = 0.0;
  double bvh_seconds = 0.0;
  double compile_seconds = 0.0;
  // Wavefront: packing the scene, opening the device (an OpenCL context: on a GPU driver that
  // starts the GPU's runtime) and allocating and filling its buffers; 0 for the scalar path.
  double setup_seconds = 0.0;
  // The time the samples took: total less BVH, kernel build and setup (what Msamples/s divide).
  double path_seconds() const;
  std::string kernel_build;  // how the program was had (ClRuntime::last_build), "" for the scalar path
  std::string kernel_features;  // "generic" or the specialised feature list
  std::string lanes;  // which stages ran on lanes, or why none did ("" for the scalar path)
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
  bool time_limited = false;   // stopped by RenderOptions::time_limit at a whole sample pass
  uint32_t checkpoints = 0;    // films handed to RenderOptions::checkpoint
  uint64_t resumed_samples = 0;  // samples the film held when the render began (--resume)
  // Host copies of the device's film taken while rendering (wavefront), so that a device lost
  // mid-render still leaves the film as of the last one (RenderDeviceError); and their cost.
  uint32_t film_snapshots = 0;
  double snapshot_seconds = 0.0;
  std::string device_error;  // the OpenCL error that ended the render early ("" = none)
  std::vector<std::string> warnings;
  std::string summary() const;  // multi-line human-readable stats
};

// The film: what a render (or a part of one) holds. width x height pixels at (x0, y0) of a
// frame_width x frame_height frame; pixel p holds the samples [sample_start, sample_start +
// count[p]) of the samples [sample_start, sample_end) the render covers.
struct RenderResult {
  int width = 0, height = 0;
  int x0 = 0, y0 = 0, frame_width = 0, frame_height = 0;
  uint32_t sample_start = 0, sample_end = 0;
  uint64_t scene_hash = 0;       // scene_identity (host/render/scene_pack.h)
  std::vector<uint64_t> acc;     // per pixel AW_FILM_WORDS: exact RGB sums (kernels/integrator/film.h)
  std::vector<float> sum;        // per pixel RGB: acc's sums rounded to float
  std::vector<uint32_t> count;   // samples per pixel
  // AOVs (kernels/integrator/aov.h): the mask the render wrote and, per pixel, the exact
  // signed sums of their aov_film_channels(aov_mask) channels, 2 words each.
  uint32_t aov_mask = 0;
  std::vector<uint64_t> aov_acc;
  RenderStats stats;
  uint32_t min_spp() const;
  // Fills `sum` from `acc`.
  void update_sums();
  // The averaged, exposed image with spp/seed/device in its header attributes; with_state adds
  // what resuming and merging need (docs/production.md: the archwave_film channels).
  Image image(const Scene& scene, bool with_state = false) const;
};

// An OpenCL error in the middle of a wavefront render (a device lost or out of resources):
// what names the call, the error code and the device; `partial` holds the film as the device
// last gave it (every pixel's completed samples, resumable with RenderOptions::resume), read
// back after the error when the device still answers, else the last snapshot
// (RenderStats::film_snapshots). Null when nothing was kept (the error came before any
// snapshot and the device no longer answers). docs/production.md#a-device-lost-mid-render.
class RenderDeviceError : public ClError {
 public:
  RenderDeviceError(const std::string& what, std::shared_ptr<RenderResult> kept)
      : ClError(what), partial(std::move(kept)) {}
  std::shared_ptr<RenderResult> partial;
};

// Throws SceneError for a scene the build cannot render, ClError for an OpenCL error before
// rendering began (device set-up, kernel build, allocations) and RenderDeviceError for one
// after. ARCHWAVE_FAULT (testing only: "launch:N" fails the Nth stage launch with
// CL_OUT_OF_RESOURCES, "lost:N" also fails every OpenCL call after it, as a lost device does)
// injects such an error.
RenderResult render_wavefront(const Scene& scene, const RenderOptions& opts);

// Paths per work-item of the lane program's ray stages and classification on `device`:
// RenderOptions::narrow_lanes when it is 8 or 16, else (0) 8 on Intel's CPU runtime where a
// SIMD register holds 8 floats, 16 otherwise. Throws std::invalid_argument for any other value.
uint32_t narrow_lane_width(const DeviceInfo& device, int narrow_lanes);

// Work-items per work-group of the lane programs on `device`: 32 on Intel's CPU runtime, whose
// threads take whole groups, so that a launch is shared out evenly; 256 (the one-path
// kernels' size) elsewhere. The image does not depend on it.
uint32_t lane_work_group(const DeviceInfo& device);

// Both renderers' start: sets res's film (window, sample range, scene_hash; acc and count
// empty or the resumed film's) from the scene, the options and the scene's parameters, and
// narrows rp to the window and sample_start. Returns the first sample some pixel lacks.
// Throws SceneError for a window outside the frame, an empty or out-of-range sample range,
// or a resume film of another scene, window or range (naming what differs).
uint32_t begin_film(const Scene& scene, const RenderOptions& opts, const PackedScene& packed, RenderParams& rp,
                    RenderResult& res);
RenderResult render_scalar(const Scene& scene, const RenderOptions& opts);

}  // namespace aw
