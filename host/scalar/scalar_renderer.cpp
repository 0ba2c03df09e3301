// The host scalar path: the cross-check of the wavefront. It runs one path at a time through
// the SAME stage functions (kernels/integrator/*.h compiled as C++), like Cycles' CPU
// megakernel, but casts rays with Embree's rtcIntersect1/rtcOccluded1: an independent
// traversal, so a BVH or intersection bug shows up as a difference between the two.
// It consumes the same random numbers and sums each pixel's samples in the same order as
// film_accumulate, so the two images agree pixel by pixel, not only on average.
#include <algorithm>
#include <cmath>
#include <atomic>
#include <chrono>
#include <thread>

#include "host/bvh/flat_bvh.h"
#include "host/film/progress.h"
#include "host/render/features.h"
#include "host/render/render.h"
#include "host/render/scene_pack.h"
#include "kernels/integrator/accumulate.h"
#include "kernels/integrator/classify_hit.h"
#include "kernels/integrator/generate_camera_ray.h"
#include "kernels/integrator/shade_surface.h"
#include "kernels/integrator/shade_shadow.h"
#include "kernels/integrator/split.h"

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
  auto t_bvh = Clock::now();
  EmbreeDevice embree;
  EmbreeScene escene(embree, packed.soup);
  st.bvh_seconds = since(t_bvh);
  st.triangles = packed.soup.indices.size();
  st.scene_bytes = packed_arrays_bytes(packed);  // Embree's BVH is Embree's business, not counted

  const RenderParams base = packed.params;
  // Cutout surfaces let shadow rays through: step with closest hits only when there are any.
  const bool cutouts = derive_features(packed).on[FeatureSet::CUTOUT];
  const uint32_t npix = base.width * base.height;
  const uint32_t spp = uint32_t(scene.render.spp);
  res.width = int(base.width);
  res.height = int(base.height);
  res.sum.assign(size_t(npix) * 3, 0.0f);
  res.count.assign(npix, 0u);

  SceneRef sc;
  sc.tri_info = packed.tri_info.data();
  sc.verts = packed.verts.data();
  sc.materials = packed.materials.data();
  sc.lights = packed.lights.data();

  std::atomic<uint32_t> next_row{0};
  std::atomic<uint64_t> closest{0}, shadow{0}, bad_total{0}, done_samples{0};
  ProgressLine progress("rendering (scalar)", uint64_t(npix) * spp, opts.progress);

  auto worker = [&] {
    float sf[AW_SF_COUNT];
    uint32_t su[AW_SU_COUNT];
    float snap_f[AW_SNAP_F_COUNT];  // lobe splitting's first-hit snapshot (split.h)
    uint32_t snap_u[AW_SNAP_U_COUNT];
    PathRef ps;
    ps.sf = sf;
    ps.su = su;
    ps.snap_f = snap_f;
    ps.snap_u = snap_u;
    ps.pool = 1;
    ps.slot = 0;
    RenderParams rp = base;
    rp.pool_size = 1;
    uint64_t n_closest = 0, n_shadow = 0, n_bad = 0;
    for (;;) {
      if (opts.cancel && opts.cancel->load()) break;
      uint32_t y = next_row.fetch_add(1);
      if (y >= base.height) break;
      for (uint32_t x = 0; x < base.width; ++x) {
        uint32_t pixel = y * base.width + x;
        float3 sum(res.sum[pixel * 3 + 0], res.sum[pixel * 3 + 1], res.sum[pixel * 3 + 2]);
        for (uint32_t s = 0; s < spp; ++s) {
          // One job: this pixel, this sample (see RenderParams: batch-local job 0).
          rp.batch_pixel = pixel;
          rp.batch_sample = s;
          rp.job_count = 1;
          generate_camera_ray(ps, &rp, 0u);
          // The wavefront's stages in its order: RAY -> (closest hit, classify) -> LOBE + lid
          // -> (shade, shadow ray) -> RAY | DONE; DONE -> accumulate, which may send a split
          // path back to its first-hit lobe (split.h).
          int next = AW_Q_RAY;
          float3 l(0.0f);
          for (;;) {
            if (next == AW_Q_RAY) {
              float3 o = ps_ray_origin(ps), d = ps_ray_dir(ps);
              // Embree's t_near is inclusive, the kernels' t_min exclusive (see classify_hit).
              float tmin = PS_F(ps, ray_tmin);
              EmbreeScene::Hit h = escene.intersect(o, d, tmin > 0.0f ? std::nextafter(tmin, FLT_MAX) : 0.0f, FLT_MAX);
              ++n_closest;
              float t = h.t;
              int light = lights_intersect(sc.lights, rp.num_lights, o, d, tmin, &t, PS_U(ps, bounce) == 0u, -1);
              if (light >= 0) ps_set_hit(ps, t, 0.0f, 0.0f, AW_NONE, uint32_t(light));
              else ps_set_hit(ps, h.t, h.u, h.v, h.prim >= 0 ? uint32_t(h.prim) : AW_NONE, AW_NONE);
              next = classify_hit(ps, sc, &rp);
              if (next == AW_Q_PASS) next = AW_Q_RAY;  // cutout: the ray goes on through the surface
              continue;
            }
            if (next >= AW_Q_LOBE) {
              next = shade_surface(ps, sc, &rp, uint32_t(next - AW_Q_LOBE));
              if (PS_U(ps, flags) & AW_PATH_HAS_SHADOW) {
                ++n_shadow;
                float3 so = ps_shadow_origin(ps), sd = ps_shadow_dir(ps);
                float tmax = PS_F(ps, sh_tmax);
                bool occ;
                if (!cutouts) {
                  occ = escene.occluded(so, sd, 0.0f, tmax);
                } else {
                  // Same steps as intersect_shadow; Embree's t_near is inclusive, ours
                  // exclusive, hence the next float after the surface passed.
                  occ = false;
                  float t0 = 0.0f;
                  for (int k = 0; k < AW_SHADOW_CUTOUT_STEPS; ++k) {
                    EmbreeScene::Hit sh = escene.intersect(so, sd, k == 0 ? 0.0f : std::nextafter(t0, FLT_MAX), tmax);
                    if (sh.prim < 0) break;
                    if (!surface_is_cutout(sc, uint32_t(sh.prim)) || k == AW_SHADOW_CUTOUT_STEPS - 1) {
                      occ = true;
                      break;
                    }
                    t0 = sh.t;
                  }
                }
                if (!occ) {
                  float tl = tmax;
                  occ = lights_intersect(sc.lights, rp.num_lights, so, sd, 0.0f, &tl, 0, int(PS_U(ps, sh_light))) >= 0;
                }
                shade_shadow(ps, occ ? 1 : 0);
              }
              continue;
            }
            // DONE: what accumulate does.
            int bad = 0;
            l = path_result(ps, &rp, &bad);
            n_bad += uint64_t(bad);
            if ((PS_U(ps, flags) & AW_PATH_SPLIT) && split_next(ps, &rp, l, &l)) {
              next = int(AW_Q_LOBE + PS_U(ps, lobe));
              continue;
            }
            break;
          }
          // Same order and precision as film_accumulate: film + s0 + s1 + ...
          sum.x += l.x;
          sum.y += l.y;
          sum.z += l.z;
        }
        res.sum[pixel * 3 + 0] = sum.x;
        res.sum[pixel * 3 + 1] = sum.y;
        res.sum[pixel * 3 + 2] = sum.z;
        res.count[pixel] += spp;
      }
      progress.update(done_samples.fetch_add(uint64_t(base.width) * spp) + uint64_t(base.width) * spp);
    }
    closest += n_closest;
    shadow += n_shadow;
    bad_total += n_bad;
  };

  auto t_render = Clock::now();
  int threads = opts.threads > 0 ? opts.threads : int(std::max(1u, std::thread::hardware_concurrency()));
  std::vector<std::thread> pool;
  for (int i = 0; i < threads; ++i) pool.emplace_back(worker);
  for (auto& t : pool) t.join();
  progress.finish();
  st.stage_seconds.emplace_back("paths (all stages)", since(t_render));
  st.closest_rays = closest;
  st.shadow_rays = shadow;
  st.bad_samples = bad_total;
  st.samples = done_samples;
  st.interrupted = done_samples < uint64_t(npix) * spp;
  st.total_seconds = since(t_start);
  return res;
}

}  // namespace aw
