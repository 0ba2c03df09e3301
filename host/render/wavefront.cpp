// The wavefront driver: a fixed pool of path states, one kernel per stage, queues between
// them (kernels/integrator/queues.h has the scheduling rule).
//
// Work is a sequence of jobs (pixel, sample) in sample-major order, processed in batches.
// Within a batch, free slots take the next jobs in order; a finished path writes its sample
// value to samples[job]; at the end of the batch film_accumulate adds the batch to the film
// pixel by pixel in sample order. So the film's summation order is fixed by the job order
// alone: the image does not depend on the pool size, the batch size, or which slot ran what.
//
// Every stage kernel takes the one argument list of kernels/integrator/stage_args.h; the
// driver binds the buffers by the generated AW_ARG_* indices (StageBuffers below) and sets
// the per-launch values the same way, so there is no argument position to keep in step.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <memory>
#include <numeric>
#include <stdexcept>

#include "host/bvh/flat_bvh.h"
#include "host/cl/cl_runtime.h"
#include "host/cl/kernel_source.h"
#include "host/film/progress.h"
#include "host/render/features.h"
#include "host/render/render.h"
#include "host/render/scene_pack.h"
#include "kernels/integrator/aov.h"
#include "kernels/integrator/film.h"
#include "kernels/integrator/path_state.h"
#include "kernels/integrator/queues.h"
#include "kernels/integrator/split.h"
#include "kernels/integrator/stage_args.h"
#include "kernels/material/lobe_list.h"

namespace aw {

namespace {

// Explicit local size everywhere (docs/design.md, fact F3; principle 2). 256 rather than 64:
// PoCL runs a work-group as one task, and its per-task overhead (~5 us) dominated the cheap
// stages at 64 (accumulate: 0.24 s -> 0.07 s for 2.6M paths on the Cornell box); the heavy
// stages do not care.
constexpr uint32_t kWorkGroup = 256;
constexpr uint32_t kLanes = 16;  // paths per vector of the lane program (kernels_lanes.cl, -DAW_LANES)
// Slots per work-item of a lane program: kLaneSpan / W blocks of W (kernels_lanes.cl,
// -DAW_LANE_BLOCKS), whose appends are one atomic per queue per work-item: 16 blocks of 16, or
// 32 of 8 in the narrow program (narrow_lane_width), so that every lane kernel covers the pool
// with pool / kLaneSpan work-items. 256 rather than 64: on an AVX-512 Xeon the atomics, whose
// counters' cache line moves between the cores, were still 7% of the lane program's profile
// at 64, and 256 made the Cornell box render 0.945x the time on Intel's runtime and 0.967x on
// PoCL (regenerate 0.79x and 0.85x, classify_hit 0.90x and 0.87x, shade_diffuse 0.91x and
// 0.94x; the groups kept at the same paths, lane_work_group); 512 gained 1.4% more on Intel's
// runtime (docs/performance.md, "Appends per sixteen blocks").
constexpr uint32_t kLaneSpan = 256;
// Slots per work-item of the sorted closest-hit kernel (kernels_lanes.cl,
// kernel_intersect_closest_sorted, -DAW_SORT_SPAN), one work-item per group: the more rays a
// sort sees, the more alike the rays of each block (Cornell box, triangle tests per block of 16:
// 12.2 over 256 slots, 9.0 over 2,048, 8.3 over 4,096, 7.5 over 16,384; docs/performance.md,
// "Rays sorted before the closest hit"), while a pool of 65,536 still gives 16 work-items for
// the runtime to share out.
constexpr uint32_t kSortSpan = 4096;
// The fewest primitives for which intersect_closest sorts its rays: where the whole tree is a
// root and a few leaves the blocks have little to share and the sort is all cost (race_spheres,
// 4 triangles and 3 spheres: the stage 1.17x its time unsorted; race_small_light, 21
// primitives: 0.92x; the Cornell box, 34: 0.86x; Intel's runtime, Zen 4 EPYC).
constexpr size_t kSortMinPrimitives = 16;
static_assert(kWorkGroup % kLaneSpan == 0, "the pool, a multiple of the group, is whole work-items of the lane program");
constexpr double kDenseFraction = 0.25;  // see Wavefront::launch
// regenerate's lane form runs over the whole pool whatever its count, while its queue form
// costs per path (52 and 57 ns on Intel's runtime and PoCL, the state written a cache line per
// word per path). With one block per work-item the lane form cost 4.0-4.4 ms a launch and
// paid from a third of the pool; with four blocks (a quarter of the atomics; kLaneSpan) it pays
// from less than a tenth (Cornell box, stage seconds on Intel's runtime: 0.083 at a third,
// 0.058-0.061 at 0.2, 0.15 and 0.1; PoCL 0.098-0.103 at a third, 0.071-0.075 at 0.15),
// and 0.15 keeps a margin for the launches near the end of a batch (docs/performance.md,
// "Appends per four blocks").
constexpr double kRegenDenseFraction = 0.15;
static_assert(kWorkGroup >= AW_C_COUNT, "wg_append keeps one local counter per queue and counter in the work-group");

size_t pad_to_group(size_t n, size_t group = kWorkGroup) { return (n + group - 1) / group * group; }

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Path states in flight when --pool is not given. Intel's CPU runtime: 2^16. Once the stages ran
// 16 paths per vector the state's traffic began to show there: the Cornell box at 256x256 took
// 0.838-0.845 s with 2^16 against 0.879-0.950 with 2^18 (classify_hit and shade_diffuse 15-20%
// faster, their state 18 MB against 71 MB), 1.63-1.66 against 1.72-1.80 s at the race's 128x128
// and 256 spp, the race's other scenes level; 2^15 and 2^14 slower (more iterations, each with
// its launches). Other CPU devices (PoCL): 2^18, where each launch costs more and 2^16 was level
// at 256x256 but 0-20% slower at the race's 64 spp (docs/performance.md, "A smaller path pool
// on CPUs"). GPUs: 2^20, measured on an H200 (132 multiprocessors, 2026-12-04):
// the Cornell box at 1024x1024, 64 spp rendered at 143 Msamples/s with 2^20 paths against 88
// with 2^18; every stage ran 1.6-3.4x more items per second, a 2^18 pool leaving most of the
// GPU's 270k resident threads without work. The image does not depend on it.
bool intel_runtime(const DeviceInfo& d) { return d.platform.find("Intel") != std::string::npos; }

uint32_t default_pool_size(const DeviceInfo& device) {
  if (const char* e = std::getenv("ARCHWAVE_POOL")) {
    long v = std::strtol(e, nullptr, 10);
    if (v >= long(kWorkGroup)) return uint32_t(v);
  }
  if (device.type == "GPU") return 1u << 20;
  return intel_runtime(device) ? 1u << 16 : 1u << 18;
}

template <class T>
cl::Buffer upload(ClRuntime& rt, const char* what, const std::vector<T>& v, cl_mem_flags flags = CL_MEM_READ_ONLY) {
  return rt.buffer(what, v.size() * sizeof(T), flags, v.empty() ? nullptr : v.data());
}

// The buffers of the stage argument list, one member per BUFFER entry of stage_args.h.
struct StageBuffers {
#define AW_HOST_STAGE_VALUE(type, name)
#define AW_HOST_STAGE_BUFFER(type, name) cl::Buffer name;
  AW_STAGE_ARGS(AW_HOST_STAGE_VALUE, AW_HOST_STAGE_BUFFER)
#undef AW_HOST_STAGE_BUFFER
};

// Binds every buffer of the argument list to a stage kernel, and zeroes the values.
void bind_stage_args(cl::Kernel& k, const StageBuffers& b) {
#define AW_BIND_STAGE_VALUE(type, name) k.setArg(AW_ARG_##name, type(0));
#define AW_BIND_STAGE_BUFFER(type, name) k.setArg(AW_ARG_##name, b.name);
  AW_STAGE_ARGS(AW_BIND_STAGE_VALUE, AW_BIND_STAGE_BUFFER)
#undef AW_BIND_STAGE_VALUE
#undef AW_BIND_STAGE_BUFFER
}

// The kernel names of the lobe stages, from the lobe list (kernels.cl: kernel_shade_<name>).
const char* const kLobeStageNames[AW_LID_COUNT] = {
#define AW_LOBE_STAGE_NAME(ID, name, FEATURE, TRAITS) "shade_" #name,
    AW_LOBE_LIST(AW_LOBE_STAGE_NAME)
#undef AW_LOBE_STAGE_NAME
};

// One stage: its kernel (kernel_<name> in kernels.cl), the queue it consumes, whether it
// may run as a dense launch and whether it appends (the host then pushes and pulls the
// queue counters around it), and what it did.
struct Stage {
  std::string name;
  int queue = -1;        // AW_Q_* it consumes; -1: none (film_accumulate)
  bool dense_ok = false; // consumes its whole queue, so a launch over the pool in slot order works
  bool appends = false;
  cl::Kernel kernel;     // null for a lobe this build lacks
  cl::Kernel lanes_kernel;  // its lane form (kernels_lanes.cl), for dense launches; null: none
  uint32_t lanes_span = 0;  // slots per work-item of lanes_kernel (kLaneSpan when 0)
  uint32_t lanes_group = 0; // its work-group size (the lane programs' lane_wg_ when 0)
  double seconds = 0.0;
  uint64_t items = 0;    // paths (pixels for film_accumulate) processed: throughput per stage
};

class Wavefront {
 public:
  Wavefront(const Scene& scene, const RenderOptions& opts, RenderResult& res)
      : scene_(scene), opts_(opts), res_(res), st_(res.stats), packed_(pack_scene(scene, &st_.warnings)),
        rt_(opts.device) {
    parse_fault();
  }

