// The host scalar path: the cross-check of the wavefront. It runs one path at a time through
// the SAME stage functions as the kernels, by way of kernels/integrator/megakernel.h compiled
// as C++, but casts rays with Embree's rtcIntersect1/rtcOccluded1 (ray_cast_embree.cpp): an
// independent traversal, so a BVH or intersection bug shows up as a difference between the
// two. It consumes the same random numbers and sums each pixel's samples in the same order as
// film_accumulate, so the two images agree pixel by pixel, not only on average.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>

#include "host/bvh/flat_bvh.h"
#include "host/film/progress.h"
#include "host/render/features.h"
#include "host/render/render.h"
#include "host/render/scene_pack.h"
#include "host/scalar/ray_cast_embree.h"
#include "kernels/integrator/aov.h"
#include "kernels/integrator/film.h"
#include "kernels/integrator/megakernel.h"

namespace aw {

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
}  // namespace

RenderResult render_scalar(const Scene& scene, const RenderOptions& opts) {
  auto t_start = Clock::now();
  RenderResult res;
  RenderStats& st = res.stats;
  st.renderer = "scalar";
  st.device = "host (Embree rtcIntersect1)";
  PackedScene packed = pack_scene(scene, &st.warnings);
  // The scene the stages read; the ray caster is set once Embree's scene exists.
  SceneRef sc_shared;
  SceneRef& sc = sc_shared;
  sc.tri_info = packed.tri_info.data();
  sc.verts = packed.verts.data();
  sc.materials = packed.materials.data();
  sc.lights = packed.lights.data();
  sc.env = packed.env.data();
  sc.light_tree = packed.light_tree.data();
  sc.tri_light = packed.tri_light.data();
  sc.textures = packed.textures.data();
  sc.tex_bindings = packed.tex_bindings.data();
  sc.texels = packed.texels.data();
  sc.insts = packed.soup.instances.data();  // the transforms (the roots are the flattened BVH's)
  sc.mat_resolved = nullptr;  // each thread's own (worker)

  auto t_bvh = Clock::now();
  EmbreeDevice embree;
  // Cutouts are tested by Embree's filter functions with the kernels' own test (flat_bvh.h).
  const TextureScene cut = scene_texture_ref(sc);
  EmbreeScene escene(embree, packed.soup, packed.features.on[FeatureSet::CUTOUT] ? &cut : nullptr);
  st.bvh_seconds = since(t_bvh);
  st.triangles = packed.soup.indices.size();
  st.spheres = packed.soup.spheres.size();
  st.instances = packed.soup.instances.size();
  st.instanced_triangles = scene.rendered_triangle_count();
  st.scene_bytes = packed_arrays_bytes(packed);  // Embree's BVH is Embree's business, not counted
  const HostRayCaster caster{&escene};
  sc.caster = &caster;

  RenderParams base = packed.params;
  const uint32_t first = begin_film(scene, opts, packed, base, res);
  const uint32_t start = res.sample_start, end = res.sample_end;
  const uint32_t fw = uint32_t(res.width), fh = uint32_t(res.height);
  const uint32_t npix = fw * fh;
  const uint32_t aov_ch = aov_film_channels(res.aov_mask);

  std::atomic<uint64_t> closest{0}, shadow{0}, bad_total{0}, missing{0}, done_samples{0};
  ProgressLine progress((opts.progress_label.empty() ? "rendering" : opts.progress_label) + " (scalar)",
                        uint64_t(npix) * (end - first), opts.progress);

  // Samples [pass_lo, pass_hi) of every film row, rows shared among the threads. Each pixel
  // takes the samples of the pass it lacks (a resumed film's pixels may hold some already);
  // the film's exact sums (kernels/integrator/film.h) make the order irrelevant.
  auto run_pass = [&](uint32_t pass_lo, uint32_t pass_hi, int threads) {
    std::atomic<uint32_t> next_row{0};
    auto worker = [&] {
      float sf[AW_SF_COUNT];
      uint32_t su[AW_SU_COUNT];
      float snap_f[AW_SNAP_F_COUNT];  // lobe splitting's first-hit snapshot (split.h)
      uint32_t snap_u[AW_SNAP_U_COUNT];
      float aov_state[AW_AOV_STATE];  // the first hit's AOV data (integrator/aov.h)
      float aov_report[AW_AOV_FLOATS];
      PathRef ps;
      ps.aov = aov_state;
      ps.sf = sf;
      ps.su = su;
      ps.snap_f = snap_f;
      ps.snap_u = snap_u;
      ps.pool = 1;
      ps.slot = 0;
      RenderParams rp = base;
      rp.pool_size = 1;
      MaterialGpu resolved;  // this thread's textured material (integrator/shading_material.h)
      SceneRef sc = sc_shared;
      sc.mat_resolved = &resolved;
      MegakernelCounts counts = {0, 0, 0, 0};
      for (;;) {
        if (opts.cancel && opts.cancel->load()) break;
        uint32_t y = next_row.fetch_add(1);
        if (y >= fh) break;
        uint64_t row_samples = 0;
        for (uint32_t x = 0; x < fw; ++x) {
          uint32_t pixel = y * fw + x;  // the film's (window's) pixel
          for (uint32_t s = std::max(pass_lo, start + res.count[pixel]); s < pass_hi; ++s) {
            // One job: this pixel, this sample (see RenderParams: batch-local job 0).
            rp.batch_pixel = pixel;
            rp.batch_sample = s;
            rp.job_count = 1;
            float3 l = megakernel_path(ps, sc, &rp, 0u, &counts, aov_report);
            film_add(&res.acc[size_t(pixel) * AW_FILM_WORDS], l);
            if (aov_ch) film_add_aovs(&res.aov_acc[size_t(pixel) * aov_ch * 2], aov_report, res.aov_mask);
            ++res.count[pixel];
            ++row_samples;
          }
        }
        progress.update(done_samples.fetch_add(row_samples) + row_samples);
      }
      closest += counts.closest;
      shadow += counts.shadow;
      bad_total += counts.bad;
      missing += counts.missing;
    };
    std::vector<std::thread> pool;
    for (int i = 0; i < threads; ++i) pool.emplace_back(worker);
    for (auto& t : pool) t.join();
  };

  auto t_render = Clock::now();
  int threads = opts.threads > 0 ? opts.threads : int(std::max(1u, std::thread::hardware_concurrency()));
  // One pass of every sample, unless a time limit or checkpoints need the film at whole
  // samples: then one pass per sample.
  const bool stepwise = opts.time_limit > 0.0 || (opts.checkpoint && opts.checkpoint_seconds > 0.0);
  auto last_checkpoint = Clock::now();
  uint32_t pass = first;
  while (pass < end) {
    const uint32_t hi = stepwise ? pass + 1 : end;
    run_pass(pass, hi, threads);
    if (opts.cancel && opts.cancel->load()) break;
    pass = hi;
    if (pass < end && opts.time_limit > 0.0 && since(t_start) >= opts.time_limit) {
      st.time_limited = true;
      break;
    }
    if (pass < end && opts.checkpoint && opts.checkpoint_seconds > 0.0 && since(last_checkpoint) >= opts.checkpoint_seconds) {
      res.update_sums();
      st.samples = done_samples;
      opts.checkpoint(res);
      ++st.checkpoints;
      progress.set_note("checkpoint " + std::to_string(st.checkpoints) + " written");
      last_checkpoint = Clock::now();
    }
  }
  progress.finish();
  st.stage_seconds.emplace_back("paths (all stages)", since(t_render));
  st.closest_rays = closest;
  st.shadow_rays = shadow;
  st.bad_samples = bad_total;
  // The scalar path is the generic build: no path can miss a feature; if one did, the image
  // would be wrong, so none is returned.
  if (missing > 0)
    throw std::logic_error("scalar path: " + std::to_string(missing.load()) + " paths met a feature the build lacks");
  st.samples = done_samples;
  st.interrupted = !st.time_limited && pass < end;
  res.update_sums();
  st.total_seconds = since(t_start);
  return res;
}

}  // namespace aw
