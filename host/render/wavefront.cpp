// The wavefront driver: a fixed pool of path states, one kernel per stage, queues between
// them (kernels/integrator/queues.h has the scheduling rule).
//
// Work is a sequence of jobs (pixel, sample) in sample-major order, processed in batches.
// Within a batch, free slots take the next jobs in order; a finished path writes its sample
// value to samples[job]; at the end of the batch film_accumulate adds the batch to the film
// pixel by pixel in sample order. So the film's summation order is fixed by the job order
// alone: the image does not depend on the pool size, the batch size, or which slot ran what.
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <numeric>
#include <stdexcept>

#include "host/bvh/flat_bvh.h"
#include "host/cl/cl_runtime.h"
#include "host/cl/kernel_source.h"
#include "host/film/progress.h"
#include "host/render/features.h"
#include "host/render/render.h"
#include "host/render/scene_pack.h"
#include "kernels/integrator/path_state.h"
#include "kernels/integrator/queues.h"
#include "kernels/integrator/split.h"

namespace aw {

namespace {

// Explicit local size everywhere (DESIGN.md: PoCL facts). 256 rather than 64: PoCL runs a
// work-group as one task, and its per-task overhead (~5 us) dominated the cheap stages at 64
// (accumulate: 0.24 s -> 0.07 s for 2.6M paths on the Cornell box); the heavy stages do not
// care.
constexpr uint32_t kWorkGroup = 256;
constexpr double kDenseFraction = 0.25;  // see dense_fraction below

size_t pad_to_group(size_t n) { return (n + kWorkGroup - 1) / kWorkGroup * kWorkGroup; }

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

uint32_t default_pool_size() {
  if (const char* e = std::getenv("ARCHWAVE_POOL")) {
    long v = std::strtol(e, nullptr, 10);
    if (v >= long(kWorkGroup)) return uint32_t(v);
  }
  return 1u << 18;
}

template <class T>
cl::Buffer upload(ClRuntime& rt, const char* what, const std::vector<T>& v, cl_mem_flags flags = CL_MEM_READ_ONLY) {
  return rt.buffer(what, v.size() * sizeof(T), flags, v.empty() ? nullptr : v.data());
}

struct Stage {
  const char* name;
  cl::Kernel kernel;
  double seconds = 0.0;
  uint64_t items = 0;  // paths (pixels for film_accumulate) processed: throughput per stage
};

}  // namespace

RenderResult render_wavefront(const Scene& scene, const RenderOptions& opts) {
  auto t_start = Clock::now();
  RenderResult res;
  RenderStats& st = res.stats;
  st.renderer = "wavefront";
  PackedScene packed = pack_scene(scene, &st.warnings);

  auto t_bvh = Clock::now();
  EmbreeDevice embree;
  FlatBvh bvh = build_flat_bvh(embree, packed.soup);
  st.bvh_seconds = since(t_bvh);

  ClRuntime rt(opts.device);
  st.device = rt.info().name + " (" + rt.info().platform + ")";
  std::string src = assemble_kernel_source("integrator/kernels.cl", opts.kernel_dir);
  // Model only what the scene requires: specialise the program on the scene's features.
  const FeatureSet need = derive_features(packed);
  FeatureSet features = opts.generic_kernels ? FeatureSet::all() : need;
  for (const std::string& off : opts.force_off)
    for (int i = 0; i < FeatureSet::COUNT; ++i)
      if (off == FeatureSet::name(i)) features.on[i] = false;
  st.kernel_features = opts.generic_kernels ? "generic (every feature)" : "specialised: " + features.describe();
  // Material features are checked at every hit (classify_hit), lobe splitting where it
  // starts (shade_surface); light types have no such check in the kernels (a compiled-out
  // type would be sampled as another one), so the host refuses the build here.
  std::string lack;
  for (int i : {FeatureSet::LIGHT_POINT, FeatureSet::LIGHT_QUAD, FeatureSet::LIGHT_DISK, FeatureSet::LIGHT_SPHERE})
    if (need.on[i] && !features.on[i]) lack += std::string(lack.empty() ? "" : ", ") + FeatureSet::name(i);
  if (!lack.empty())
    throw std::logic_error("the scene has lights of a type the specialised kernels lack (" + lack + "; built: " +
                           st.kernel_features + "); the image would be wrong, so none is rendered");
  std::string options = "-cl-std=CL1.2 -DAW_WG=" + std::to_string(kWorkGroup) + " " +
                        (opts.generic_kernels ? std::string() : features.defines()) + " " + opts.build_options;
  cl::Program program = rt.build(src, options, &st.compile_seconds);

  try {
    RenderParams rp = packed.params;
    const uint32_t npix = rp.width * rp.height;
    const uint64_t total_jobs = uint64_t(npix) * uint64_t(scene.render.spp);
    uint32_t pool = opts.pool_size ? opts.pool_size : default_pool_size();
    pool = uint32_t(std::min<uint64_t>(pool, pad_to_group(total_jobs)));
    pool = uint32_t(pad_to_group(pool));
    rp.pool_size = pool;
    rp.num_nodes = uint32_t(bvh.nodes.size());
    uint32_t max_batch = opts.max_batch ? opts.max_batch : 4u * pool;
    max_batch = uint32_t(std::min<uint64_t>(max_batch, total_jobs));

    auto& q = rt.queue();
    cl::Buffer sf = rt.buffer("path state (float fields)", size_t(AW_SF_COUNT) * pool * 4);
    cl::Buffer su = rt.buffer("path state (uint fields)", size_t(AW_SU_COUNT) * pool * 4);
    st.state_bytes = size_t(AW_SF_COUNT + AW_SU_COUNT) * pool * 4;
    // Lobe splitting's first-hit snapshots (integrator/split.h): only when the scene splits.
    const bool splits = rp.split_spp != 0u;
    cl::Buffer snap_f = rt.buffer("lobe-split snapshots (float fields)", splits ? size_t(AW_SNAP_F_COUNT) * pool * 4 : 4);
    cl::Buffer snap_u = rt.buffer("lobe-split snapshots (uint fields)", splits ? size_t(AW_SNAP_U_COUNT) * pool * 4 : 4);
    if (splits) st.state_bytes += size_t(AW_SNAP_F_COUNT + AW_SNAP_U_COUNT) * pool * 4;
    st.pool_size = pool;
    // All queues in one buffer: queue i at [i * pool, (i + 1) * pool).
    cl::Buffer queues = rt.buffer("queues", size_t(AW_Q_COUNT) * pool * 4);
    cl::Buffer counters = rt.buffer("queue counters", AW_Q_COUNT * 4);
    // The queue each slot is in (kernels.cl: wg_append, AW_DENSE_ITEM); all free at the start
    // of every batch.
    cl::Buffer tags = rt.buffer("queue tags", size_t(pool) * 4);
    std::vector<uint32_t> zero_stats(AW_STAT_COUNT, 0);
    cl::Buffer stats = upload(rt, "stats counters", zero_stats, CL_MEM_READ_WRITE);
    cl::Buffer samples = rt.buffer("batch samples", size_t(max_batch) * 3 * 4);
    std::vector<float> film_init(size_t(npix) * 3, 0.0f);
    std::vector<uint32_t> count_init(npix, 0);
    cl::Buffer film = upload(rt, "film", film_init, CL_MEM_READ_WRITE);
    cl::Buffer film_count = upload(rt, "film sample counts", count_init, CL_MEM_READ_WRITE);
    cl::Buffer nodes = rt.buffer("BVH nodes", bvh.nodes.size() * sizeof(BvhNode), CL_MEM_READ_ONLY,
                                 bvh.nodes.empty() ? nullptr : bvh.nodes.data());
    cl::Buffer tris = rt.buffer("BVH leaf triangles", bvh.leaf_tris.size() * sizeof(LeafTriangle), CL_MEM_READ_ONLY,
                                bvh.leaf_tris.empty() ? nullptr : bvh.leaf_tris.data());
    cl::Buffer tri_info = upload(rt, "triangle info", packed.tri_info);
    cl::Buffer verts = upload(rt, "vertices", packed.verts);
    cl::Buffer materials = upload(rt, "materials", packed.materials);
    cl::Buffer lights = upload(rt, "lights", packed.lights);
    st.triangles = packed.soup.indices.size();
    st.scene_bytes = bvh.nodes.size() * sizeof(BvhNode) + bvh.leaf_tris.size() * sizeof(LeafTriangle) +
                     packed_arrays_bytes(packed);
    st.film_bytes = size_t(npix) * (3 + 1) * 4 + size_t(max_batch) * 3 * 4;  // film, counts, batch samples
    st.device_bytes = rt.allocated_bytes();
    std::vector<uint32_t> identity(pool);
    std::iota(identity.begin(), identity.end(), 0u);

    // Kernels and their fixed arguments (argument 0, the RenderParams, and the item count are
    // set per launch). `count_arg` is the index of the count argument.
    auto make = [&](const char* name, const char* kernel) { return Stage{name, cl::Kernel(program, kernel)}; };
    Stage regen = make("regenerate", "regenerate");
    regen.kernel.setArg(1, sf); regen.kernel.setArg(2, su); regen.kernel.setArg(3, queues);
    regen.kernel.setArg(4, counters); regen.kernel.setArg(7, tags);
    Stage isect = make("intersect_closest", "intersect_closest");
    isect.kernel.setArg(1, sf); isect.kernel.setArg(2, su); isect.kernel.setArg(3, queues);
    isect.kernel.setArg(5, nodes); isect.kernel.setArg(6, tris); isect.kernel.setArg(7, lights);
    isect.kernel.setArg(9, tags);
    auto shading_args = [&](Stage& s) {
      s.kernel.setArg(1, sf); s.kernel.setArg(2, su); s.kernel.setArg(3, queues); s.kernel.setArg(4, counters);
      s.kernel.setArg(6, tri_info); s.kernel.setArg(7, verts); s.kernel.setArg(8, materials);
      s.kernel.setArg(9, lights);
    };
    Stage classify = make("classify_hit", "classify_hit_stage");
    shading_args(classify);
    classify.kernel.setArg(11, tags);
    Stage pass = make("pass_through", "pass_through");
    pass.kernel.setArg(1, queues); pass.kernel.setArg(2, counters); pass.kernel.setArg(4, tags);
    const char* lobe_kernels[AW_LID_COUNT] = {"shade_diffuse", "shade_translucency", "shade_reflection",
                                              "shade_reflection2", "shade_refraction"};
    std::vector<Stage> shade;  // one per lobe; lobes absent from the build have no kernel
    std::vector<bool> has_lobe(AW_LID_COUNT);
    for (uint32_t l = 0; l < AW_LID_COUNT; ++l) {
      has_lobe[l] = features.lobe(l);
      shade.push_back(has_lobe[l] ? make(lobe_kernels[l], lobe_kernels[l]) : Stage{lobe_kernels[l], cl::Kernel()});
      if (has_lobe[l]) {
        shading_args(shade.back());
        shade.back().kernel.setArg(10, snap_f);
        shade.back().kernel.setArg(11, snap_u);
        shade.back().kernel.setArg(13, tags);
      }
    }
    Stage shadow = make("intersect_shadow", "intersect_shadow");
    shadow.kernel.setArg(1, sf); shadow.kernel.setArg(2, su); shadow.kernel.setArg(3, queues);
    shadow.kernel.setArg(5, nodes); shadow.kernel.setArg(6, tris); shadow.kernel.setArg(7, lights);
    shadow.kernel.setArg(8, tri_info); shadow.kernel.setArg(9, materials);
    Stage accum = make("accumulate", "accumulate");
    accum.kernel.setArg(1, sf); accum.kernel.setArg(2, su); accum.kernel.setArg(3, queues);
    accum.kernel.setArg(4, counters); accum.kernel.setArg(6, samples); accum.kernel.setArg(7, stats);
    accum.kernel.setArg(8, snap_f); accum.kernel.setArg(9, snap_u); accum.kernel.setArg(10, tags);
    Stage filmacc = make("film_accumulate", "film_accumulate");
    filmacc.kernel.setArg(1, samples); filmacc.kernel.setArg(2, film); filmacc.kernel.setArg(3, film_count);

    std::vector<Stage*> all = {&regen, &isect, &classify, &pass};
    for (uint32_t l = 0; l < AW_LID_COUNT; ++l)
      if (has_lobe[l]) all.push_back(&shade[l]);
    for (Stage* s : {&shadow, &accum, &filmacc}) all.push_back(s);
    auto count_arg = [&](const Stage* s) {
      if (s == &pass) return 3;
      if (s == &isect || s == &shadow) return 4;
      if (s == &filmacc) return -1;
      return 5;
    };
    // The `dense` argument of the stages that can run over the pool in slot order, or -1.
    auto dense_arg = [&](const Stage* s) {
      if (s == &isect) return 8;
      if (s == &classify || s == &shadow) return 10;
      for (const Stage& l : shade)
        if (s == &l) return 12;
      return -1;
    };
    // A queue holding at least this share of the pool is consumed by a dense launch: one
    // work-item per slot, in slot order (kernels.cl, AW_DENSE_ITEM). The scattered slot order
    // that appends leave behind costs more than the idle work-items of a dense launch once a
    // queue holds about a quarter of the pool (docs/architecture.md, "Dense launches").
    const double dense_fraction = opts.dense_fraction >= 0.0 ? opts.dense_fraction : kDenseFraction;

    // PoCL compiles the work-group function of a kernel at its first launch with a given
    // local size, not at clBuildProgram: launch every stage once on zero items now, so that
    // cost is reported as compile time and not as the first iteration's stage time. PoCL also
    // builds a second work-group function for large grids (above ~2^16 work-items) at the
    // first such launch: a second, large launch on zero items compiles that one too (every
    // work-item masks itself out by the count, so nothing is written).
    {
      auto t0 = Clock::now();
      rp.job_count = 0;
      for (Stage* s : all) {
        s->kernel.setArg(0, sizeof(RenderParams), &rp);
        if (count_arg(s) >= 0) s->kernel.setArg(count_arg(s), 0u);
        if (dense_arg(s) >= 0) s->kernel.setArg(dense_arg(s), 0u);
        if (s == &regen) s->kernel.setArg(6, 0u);
        for (size_t global : {size_t(kWorkGroup), size_t(1) << 17})
          q.enqueueNDRangeKernel(s->kernel, cl::NullRange, cl::NDRange(global), cl::NDRange(kWorkGroup));
      }
      q.finish();
      st.compile_seconds += since(t0);
    }

    uint32_t cnt[AW_Q_COUNT] = {};
    auto push_counters = [&] { q.enqueueWriteBuffer(counters, CL_TRUE, 0, sizeof cnt, cnt); };
    auto pull_counters = [&] { q.enqueueReadBuffer(counters, CL_TRUE, 0, sizeof cnt, cnt); };
    // Runs one stage over `n` items and waits, so its time is its own. Stages that append
    // to queues get the host's counters first and return the new ones.
    auto run = [&](Stage& s, size_t n, bool counts) {
      if (n == 0 && &s != &filmacc) return;
      auto t0 = Clock::now();
      if (counts) push_counters();
      s.kernel.setArg(0, sizeof(RenderParams), &rp);
      if (count_arg(&s) >= 0) s.kernel.setArg(count_arg(&s), uint32_t(n));
      bool dense = dense_arg(&s) >= 0 && double(n) >= dense_fraction * double(pool);
      if (dense_arg(&s) >= 0) s.kernel.setArg(dense_arg(&s), uint32_t(dense));
      size_t global = dense ? size_t(pool) : pad_to_group(n);  // pool is a multiple of the group
      q.enqueueNDRangeKernel(s.kernel, cl::NullRange, cl::NDRange(global), cl::NDRange(kWorkGroup));
      if (counts) pull_counters();
      else q.finish();
      s.seconds += since(t0);
      s.items += n;
    };

    ProgressLine progress("rendering", total_jobs, opts.progress);
    uint64_t jobs_done = 0;
    while (jobs_done < total_jobs) {
      if (opts.cancel && opts.cancel->load()) break;
      uint32_t batch = uint32_t(std::min<uint64_t>(max_batch, total_jobs - jobs_done));
      rp.batch_pixel = uint32_t(jobs_done % npix);
      rp.batch_sample = uint32_t(jobs_done / npix);
      rp.job_count = batch;
      q.enqueueWriteBuffer(queues, CL_TRUE, size_t(AW_Q_FREE) * pool * 4, size_t(pool) * 4, identity.data());
      q.enqueueFillBuffer(tags, uint32_t(AW_Q_FREE), 0, size_t(pool) * 4);
      std::fill(cnt, cnt + AW_Q_COUNT, 0u);
      cnt[AW_Q_FREE] = pool;
      uint32_t next_job = 0, issue_limit = batch;
      for (;;) {
        // An interrupt stops new paths; the ones in flight finish (bounded by max_depth), so
        // every job issued so far lands in the film.
        if (opts.cancel && opts.cancel->load()) issue_limit = next_job;
        uint32_t take = std::min(cnt[AW_Q_FREE], issue_limit - next_job);
        if (take) {
          regen.kernel.setArg(6, next_job);
          run(regen, take, true);
          next_job += take;
        }
        cnt[AW_Q_FREE] = 0;  // leftover free slots only remain when no jobs are left
        uint32_t n_ray = cnt[AW_Q_RAY];
        // Lobe queues can be non-empty here: accumulate sends split paths back to them.
        uint32_t n_lobe = 0;
        for (uint32_t l = 0; l < AW_LID_COUNT; ++l) n_lobe += cnt[AW_Q_LOBE + l];
        if (n_ray == 0 && n_lobe == 0) {
          if (next_job >= issue_limit) break;
          // No path in flight and jobs left means slots were lost: a broken scheduling rule.
          throw std::logic_error("wavefront: no path in flight but jobs remain (a stage lost a path)");
        }
        ++st.iterations;
        st.closest_rays += n_ray;
        run(isect, n_ray, false);
        run(classify, n_ray, true);
        cnt[AW_Q_RAY] = 0;  // consumed; shading and pass-through refill it
        run(pass, cnt[AW_Q_PASS], true);
        cnt[AW_Q_PASS] = 0;
        for (uint32_t l = 0; l < AW_LID_COUNT; ++l) {
          uint32_t n = cnt[AW_Q_LOBE + l];
          if (n && !has_lobe[l])
            throw std::logic_error(std::string("wavefront: paths queued for lobe '") + lobe_kernels[l] +
                                   "', which this kernel build does not have");
          run(shade[l], n, true);
          cnt[AW_Q_LOBE + l] = 0;
        }
        uint32_t n_shadow = cnt[AW_Q_SHADOW];
        st.shadow_rays += n_shadow;
        run(shadow, n_shadow, false);
        cnt[AW_Q_SHADOW] = 0;
        run(accum, cnt[AW_Q_DONE], true);
        cnt[AW_Q_DONE] = 0;
        uint32_t in_flight = cnt[AW_Q_RAY];
        for (uint32_t l = 0; l < AW_LID_COUNT; ++l) in_flight += cnt[AW_Q_LOBE + l];
        progress.update(jobs_done + next_job - std::min(next_job, in_flight));
      }
      rp.job_count = next_job;
      run(filmacc, npix, false);
      jobs_done += next_job;
      st.samples += next_job;
      progress.update(jobs_done);
      if (next_job < batch) break;  // interrupted
    }
    progress.finish();
    st.interrupted = jobs_done < total_jobs;

    res.width = int(rp.width);
    res.height = int(rp.height);
    res.sum.resize(size_t(npix) * 3);
    res.count.resize(npix);
    q.enqueueReadBuffer(film, CL_TRUE, 0, res.sum.size() * 4, res.sum.data());
    q.enqueueReadBuffer(film_count, CL_TRUE, 0, res.count.size() * 4, res.count.data());
    std::vector<uint32_t> stat_vals(AW_STAT_COUNT);
    q.enqueueReadBuffer(stats, CL_TRUE, 0, stat_vals.size() * 4, stat_vals.data());
    st.bad_samples = stat_vals[AW_STAT_BAD_SAMPLES];
    if (stat_vals[AW_STAT_MISSING_FEATURE] > 0)
      throw std::logic_error(std::to_string(stat_vals[AW_STAT_MISSING_FEATURE]) +
                             " paths met a material feature that the specialised kernels lack (" +
                             st.kernel_features + "); the image would be wrong, so none is written. "
                             "--generic-kernels renders it; please report this scene");
    for (Stage* s : all)
      if (s->seconds > 0.0) {
        st.stage_seconds.emplace_back(s->name, s->seconds);
        st.stage_items.push_back(s->items);
      }
  } catch (const cl::Error& e) {
    throw ClError(std::string("OpenCL error while rendering on ") + rt.info().name + ": " + e.what() + " (" +
                  cl_error_name(e.err()) + ")");
  }
  st.total_seconds = since(t_start);
  return res;
}

}  // namespace aw