  void render() {
    build_bvh();
    build_program();
    try {
      auto t_setup = Clock::now();
      allocate();
      bind();
      st_.setup_seconds += since(t_setup);
      warm_up();
    } catch (const cl::Error& e) {
      throw ClError(error_text(e));
    }
    ProgressLine progress(opts_.progress_label.empty() ? "rendering" : opts_.progress_label, total_jobs_, opts_.progress);
    uint64_t jobs_done = 0;
    try {
      // Jobs until which to render: all of them, or (time limit) the end of the sample pass
      // under way when the limit passed, so every pixel has the same number of new samples.
      uint64_t stop_at = total_jobs_;
      last_snapshot_ = Clock::now();
      run_jobs(jobs_done, stop_at, progress);
      progress.finish();
      st_.interrupted = jobs_done < stop_at;
      read_back();
    } catch (const cl::Error& e) {
      progress.finish();
      device_failed(e);
    }
  }

 private:
  // "OpenCL error while rendering on DEVICE: CALL (CODE)": the call and the error code come
  // from the C++ bindings' exception (the failing clXxx function and its status).
  std::string error_text(const cl::Error& e) const {
    return std::string("OpenCL error while rendering on ") + rt_.info().name + ": " + e.what() + " (" +
           cl_error_name(e.err()) + ")";
  }

  // Snapshots of the film: a device lost mid-render loses at most the work since the last one
  // (and the batch under way). Taken after a batch at most every RenderOptions::snapshot_seconds
  // (2 s), and never sooner than kSnapshotCostFactor times the last one's cost after it, so
  // they cost at most ~1% of the render however large the film (docs/production.md).
  static constexpr double kSnapshotCostFactor = 100.0;

  // The film's words and counts from the device into res_. res_ is not a usable film while
  // a read is under way: if one fails half-way, only a read after the error can keep anything.
  void snapshot() {
    auto t0 = Clock::now();
    film_kept_ = false;
    read_film_words(res_.acc, res_.count, res_.aov_acc);
    film_kept_ = true;
    last_snapshot_ = Clock::now();
    last_snapshot_cost_ = since(t0);
    ++st_.film_snapshots;
    st_.snapshot_seconds += last_snapshot_cost_;
  }

  void read_film_words(std::vector<uint64_t>& acc, std::vector<uint32_t>& count, std::vector<uint64_t>& aov_acc) {
    check_fault_lost("clEnqueueReadBuffer");
    auto& q = rt_.queue();
    q.enqueueReadBuffer(buf_.film, CL_TRUE, 0, acc.size() * 8, acc.data());
    q.enqueueReadBuffer(buf_.film_count, CL_TRUE, 0, count.size() * 4, count.data());
    if (!aov_acc.empty()) q.enqueueReadBuffer(buf_.aov_film, CL_TRUE, 0, aov_acc.size() * 8, aov_acc.data());
  }

  // An OpenCL error after rendering began. The film on the device holds whole samples up to
  // the last film_accumulate that ran (a batch cut short never reached its own), so it is
  // read back when the device still answers; else the last snapshot stands. Either way the
  // error leaves with the film, for the caller to write and to resume from.
  void device_failed(const cl::Error& e) {
    std::string what = error_text(e);
    st_.device_error = what;
    st_.interrupted = true;
    std::string kept, silent;  // how the film was had; why the device gave nothing
    try {
      std::vector<uint64_t> acc(res_.acc.size()), aov(res_.aov_acc.size());
      std::vector<uint32_t> count(res_.count.size());
      read_film_words(acc, count, aov);
      res_.acc.swap(acc);
      res_.count.swap(count);
      res_.aov_acc.swap(aov);
      film_kept_ = true;
      kept = "read back after the error";
    } catch (const cl::Error& again) {
      silent = std::string("the device no longer answers (") + again.what() + ": " + cl_error_name(again.err()) + ")";
      kept = "from the last snapshot, " + std::to_string(int(std::lround(since(last_snapshot_)))) + " s before the error: " + silent;
    }
    st_.total_seconds = since(t_start_);
    if (!film_kept_) throw RenderDeviceError(what + "; no film could be kept (the device failed while its film was read)", nullptr);
    const uint64_t held = film_held();
    if (held == 0 && !silent.empty() && st_.film_snapshots == 0)
      throw RenderDeviceError(what + "; no film was kept: no snapshot had been taken yet and " + silent, nullptr);
    if (held == 0) throw RenderDeviceError(what + "; no sample had been completed (" + kept + ")", nullptr);
    res_.update_sums();
    st_.samples = held - st_.resumed_samples;
    auto partial = std::make_shared<RenderResult>(std::move(res_));
    throw RenderDeviceError(what + "; the film keeps " + std::to_string(held) + " samples, " + kept, partial);
  }

  // The samples res_'s film holds.
  uint64_t film_held() const {
    uint64_t held = 0;
    for (uint32_t c : res_.count) held += c;
    return held;
  }

  // ARCHWAVE_FAULT, for the tests of the above: "launch:N" makes the Nth stage launch fail,
  // "lost:N" also every OpenCL call after it (a lost device answers nothing).
  void parse_fault() {
    const char* f = std::getenv("ARCHWAVE_FAULT");
    if (!f || !*f) return;
    std::string v = f;
    size_t colon = v.find(':');
    std::string mode = v.substr(0, colon);
    char* end = nullptr;
    unsigned long n = colon == std::string::npos ? 0 : std::strtoul(v.c_str() + colon + 1, &end, 10);
    if ((mode != "launch" && mode != "lost") || n == 0 || !end || *end)
      throw std::invalid_argument("ARCHWAVE_FAULT=" + v + ": not launch:N or lost:N with N >= 1 (a testing aid)");
    fault_at_ = n;
    fault_lost_ = mode == "lost";
  }
  void check_fault_lost(const char* call) const {
    if (lost_) throw cl::Error(CL_OUT_OF_RESOURCES, call);
  }

  bool cancelled() const { return opts_.cancel && opts_.cancel->load(); }

  void build_bvh() {
    auto t0 = Clock::now();
    EmbreeDevice embree;
    bvh_ = build_flat_bvh(embree, packed_.soup);
    st_.bvh_seconds = since(t0);
  }

  // Model only what the scene requires: specialise the program on the scene's features.
  // Its whole time is kernel build (compile_seconds): assembling the sources, the binary
  // cache's key and every program the render uses. (Until 2026-12-06 only the last program's
  // clBuildProgram was counted there, and the rest, 60-90 ms on Intel's runtime with a
  // cached binary, fell into the render time: docs/performance.md, "Render time without the
  // kernel build".)
  void build_program() {
    const auto t0 = Clock::now();
    build_programs();
    st_.compile_seconds += since(t0);
  }

  void build_programs() {
    st_.device = rt_.info().name + " (" + rt_.info().platform + ")";
    std::string src = assemble_kernel_source("integrator/kernels.cl", opts_.kernel_dir);
    const FeatureSet& need = packed_.features;
    features_ = opts_.generic_kernels ? FeatureSet::all() : need;
    for (const std::string& off : opts_.force_off)
      for (int i = 0; i < FeatureSet::COUNT; ++i)
        if (off == FeatureSet::name(i)) features_.on[i] = false;
    st_.kernel_features = opts_.generic_kernels ? "generic (every feature)" : "specialised: " + features_.describe();
    // Material features are checked at every hit (classify_hit), lobe splitting where it
    // starts (shade_surface); light types, the sampler, analytic spheres and instances have no
    // such check in the kernels (a compiled-out light type would be sampled as another one, a
    // compiled-out sampler falls through to Sobol', spheres would be tested as triangles,
    // instances never entered), so the host refuses the build here.
    std::string lack;
    for (int i : {FeatureSet::LIGHT_POINT, FeatureSet::LIGHT_QUAD, FeatureSet::LIGHT_DISK, FeatureSet::LIGHT_SPHERE,
                  FeatureSet::LIGHT_SUN, FeatureSet::ENV_MAP, FeatureSet::LIGHT_MESH, FeatureSet::LIGHT_TREE, FeatureSet::SPHERE,
                  FeatureSet::INSTANCE,
                  FeatureSet::SAMPLER_INDEPENDENT, FeatureSet::SAMPLER_ZSOBOL})
      if (need.on[i] && !features_.on[i]) lack += std::string(lack.empty() ? "" : ", ") + FeatureSet::name(i);
    if (!lack.empty())
      throw std::logic_error("the scene has lights or a sampler of a kind the specialised kernels lack (" + lack + "; built: " +
                             st_.kernel_features + "); the image would be wrong, so none is rendered");
    // The options at a work-group size: the one-path program's kWorkGroup, the lane programs' lane_wg_.
    auto options_at = [&](uint32_t wg) {
      return "-cl-std=CL1.2 -DAW_WG=" + std::to_string(wg) + " " +
             (opts_.generic_kernels ? std::string() : features_.defines()) + " " + opts_.build_options;
    };
    program_ = rt_.build(src, options_at(kWorkGroup));
    st_.kernel_build = rt_.last_build();
    lane_wg_ = lane_work_group(rt_.info());
    build_lanes_program(need, options_at(lane_wg_));
  }

  // The most primitives (triangles and analytic spheres) for which the ray stages run on lanes
  // by default (--lane-traversal auto). The lane traversal visits every node that any of a
  // work-item's 16 rays enters, and the rays of neighbouring slots are unrelated after the
  // first bounce, so it pays while the tree is small enough that they share most of it.
  // Measured (docs/performance.md, "The ray stages on lanes": Cornell box, race scenes, torus
  // knots of 386 to 24578 triangles, 256x256, 32 spp): on Intel's CPU runtime the closest hit
  // is 2x as fast at 34 triangles, 1.13x at 2306, 1.05x at 6146, 0.92x at 24578, and the
  // shadow rays (which a one-ray traversal leaves at their first hit) 1.5x at 34, 1.02x at
  // 770, 0.95x at 2306. PoCL 3.1 compiles the lane code less well (the race spheres, 7
  // primitives: 1.44x closest, 1.33x shadow; the Cornell box, 34: 1.0x and 0.88x; 386: 0.91x
  // and 0.73x).
  struct LaneTraversalLimit {
    size_t closest, shadow;
  };
  static bool prefaults_state(const DeviceInfo& d) {
    return d.type == "CPU" && d.platform.find("Portable Computing Language") != std::string::npos;
  }

  static LaneTraversalLimit lane_traversal_limit(const DeviceInfo& d) {
    if (intel_runtime(d)) return {8192, 1024};
    return {32, 32};
  }

  // The stages written on lanes (kernels/integrator/kernels_lanes.cl), 16 paths per
  // work-item: on a CPU device (a GPU's work-items are SIMD lanes already), and only for a
  // scene that needs nothing the lane program leaves out (its header says what); otherwise
  // every stage runs one path per work-item, and the stats say why.
  void build_lanes_program(const FeatureSet& need, const std::string& options) {
    classify_on_lanes_ = false;
    closest_on_lanes_ = closest_sorted_ = shadow_on_lanes_ = accumulate_on_lanes_ = false;
    if (!opts_.lanes) {
      st_.lanes = "off (--no-lanes)";
      return;
    }
    if (rt_.info().type != "CPU") {
      st_.lanes = "off (not a CPU device)";
      return;
    }
    std::string why;
    // (Per-lobe samples do not stop it: a split starts only in the stage of a lobe with
    // `samples`, and the lobes on lanes have none; kernels/integrator/shade_surface.h.)
    for (int i : {FeatureSet::TEXTURE, FeatureSet::BUMP, FeatureSet::LIGHT_TREE, FeatureSet::ENV_MAP, FeatureSet::AOV,
                  FeatureSet::SAMPLER_ZSOBOL})
      if (need.on[i]) why += (why.empty() ? "" : ", ") + FeatureSet::lower_name(i);
    if (!why.empty()) {
      st_.lanes = "off (the scene needs " + why + ", one path per work-item still)";
      return;
    }
    std::string src = assemble_kernel_source("integrator/kernels_lanes.cl", opts_.kernel_dir);
    auto build_at = [&](uint32_t w) {
      return rt_.build(src, options + " -DAW_LANES=" + std::to_string(w) + " -DAW_LANE_BLOCKS=" + std::to_string(kLaneSpan / w) +
                                " -DAW_SORT_SPAN=" + std::to_string(kSortSpan));
    };
    lanes_program_ = build_at(kLanes);
    narrow_lanes_ = narrow_lane_width(rt_.info(), opts_.narrow_lanes);
    narrow_program_ = narrow_lanes_ == kLanes ? lanes_program_ : build_at(narrow_lanes_);
    // classify_hit on lanes leaves out more (kernels/integrator/classify_hit.h): fog,
    // instances, and of the reflection lobes' sampled split all but isotropic GGX and mirrors
    // (kernels/material/architectural.h, material_sampled_fresnel).
    std::string classify_why;
    for (int i : {FeatureSet::FOG, FeatureSet::INSTANCE, FeatureSet::BRDF_BECKMANN, FeatureSet::BRDF_AS,
                  FeatureSet::ANISOTROPY})
      if (need.on[i]) classify_why += (classify_why.empty() ? "" : ", ") + FeatureSet::lower_name(i);
    classify_on_lanes_ = classify_why.empty();
    // The lane traversal leaves out instances and cutouts (kernels/bvh/traverse_lanes.h), and
    // pays only where its rays share most of the nodes they visit: see lane_traversal_limit.
    std::string rays_why;
    for (int i : {FeatureSet::INSTANCE, FeatureSet::CUTOUT})
      if (need.on[i]) rays_why += (rays_why.empty() ? "" : ", ") + FeatureSet::lower_name(i);
    if (!rays_why.empty()) rays_why = "the scene needs " + rays_why;
    const size_t primitives = packed_.soup.indices.size() + packed_.soup.spheres.size();
    const LaneTraversalLimit limit = lane_traversal_limit(rt_.info());
    if (rays_why.empty() && opts_.lane_traversal == 0) rays_why = "--lane-traversal off";
    std::string shadow_why = rays_why;
    auto too_many = [&](size_t most) {
      return std::to_string(primitives) + " primitives, above the " + std::to_string(most) +
             " where it pays on this device; --lane-traversal on to force";
    };
    if (rays_why.empty() && opts_.lane_traversal < 0 && primitives > limit.closest) rays_why = too_many(limit.closest);
    if (shadow_why.empty() && opts_.lane_traversal < 0 && primitives > limit.shadow) shadow_why = too_many(limit.shadow);
    closest_on_lanes_ = rays_why.empty();
    closest_sorted_ = closest_on_lanes_ && primitives >= kSortMinPrimitives;
    shadow_on_lanes_ = shadow_why.empty();
    // accumulate on lanes leaves out per-lobe splits (a split path goes back to its lobe's queue
    // from accumulate_path, one path per call; kernels/integrator/accumulate.h).
    accumulate_on_lanes_ = !need.on[FeatureSet::SPLIT];
    // The stages in pipeline order; with a narrow program, its stages after a "; 8:".
    std::string narrow;
    auto name = [&](bool narrow_stage, const char* stage) {
      (narrow_stage && narrow_lanes_ != kLanes ? narrow : st_.lanes) += std::string(" ") + stage;
    };
    st_.lanes = std::to_string(kLanes) + " paths per work-item:";
    name(false, "regenerate");
    if (closest_on_lanes_) name(true, closest_sorted_ ? "intersect_closest(sorted)" : "intersect_closest");
    if (classify_on_lanes_) name(true, "classify_hit");
#define AW_LANES_STAGE_NAME(ID, name_, FEATURE, TRAITS) name(false, "shade_" #name_);
    AW_LOBE_LIST_ON_LANES(AW_LANES_STAGE_NAME)
#undef AW_LANES_STAGE_NAME
    if (shadow_on_lanes_) name(true, "intersect_shadow");
    if (accumulate_on_lanes_) name(false, "accumulate");
    if (!narrow.empty()) st_.lanes += "; " + std::to_string(narrow_lanes_) + ":" + narrow;
    if (!closest_on_lanes_ && !shadow_on_lanes_ && rays_why == shadow_why)
      st_.lanes += " (the ray stages one path per work-item: " + rays_why + ")";
    else if (!closest_on_lanes_)
      st_.lanes += " (intersect_closest one path per work-item: " + rays_why + ")";
    if (!shadow_on_lanes_ && (closest_on_lanes_ || rays_why != shadow_why))
      st_.lanes += " (intersect_shadow one path per work-item: " + shadow_why + ")";
    if (!classify_on_lanes_) st_.lanes += " (classify_hit one path per work-item: the scene needs " + classify_why + ")";
    if (!accumulate_on_lanes_) st_.lanes += " (accumulate one path per work-item: the scene needs split)";
  }

  void allocate() {
    rp_ = packed_.params;
    first_sample_ = begin_film(scene_, opts_, packed_, rp_, res_);
    npix_ = rp_.win_w * rp_.win_h;
    // Jobs are (film pixel, sample) from the first sample some pixel lacks (0 unless resumed)
    // to the range's end; film_accumulate skips the samples a resumed pixel holds already.
    total_jobs_ = uint64_t(npix_) * uint64_t(res_.sample_end - first_sample_);
    // (A resumed film that is complete has no job left: the buffers keep their smallest size.)
    const uint64_t sized_jobs = std::max<uint64_t>(total_jobs_, 1);
    uint32_t pool = opts_.pool_size ? opts_.pool_size : default_pool_size(rt_.info());
    pool = uint32_t(std::min<uint64_t>(pool, pad_to_group(sized_jobs)));
    pool_ = uint32_t(pad_to_group(pool));
    rp_.pool_size = pool_;
    rp_.num_nodes = uint32_t(bvh_.nodes.size());
    max_batch_ = opts_.max_batch ? opts_.max_batch : 4u * pool_;
    max_batch_ = uint32_t(std::min<uint64_t>(max_batch_, sized_jobs));
    // The ring holds two batches, and a job's three floats are indexed in 32 bits (kernels.cl).
    max_batch_ = std::min<uint32_t>(max_batch_, 1u << 28);

    StageBuffers& b = buf_;
    b.sf = rt_.buffer("path state (float fields)", size_t(AW_SF_COUNT) * pool_ * 4);
    b.su = rt_.buffer("path state (uint fields)", size_t(AW_SU_COUNT) * pool_ * 4);
    st_.state_bytes = size_t(AW_SF_COUNT + AW_SU_COUNT) * pool_ * 4;
    // On PoCL the path state is written once in order here, at setup: the stages' first,
    // scattered writes from every thread otherwise fault it in page by page inside the timed
    // render (Cornell box, 256x256, 32 spp, pool 2^18, three rounds: 47,400 minor faults
    // against 37,900, total 1.65 -> 1.54 s; docs/performance.md, "regenerate on lanes"). On
    // Intel's runtime the same fill cost 70 ms of setup and saved nothing, and it is not done.
    if (prefaults_state(rt_.info())) {
      rt_.queue().enqueueFillBuffer(b.sf, 0.0f, 0, size_t(AW_SF_COUNT) * pool_ * 4);
      rt_.queue().enqueueFillBuffer(b.su, 0u, 0, size_t(AW_SU_COUNT) * pool_ * 4);
    }
    // Lobe splitting's first-hit snapshots (integrator/split.h): only when the scene splits.
    const bool splits = rp_.split_spp != 0u;
    b.snap_f = rt_.buffer("lobe-split snapshots (float fields)", splits ? size_t(AW_SNAP_F_COUNT) * pool_ * 4 : 4);
    b.snap_u = rt_.buffer("lobe-split snapshots (uint fields)", splits ? size_t(AW_SNAP_U_COUNT) * pool_ * 4 : 4);
    if (splits) st_.state_bytes += size_t(AW_SNAP_F_COUNT + AW_SNAP_U_COUNT) * pool_ * 4;
    st_.pool_size = pool_;
    // All queues in one buffer: queue i at [i * pool, (i + 1) * pool).
    b.queues = rt_.buffer("queues", size_t(AW_Q_COUNT) * pool_ * 4);
    b.counters = rt_.buffer("queue counters", AW_C_COUNT * 4);
    // The queue each slot is in (kernels.cl: wg_append, stage_slot); all free at the start
    // of the render (run_jobs).
    b.tags = rt_.buffer("queue tags", size_t(pool_) * 4);
    b.stats = upload(rt_, "stats counters", std::vector<uint32_t>(AW_STAT_COUNT, 0), CL_MEM_READ_WRITE);
    // The batch ring (run_jobs): two halves of max_batch_ jobs, one when one batch is the render.
    ring_jobs_ = total_jobs_ > max_batch_ ? 2 * max_batch_ : max_batch_;
    b.samples = rt_.buffer("batch samples", size_t(ring_jobs_) * 3 * 4);
    // Zeroed on the device: a host vector of zeros the film's size would be allocated (and
    // filled) before the device could refuse a film too large for it.
    // (A resumed film is uploaded from the host; it exists there already.)
    const size_t film_bytes = size_t(npix_) * AW_FILM_WORDS * 8;
    b.film = rt_.buffer("film", film_bytes, CL_MEM_READ_WRITE);
    b.film_count = rt_.buffer("film sample counts", size_t(npix_) * 4, CL_MEM_READ_WRITE);
    // AOVs (kernels/integrator/aov.h): the first hit's data per slot, the report per job and
    // the exact sums per pixel; a float each without AOVs.
    const bool aovs = rp_.aov_mask != 0u;
    const size_t aov_film_bytes = size_t(npix_) * aov_film_channels(rp_.aov_mask) * 16;
    b.aov_state = rt_.buffer("AOVs: first-hit data", aovs ? size_t(AW_AOV_STATE) * pool_ * 4 : 4);
    b.aov_samples = rt_.buffer("AOVs: batch reports", aovs ? size_t(ring_jobs_) * AW_AOV_FLOATS * 4 : 4);
    b.aov_film = rt_.buffer("AOVs: film", aovs ? aov_film_bytes : 16, CL_MEM_READ_WRITE);
    if (aovs) st_.state_bytes += size_t(AW_AOV_STATE) * pool_ * 4;
    if (opts_.resume) {
      rt_.queue().enqueueWriteBuffer(b.film, CL_TRUE, 0, film_bytes, res_.acc.data());
      rt_.queue().enqueueWriteBuffer(b.film_count, CL_TRUE, 0, size_t(npix_) * 4, res_.count.data());
      if (aovs) rt_.queue().enqueueWriteBuffer(b.aov_film, CL_TRUE, 0, aov_film_bytes, res_.aov_acc.data());
    } else {
      rt_.queue().enqueueFillBuffer(b.film, cl_ulong(0), 0, film_bytes);
      rt_.queue().enqueueFillBuffer(b.film_count, uint32_t(0), 0, size_t(npix_) * 4);
      if (aovs) rt_.queue().enqueueFillBuffer(b.aov_film, cl_ulong(0), 0, aov_film_bytes);
    }
    b.nodes = rt_.buffer("BVH nodes", bvh_.nodes.size() * sizeof(BvhNode), CL_MEM_READ_ONLY,
                         bvh_.nodes.empty() ? nullptr : bvh_.nodes.data());
    b.tris = rt_.buffer("BVH leaf triangles", bvh_.leaf_tris.size() * sizeof(LeafTriangle), CL_MEM_READ_ONLY,
                        bvh_.leaf_tris.empty() ? nullptr : bvh_.leaf_tris.data());
    b.insts = bvh_.instances.empty() ? rt_.buffer("instances", sizeof(InstanceGpu)) : upload(rt_, "instances", bvh_.instances);
    b.tri_info = upload(rt_, "triangle info", packed_.tri_info);
    b.verts = upload(rt_, "vertices", packed_.verts);
    b.materials = upload(rt_, "materials", packed_.materials);
    b.lights = upload(rt_, "lights", packed_.lights);
    // The environment map's texels and distributions (lights/environment.h); one float without.
    b.env = packed_.env.empty() ? rt_.buffer("environment map", 4) : upload(rt_, "environment map", packed_.env);
    b.light_tree = packed_.light_tree.empty() ? rt_.buffer("light tree", sizeof(LightTreeNode))
                                              : upload(rt_, "light tree", packed_.light_tree);
    b.tri_light = packed_.tri_light.empty() ? rt_.buffer("triangle lights", 4) : upload(rt_, "triangle lights", packed_.tri_light);
    // Textures (kernels/texture/texture.h) and, per path slot, the hit's material with its
    // textures applied: only for scenes with textures.
    const bool textured = !packed_.tex_bindings.empty();
    b.textures = packed_.textures.empty() ? rt_.buffer("textures", sizeof(TextureGpu))
                                          : upload(rt_, "textures", packed_.textures);
    b.tex_bindings = textured ? upload(rt_, "texture bindings", packed_.tex_bindings)
                              : rt_.buffer("texture bindings", sizeof(TexBindingGpu));
    b.texels = packed_.texels.empty() ? rt_.buffer("texels", 4) : upload(rt_, "texels", packed_.texels);
    b.mat_resolved = rt_.buffer("textured materials (per path)", textured ? size_t(pool_) * sizeof(MaterialGpu) : sizeof(MaterialGpu),
                                CL_MEM_READ_WRITE);
    if (textured) st_.state_bytes += size_t(pool_) * sizeof(MaterialGpu);
    st_.triangles = packed_.soup.indices.size();
    st_.spheres = packed_.soup.spheres.size();
    st_.instances = packed_.soup.instances.size();
    st_.instanced_triangles = scene_.rendered_triangle_count();
    st_.scene_bytes = bvh_.nodes.size() * sizeof(BvhNode) + bvh_.leaf_tris.size() * sizeof(LeafTriangle) +
                      packed_arrays_bytes(packed_);
    st_.film_bytes = film_bytes + size_t(npix_) * 4 + size_t(ring_jobs_) * 3 * 4;  // film, counts, batch samples
    if (aovs) st_.film_bytes += aov_film_bytes + size_t(ring_jobs_) * AW_AOV_FLOATS * 4;
    st_.device_bytes = rt_.allocated_bytes();
    identity_.resize(pool_);
    std::iota(identity_.begin(), identity_.end(), 0u);
  }

  // The stages in pipeline order (the order of the stats), their kernels, their buffers.
  void bind() {
    auto add = [&](const std::string& name, int queue, bool dense_ok, bool appends, bool built) {
      Stage s;
      s.name = name;
      s.queue = queue;
      s.dense_ok = dense_ok;
      s.appends = appends;
      if (built) {
        s.kernel = cl::Kernel(program_, ("kernel_" + name).c_str());
        bind_stage_args(s.kernel, buf_);
      }
      stages_.push_back(std::move(s));
      return stages_.size() - 1;
    };
    // regenerate's queue launch takes the first `take` entries of the FREE queue; its lane form
    // (a dense launch) takes every FREE-tagged slot of the pool instead (kernels_lanes.cl).
    regen_ = add("regenerate", AW_Q_FREE, bool(lanes_program_()), true, true);
    if (lanes_program_()) {
      Stage& s = stages_[regen_];
      s.lanes_kernel = cl::Kernel(lanes_program_, "kernel_regenerate_lanes");
      bind_stage_args(s.lanes_kernel, buf_);
    }
    isect_ = add("intersect_closest", AW_Q_RAY, true, false, true);
    if (closest_on_lanes_) {
      Stage& s = stages_[isect_];
      if (closest_sorted_) {
        s.lanes_kernel = cl::Kernel(narrow_program_, "kernel_intersect_closest_sorted");
        s.lanes_span = kSortSpan;
        s.lanes_group = 1;
      } else {
        s.lanes_kernel = cl::Kernel(narrow_program_, "kernel_intersect_closest_lanes");
      }
      bind_stage_args(s.lanes_kernel, buf_);
    }
    classify_ = add("classify_hit", AW_Q_RAY, true, true, true);
    if (classify_on_lanes_) {
      Stage& s = stages_[classify_];
      s.lanes_kernel = cl::Kernel(narrow_program_, "kernel_classify_hit_lanes");
      bind_stage_args(s.lanes_kernel, buf_);
    }
    ao_ = add("ambient_occlusion", AW_Q_AO, true, true, features_.on[FeatureSet::AO]);
    for (uint32_t l = 0; l < AW_LID_COUNT; ++l)
      shade_[l] = add(kLobeStageNames[l], AW_Q_LOBE + int(l), true, true, features_.lobe(l));
    if (lanes_program_()) {
#define AW_LANES_KERNEL(ID, name, FEATURE, TRAITS)                                          \
  if (features_.lobe(AW_LID_##ID)) {                                                        \
    Stage& s = stages_[shade_[AW_LID_##ID]];                                                \
    s.lanes_kernel = cl::Kernel(lanes_program_, "kernel_shade_" #name "_lanes");           \
    bind_stage_args(s.lanes_kernel, buf_);                                                  \
  }
      AW_LOBE_LIST_ON_LANES(AW_LANES_KERNEL)
#undef AW_LANES_KERNEL
    }
    shadow_ = add("intersect_shadow", AW_Q_SHADOW, true, false, true);
    if (shadow_on_lanes_) {
      Stage& s = stages_[shadow_];
      s.lanes_kernel = cl::Kernel(narrow_program_, "kernel_intersect_shadow_lanes");
      bind_stage_args(s.lanes_kernel, buf_);
    }
    // accumulate's queue launch runs over its queue entries only; its lane form (a dense
    // launch) over every DONE-tagged slot of the pool (kernels_lanes.cl).
    accum_ = add("accumulate", AW_Q_DONE, accumulate_on_lanes_, true, true);
    if (accumulate_on_lanes_) {
      Stage& s = stages_[accum_];
      s.lanes_kernel = cl::Kernel(lanes_program_, "kernel_accumulate_lanes");
      bind_stage_args(s.lanes_kernel, buf_);
    }
    film_ = add("film_accumulate", -1, false, false, true);
  }

  // PoCL compiles the work-group function of a kernel at its first launch with a given
  // local size, not at clBuildProgram: launch every stage once on zero items now, so that
  // cost is reported as compile time and not as the first iteration's stage time. PoCL also
  // builds a second work-group function for large grids (above ~2^16 work-items) at the
  // first such launch: a second, large launch on zero items compiles that one too (every
  // work-item masks itself out by the count, so nothing is written).
  void warm_up() {
    auto t0 = Clock::now();
    rp_.job_count = 0;
    for (Stage& s : stages_) {
      if (!s.kernel()) continue;
      set_launch_args(s, 0, false, 0);
      for (size_t global : {size_t(kWorkGroup), size_t(1) << 17})
        rt_.queue().enqueueNDRangeKernel(s.kernel, cl::NullRange, cl::NDRange(global), cl::NDRange(kWorkGroup));
      // A lane kernel is always dense: a launch over the pool with every tag reset would do
      // work, so it warms up on one group of a pool of 0 slots (every work-item masks itself out).
      if (s.lanes_kernel()) {
        RenderParams warm = rp_;
        warm.pool_size = 0;
        set_launch_args(s.lanes_kernel, warm, 0, false, 0);
        const size_t group = lanes_group(s);
        for (size_t global : {group, size_t(1) << 17})
          rt_.queue().enqueueNDRangeKernel(s.lanes_kernel, cl::NullRange, cl::NDRange(global), cl::NDRange(group));
      }
    }
    rt_.queue().finish();
    st_.compile_seconds += since(t0);
  }

  void set_launch_args(Stage& s, uint32_t count, bool dense, uint32_t job_start) {
    set_launch_args(s.kernel, rp_, count, dense, job_start);
  }
  static void set_launch_args(cl::Kernel& k, const RenderParams& rp, uint32_t count, bool dense, uint32_t job_start) {
    k.setArg(AW_ARG_rp, sizeof(RenderParams), &rp);
    k.setArg(AW_ARG_count, count);
    k.setArg(AW_ARG_dense, uint32_t(dense));
    k.setArg(AW_ARG_job_start, job_start);
  }

  size_t lanes_group(const Stage& s) const { return s.lanes_group ? s.lanes_group : lane_wg_; }

  // Whether a launch of stage s over n items is dense (see launch).
  bool launches_dense(const Stage& s, size_t n) const {
    const double dense_fraction = opts_.dense_fraction >= 0.0  ? opts_.dense_fraction
                                  : &s == &stages_[regen_]    ? kRegenDenseFraction
                                                              : kDenseFraction;
    return s.dense_ok && double(n) >= dense_fraction * double(pool_);
  }

  // Runs one stage over `n` items and waits, so its time is its own. Stages that append to
  // queues get the host's counters first and return the new ones. A queue holding at least
  // `dense_fraction` of the pool is consumed by a dense launch: one work-item per slot, in
  // slot order (kernels.cl, stage_slot). The scattered slot order that appends leave behind
  // costs more than the idle work-items of a dense launch once a queue holds about a quarter
  // of the pool (docs/architecture.md, "Dense launches").
  void launch(Stage& s, size_t n, uint32_t job_start = 0) {
    if (n == 0 && s.queue >= 0) return;
    if (!s.kernel())
      throw std::logic_error("wavefront: paths queued for '" + s.name + "', which this kernel build does not have");
    check_fault_lost("clEnqueueNDRangeKernel");
    if (fault_at_ && ++launches_ == fault_at_) {
      lost_ = fault_lost_;
      throw cl::Error(CL_OUT_OF_RESOURCES, "clEnqueueNDRangeKernel");
    }
    auto t0 = Clock::now();
    const bool regen = &s == &stages_[regen_];
    const bool dense = launches_dense(s, n);
    // The lane regenerate hands out its jobs from the FREE counter, from 0 (kernels_lanes.cl);
    // the FREE queue's entries are not read, and run_batch drops them after this launch.
    if (dense && s.lanes_kernel() && regen) cnt_[AW_Q_FREE] = 0;
    // Not blocking: the queue is in order, so the kernel below sees these counters, and cnt_ is
    // not touched again before the blocking read after the kernel has overwritten it. A
    // blocking write made the host wait for the copy before it could enqueue the kernel: one
    // round trip per appending launch, over the bus on a GPU. On the CPU devices it measured
    // level (Intel's runtime, Zen 4 EPYC: render 0.987x and 1.007x, 8 pairs each;
    // docs/performance.md, "Counters written without waiting").
    if (s.appends) rt_.queue().enqueueWriteBuffer(buf_.counters, CL_FALSE, 0, sizeof cnt_, cnt_);
    if (dense && s.lanes_kernel()) {
      // The lane form: a work-item per span of consecutive slots (kLaneSpan, or the stage's
      // own), in groups of lane_wg_ (lane_work_group) or the stage's own size.
      set_launch_args(s.lanes_kernel, rp_, uint32_t(n), true, job_start);
      const uint32_t span = s.lanes_span ? s.lanes_span : kLaneSpan;
      const size_t group = lanes_group(s);
      rt_.queue().enqueueNDRangeKernel(s.lanes_kernel, cl::NullRange,
                                       cl::NDRange(pad_to_group((pool_ + span - 1) / span, group)), cl::NDRange(group));
    } else {
      set_launch_args(s, uint32_t(n), dense, job_start);
      size_t global = dense ? size_t(pool_) : pad_to_group(n);  // pool is a multiple of the group
      rt_.queue().enqueueNDRangeKernel(s.kernel, cl::NullRange, cl::NDRange(global), cl::NDRange(kWorkGroup));
    }
    if (s.appends) rt_.queue().enqueueReadBuffer(buf_.counters, CL_TRUE, 0, sizeof cnt_, cnt_);
    else rt_.queue().finish();
    s.seconds += since(t0);
    s.items += n;
  }

  // Paths in the queues the iteration loop consumes (accumulate sends split paths back to
  // the lobe queues, so those can be non-empty at the top of an iteration).
  uint32_t in_flight() const {
    uint32_t n = cnt_[AW_Q_RAY];
    for (uint32_t l = 0; l < AW_LID_COUNT; ++l) n += cnt_[AW_Q_LOBE + l];
    return n;
  }

  // The batch ring. A batch is a run of jobs whose samples go to the film together
  // (film_accumulate), at most max_batch_ of them; the samples (and AOV reports) of two batches
  // fit in the ring's two halves, so the next batch's paths start in the slots that the last
  // paths of the one before leave free, and the pool drains only at the end of the render.
  // Why: a batch that waited for its last paths ran its last iterations on an ever smaller
  // share of the pool, and the stages written on lanes cost per block of 16 slots, not per
  // path: on an AVX-512 Xeon those tails were 5% of the Cornell box's render on Intel's
  // runtime (one batch for the whole render measured 0.947x; docs/performance.md, "The batch
  // ring"). accumulate counts each half's finished jobs (AW_C_FINISHED), and a batch goes to
  // the film, oldest first, once all its issued jobs have finished; the time limit, the
  // checkpoints and the snapshots are taken there, as at the end of a batch before.
  struct Batch {
    uint64_t first = 0;   // its first job (of the render's jobs)
    uint32_t size = 0;    // its jobs (cut to those issued when issuing stops)
    uint32_t issued = 0;  // its jobs started so far
    uint32_t base = 0;    // its half of the ring: jobs base .. base + size - 1 there
  };

  // RenderParams' batch fields for batch b: ring index base + i is the batch's job i
  // (kernels/types/scene.h: batch_pixel + j maps to the pixel, in uint arithmetic).
  void set_batch_params(const Batch& b, uint32_t jobs) {
    const uint64_t c = (uint64_t(b.base) + npix_ - 1) / npix_;  // whole passes of pixels at or above base
    rp_.batch_pixel = uint32_t(b.first % npix_ + c * npix_ - b.base);
    rp_.batch_sample = first_sample_ + uint32_t(b.first / npix_) - uint32_t(c);
    rp_.job_count = jobs;
  }

  // Jobs [jobs_done, stop_at) through the pool: every issued job's sample lands in the film,
  // and jobs_done counts them. An interrupt stops new paths; the ones in flight finish
  // (bounded by max_depth), so every job issued lands in the film.
  void run_jobs(uint64_t& jobs_done, uint64_t& stop_at, ProgressLine& progress) {
    auto& q = rt_.queue();
    q.enqueueWriteBuffer(buf_.queues, CL_TRUE, size_t(AW_Q_FREE) * pool_ * 4, size_t(pool_) * 4, identity_.data());
    q.enqueueFillBuffer(buf_.tags, uint32_t(AW_Q_FREE), 0, size_t(pool_) * 4);
    std::fill(cnt_, cnt_ + AW_C_COUNT, 0u);
    cnt_[AW_Q_FREE] = pool_;
    untracked_free_ = 0;
    std::deque<Batch> ring;  // oldest first: at most two
    uint64_t next_first = jobs_done, issued = jobs_done;
    bool issuing = true;
    auto last_checkpoint = Clock::now();
    for (;;) {
      // Batches whose every issued path has ended go to the film, oldest first.
      while (!ring.empty()) {
        Batch& b = ring.front();
        if (!issuing && b.issued < b.size) b.size = b.issued;
        if (b.issued < b.size || cnt_[AW_C_FINISHED + (b.base != 0)] != b.issued) break;
        set_batch_params(b, b.issued);
        launch(stages_[film_], npix_, b.base);
        jobs_done += b.issued;
        ring.pop_front();
        progress.update(jobs_done);
        if (!issuing) continue;
        if (opts_.time_limit > 0.0 && stop_at == total_jobs_ && since(t_start_) >= opts_.time_limit) {
          // The end of the sample pass of the last job issued; the open batch ends there.
          stop_at = std::min(total_jobs_, (issued + npix_ - 1) / npix_ * npix_);
          st_.time_limited = stop_at < total_jobs_;
          if (st_.time_limited) progress.set_note("time limit: finishing this sample pass");
          if (!ring.empty() && ring.back().first + ring.back().size > stop_at)
            ring.back().size = uint32_t(stop_at - ring.back().first);
          next_first = std::min(next_first, stop_at);
        }
        if (jobs_done >= stop_at) continue;
        if (opts_.checkpoint && opts_.checkpoint_seconds > 0.0 && since(last_checkpoint) >= opts_.checkpoint_seconds) {
          read_film();
          opts_.checkpoint(res_);
          ++st_.checkpoints;
          progress.set_note("checkpoint " + std::to_string(st_.checkpoints) + " written");
          last_checkpoint = Clock::now();
        } else if (opts_.snapshot_seconds == 0.0 ||
                   (opts_.snapshot_seconds > 0.0 &&
                    since(last_snapshot_) >= std::max(opts_.snapshot_seconds, kSnapshotCostFactor * last_snapshot_cost_))) {
          snapshot();
        }
      }
      if (cancelled()) issuing = false;
      if (issuing) issue(ring, next_first, issued, stop_at);
      if (in_flight() == 0) {
        if (ring.empty() && (!issuing || next_first >= stop_at)) return;
        // Every issued path has ended, so the ring's batches go to the film at the top of the
        // loop, and then the next ones start; a batch still waiting for paths, or jobs left
        // with no batch to take them, means a stage lost a path.
        bool all_finished = true;
        for (const Batch& b : ring) all_finished = all_finished && cnt_[AW_C_FINISHED + (b.base != 0)] == b.issued;
        if (!all_finished || ring.empty())
          throw std::logic_error("wavefront: no path in flight but jobs remain (a stage lost a path)");
        continue;
      }
      run_iteration();
      progress.update(issued - std::min<uint64_t>(issued, in_flight()));
    }
  }

  // regenerate: the free slots take the next jobs, of the open batch and then of a new one in
  // the ring's other half, one launch per batch. The queue form takes the last entries of the
  // FREE queue (kernels.cl), so what it leaves stays queued; the lane form takes FREE-tagged
  // slots (kernels_lanes.cl), whatever the queue holds, and the FREE slots it leaves are
  // counted in untracked_free_ for the next dense launch.
  void issue(std::deque<Batch>& ring, uint64_t& next_first, uint64_t& issued, uint64_t stop_at) {
    Stage& s = stages_[regen_];
    for (;;) {
      const uint32_t free_total = cnt_[AW_Q_FREE] + untracked_free_;
      if (free_total == 0) return;
      if (ring.empty() || ring.back().issued == ring.back().size) {
        if (next_first >= stop_at || ring.size() == 2) return;
        Batch b;
        b.first = next_first;
        b.size = uint32_t(std::min<uint64_t>(max_batch_, stop_at - next_first));
        b.base = ring.empty() || ring.front().base != 0 ? 0u : max_batch_;
        cnt_[AW_C_FINISHED + (b.base != 0)] = 0;
        ring.push_back(b);
        next_first += b.size;
      }
      Batch& b = ring.back();
      const uint32_t want = std::min(free_total, b.size - b.issued);
      const bool dense = launches_dense(s, want);
      const uint32_t take = dense ? want : std::min(want, cnt_[AW_Q_FREE]);
      if (take == 0) return;  // free slots only the lane form sees, too few for it: they wait
      set_batch_params(b, b.size);
      launch(s, take, b.base + b.issued);
      if (dense) {
        untracked_free_ = free_total - take;
        cnt_[AW_Q_FREE] = 0;
      } else {
        cnt_[AW_Q_FREE] -= take;
      }
      b.issued += take;
      issued += take;
    }
  }

  // Every stage once, in queue order: each consumes the whole queue it reads.
  void run_iteration() {
    ++st_.iterations;
    uint32_t n_ray = cnt_[AW_Q_RAY];
    st_.closest_rays += n_ray;
    launch(stages_[isect_], n_ray);
    launch(stages_[classify_], n_ray);
    cnt_[AW_Q_RAY] = 0;  // consumed; shading refills it
    launch(stages_[ao_], cnt_[AW_Q_AO]);  // hands its paths to the lobe queues below
    cnt_[AW_Q_AO] = 0;
    for (uint32_t l = 0; l < AW_LID_COUNT; ++l) {
      launch(stages_[shade_[l]], cnt_[AW_Q_LOBE + l]);
      cnt_[AW_Q_LOBE + l] = 0;
    }
    uint32_t n_shadow = cnt_[AW_Q_SHADOW];
    st_.shadow_rays += n_shadow;
    launch(stages_[shadow_], n_shadow);
    cnt_[AW_Q_SHADOW] = 0;
    launch(stages_[accum_], cnt_[AW_Q_DONE], max_batch_);  // job_start: the ring's half (AW_C_FINISHED)
    cnt_[AW_Q_DONE] = 0;
  }

  // The film so far into res_ (acc, count, sum, samples).
  void read_film() {
    snapshot();
    res_.update_sums();
    st_.samples = film_held() - st_.resumed_samples;
  }

  void read_back() {
    auto& q = rt_.queue();
    read_film();
    std::vector<uint32_t> stat_vals(AW_STAT_COUNT);
    q.enqueueReadBuffer(buf_.stats, CL_TRUE, 0, stat_vals.size() * 4, stat_vals.data());
    st_.bad_samples = stat_vals[AW_STAT_BAD_SAMPLES];
    if (stat_vals[AW_STAT_MISSING_FEATURE] > 0)
      throw std::logic_error(std::to_string(stat_vals[AW_STAT_MISSING_FEATURE]) +
                             " paths met a material feature that the specialised kernels lack (" +
                             st_.kernel_features + "); the image would be wrong, so none is written. "
                             "--generic-kernels renders it; please report this scene");
    for (const Stage& s : stages_)
      if (s.seconds > 0.0) {
        st_.stage_seconds.emplace_back(s.name, s.seconds);
        st_.stage_items.push_back(s.items);
      }
  }

  const Scene& scene_;
  const RenderOptions& opts_;
  RenderResult& res_;
  RenderStats& st_;
  PackedScene packed_;
  ClRuntime rt_;
  FlatBvh bvh_;
  FeatureSet features_;
  cl::Program program_;
  cl::Program lanes_program_;  // kernels_lanes.cl, when the device and the scene allow (build_lanes_program)
  // The ray stages' and classification's lane program, at narrow_lanes_ (narrow_lane_width):
  // lanes_program_ itself where that is 16 lanes too.
  cl::Program narrow_program_;
  uint32_t narrow_lanes_ = kLanes;
  uint32_t lane_wg_ = kWorkGroup;  // the lane programs' work-group size (lane_work_group)
  bool classify_on_lanes_ = false;  // its classify_hit too (build_lanes_program)
  bool closest_sorted_ = false;     // and sorts its rays first (kSortMinPrimitives)
  bool closest_on_lanes_ = false;   // its intersect_closest too (build_lanes_program)
  bool shadow_on_lanes_ = false;    // its intersect_shadow too (build_lanes_program)
  bool accumulate_on_lanes_ = false;  // its accumulate too (build_lanes_program)
  RenderParams rp_{};
  uint32_t npix_ = 0, pool_ = 0, max_batch_ = 0, ring_jobs_ = 0;
  uint32_t first_sample_ = 0;  // the sample of job 0 (begin_film)
  Clock::time_point t_start_ = Clock::now();
  uint64_t total_jobs_ = 0;
  StageBuffers buf_;
  std::vector<uint32_t> identity_;
  std::vector<Stage> stages_;
  size_t regen_ = 0, isect_ = 0, classify_ = 0, ao_ = 0, shadow_ = 0, accum_ = 0, film_ = 0;
  size_t shade_[AW_LID_COUNT] = {};
  uint32_t cnt_[AW_C_COUNT] = {};  // the host's copy of the queue counters (and AW_C_FINISHED)
  uint32_t untracked_free_ = 0;    // FREE-tagged slots not in the FREE queue (issue)
  Clock::time_point last_snapshot_ = Clock::now();
  double last_snapshot_cost_ = 0.0;
  bool film_kept_ = true;  // res_ holds a whole film (begin_film's, or a finished snapshot)
  unsigned long fault_at_ = 0, launches_ = 0;  // ARCHWAVE_FAULT
  bool fault_lost_ = false, lost_ = false;
};

}  // namespace

// Paths per work-item of the stages whose 16-lane form spills most where a SIMD register holds
// 8 floats (AVX2): the ray stages and classification. Intel's runtime on an AMD EPYC (Zen 3,
// AVX2; Cornell box, medians of 8 interleaved pairs, everything at 8 lanes against 16):
// intersect_closest 0.92x, classify_hit 0.84x, intersect_shadow 0.85x the time, but
// shade_diffuse 1.12x and regenerate 1.29x, so those keep 16; with only these three at 8, at
// the race's 128x128 and 256 spp: 0.94x, 0.91x, 0.90x, the render 0.96x. PoCL there: 1.01x,
// 0.97x, 1.02x and shading 1.36x, so it keeps 16 throughout; so does a device with 16 floats
// per register (AVX-512), where 16 lanes are one register (docs/performance.md, "On an AMD
// EPYC (AVX2)").
uint32_t narrow_lane_width(const DeviceInfo& d, int forced) {
  if (forced != 0 && forced != 8 && forced != 16)
    throw std::invalid_argument("narrow lane width " + std::to_string(forced) + ": expected 8 or 16 (or 0: the device's choice)");
  if (forced != 0) return uint32_t(forced);
  return intel_runtime(d) && d.native_float_width == 8 ? 8u : kLanes;
}

// Work-items per group of the lane programs: 2,048 paths per group on Intel's CPU runtime
// (8 work-items of kLaneSpan), 16,384 on other devices (64). Intel's runtime shares out whole
// groups among its threads, and with 4 groups per launch of its default pool (2^16) one thread
// idled at the end of every launch where a stage's paths sat unevenly in the pool (TBB's
// waits were 3.5% of a profile's samples): 32 groups made the render 0.89x the time on an AMD
// EPYC (Zen 3, 2 cores; Cornell box, 128x128, 256 spp, median of 12 interleaved pairs; 16
// groups: 0.93x; 64: 0.98x, 8 pairs), every stage alike. PoCL runs a group as one task with
// its own overhead, and smaller groups were slower there (docs/performance.md, "Smaller
// work-groups for the lane programs on Intel's runtime"). Both measured at 64 paths per
// work-item and kept per group at 256 (on PoCL, 32 work-items a group measured level with 64).
uint32_t lane_work_group(const DeviceInfo& d) { return (intel_runtime(d) ? 2048u : 16384u) / kLaneSpan; }

RenderResult render_wavefront(const Scene& scene, const RenderOptions& opts) {
  auto t_start = Clock::now();
  RenderResult res;
  res.stats.renderer = "wavefront";
  Wavefront w(scene, opts, res);  // packs the scene and opens the device
  res.stats.setup_seconds = since(t_start);
  w.render();
  res.stats.total_seconds = since(t_start);
  return res;
}

}  // namespace aw
