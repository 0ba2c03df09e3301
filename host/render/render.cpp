#include "host/render/render.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "host/cl/cl_runtime.h"
#include "host/film/progress.h"
#include "host/render/film_state.h"
#include "kernels/integrator/aov.h"
#include "kernels/integrator/film.h"

namespace aw {

uint32_t RenderResult::min_spp() const {
  if (count.empty()) return 0;
  return *std::min_element(count.begin(), count.end());
}

void RenderResult::update_sums() {
  sum.resize(count.size() * 3);
  for (size_t i = 0; i < sum.size(); ++i) sum[i] = float(film_word_value(&acc[i * 2]));
}

Image RenderResult::image(const Scene& scene, bool with_state) const {
  FilmState f = film_state(*this, scene);
  return film_image(f, with_state);
}

uint32_t begin_film(const Scene& scene, const RenderOptions& opts, const PackedScene& packed, RenderParams& rp,
                    RenderResult& res) {
  const int fw = int(rp.width), fh = int(rp.height);
  PixelBounds win = opts.window;
  if (win.empty()) {
    if (win.x0 != 0 || win.x1 != 0 || win.y0 != 0 || win.y1 != 0)
      throw SceneError("pixel bounds " + std::to_string(win.x0) + "," + std::to_string(win.x1) + "," + std::to_string(win.y0) +
                       "," + std::to_string(win.y1) + " hold no pixel (x0 < x1 and y0 < y1 are needed)");
    win = PixelBounds{0, fw, 0, fh};
  }
  if (win.x0 < 0 || win.y0 < 0 || win.x1 > fw || win.y1 > fh)
    throw SceneError("pixel bounds " + std::to_string(win.x0) + "," + std::to_string(win.x1) + "," + std::to_string(win.y0) +
                     "," + std::to_string(win.y1) + " are not inside the " + std::to_string(fw) + "x" + std::to_string(fh) +
                     " frame");
  const uint32_t spp = uint32_t(scene.render.spp);
  const uint32_t start = opts.sample_start, end = opts.sample_end ? opts.sample_end : spp;
  if (!(start < end) || end > spp)
    throw SceneError("sample range " + std::to_string(start) + ":" + std::to_string(end) +
                     " is not a non-empty part of the render's " + std::to_string(spp) + " samples (0 <= START < END <= spp)");
  res.frame_width = fw;
  res.frame_height = fh;
  res.x0 = win.x0;
  res.y0 = win.y0;
  res.width = win.x1 - win.x0;
  res.height = win.y1 - win.y0;
  res.sample_start = start;
  res.sample_end = end;
  res.scene_hash = scene_identity(packed);
  const size_t npix = size_t(res.width) * size_t(res.height);
  rp.win_x0 = uint32_t(win.x0);
  rp.win_y0 = uint32_t(win.y0);
  rp.win_w = uint32_t(res.width);
  rp.win_h = uint32_t(res.height);
  rp.sample_start = start;
  uint32_t first = start;
  if (const RenderResult* r = opts.resume) {
    auto bounds = [](const RenderResult& x) {
      return std::to_string(x.x0) + "," + std::to_string(x.x0 + x.width) + "," + std::to_string(x.y0) + "," +
             std::to_string(x.y0 + x.height) + " of " + std::to_string(x.frame_width) + "x" + std::to_string(x.frame_height);
    };
    if (r->scene_hash != res.scene_hash)
      throw SceneError("the film to resume was rendered from another scene (its scene hash differs: a material, light, mesh, "
                       "camera, seed, depth or sampler setting is not the same)");
    if (r->frame_width != fw || r->frame_height != fh || r->x0 != res.x0 || r->y0 != res.y0 || r->width != res.width ||
        r->height != res.height)
      throw SceneError("the film to resume covers pixels " + bounds(*r) + ", this render " + bounds(res));
    if (r->sample_start != start)
      throw SceneError("the film to resume starts at sample " + std::to_string(r->sample_start) + ", this render at " +
                       std::to_string(start));
    if (r->acc.size() != npix * AW_FILM_WORDS || r->count.size() != npix)
      throw SceneError("the film to resume does not hold one film value per pixel");
    if (r->aov_mask != rp.aov_mask)
      throw SceneError("the film to resume holds the AOVs \"" + aov_mask_names(r->aov_mask) + "\", this render asks for \"" +
                       aov_mask_names(rp.aov_mask) + "\"");
    res.acc = r->acc;
    res.count = r->count;
    res.aov_mask = r->aov_mask;
    res.aov_acc = r->aov_acc;
    uint32_t lo = UINT32_MAX;
    for (uint32_t c : res.count) {
      lo = std::min(lo, c);
      res.stats.resumed_samples += c;
      if (c > end - start)
        throw SceneError("the film to resume holds " + std::to_string(c) + " samples in a pixel, more than the " +
                         std::to_string(end - start) + " this render asks for");
    }
    first = start + lo;
  } else {
    res.acc.assign(npix * AW_FILM_WORDS, 0ull);
    res.count.assign(npix, 0u);
    res.aov_mask = rp.aov_mask;
    res.aov_acc.assign(npix * aov_film_channels(rp.aov_mask) * 2, 0ull);
  }
  return first;
}

double RenderStats::path_seconds() const {
  return std::max(0.0, total_seconds - compile_seconds - bvh_seconds - setup_seconds);
}

std::string RenderStats::summary() const {
  std::ostringstream s;
  char buf[256];
  s << "renderer        " << renderer << " on " << device << "\n";
  if (!device_choice.empty()) s << "device choice   " << device_choice << "\n";
  if (!kernel_features.empty()) s << "kernels         " << kernel_features << "\n";
  if (!lanes.empty()) s << "lanes           " << lanes << "\n";
  std::snprintf(buf, sizeof buf, "time            %.3f s total (BVH %.3f s, kernel build %.3f s%s%s, setup %.3f s)\n",
                total_seconds, bvh_seconds, compile_seconds, kernel_build.empty() ? "" : ": ", kernel_build.c_str(),
                setup_seconds);
  s << buf;
  double traced = 0.0;
  for (const auto& st : stage_seconds) traced += st.second;
  for (size_t i = 0; i < stage_seconds.size(); ++i) {
    const auto& st = stage_seconds[i];
    std::snprintf(buf, sizeof buf, "  %-22s %9.3f s  %5.1f%%", st.first.c_str(), st.second,
                  traced > 0 ? 100.0 * st.second / traced : 0.0);
    s << buf;
    if (i < stage_items.size() && st.second > 0.0) {
      std::snprintf(buf, sizeof buf, "  %10llu items  %8.2f M/s", (unsigned long long)stage_items[i],
                    double(stage_items[i]) / st.second * 1e-6);
      s << buf;
    }
    s << "\n";
  }
  double secs = std::max(1e-9, path_seconds());
  std::snprintf(buf, sizeof buf, "rays            %llu closest + %llu shadow = %.3f Mrays/s\n",
                (unsigned long long)closest_rays, (unsigned long long)shadow_rays,
                double(closest_rays + shadow_rays) / secs * 1e-6);
  s << buf;
  std::snprintf(buf, sizeof buf, "samples         %llu (%.3f Msamples/s), %llu wavefront iterations\n",
                (unsigned long long)samples, double(samples) / secs * 1e-6, (unsigned long long)iterations);
  s << buf;
  std::snprintf(buf, sizeof buf, "NaN/Inf samples %llu discarded\n", (unsigned long long)bad_samples);
  s << buf;
  if (state_bytes) s << "path pool       " << format_bytes(state_bytes) << "\n";
  if (scene_bytes) {
    s << "memory          scene " << format_bytes(scene_bytes) << " (" << triangles << " triangles";
    if (spheres > 0) s << ", " << spheres << " spheres";
    if (instances > 0) s << ", " << instances << " instances of shared meshes, " << instanced_triangles << " triangles rendered";
    s << ")";
    if (film_bytes) s << ", film " << format_bytes(film_bytes);
    if (device_bytes) s << ", all device buffers " << format_bytes(device_bytes);
    s << "\n";
  }
  if (resumed_samples) s << "resumed         from a film holding " << resumed_samples << " samples\n";
  if (checkpoints) s << "checkpoints     " << checkpoints << " written\n";
  if (film_snapshots) {
    std::snprintf(buf, sizeof buf, "film snapshots  %u (%.3f s), kept for a device failing mid-render\n", film_snapshots,
                  snapshot_seconds);
    s << buf;
  }
  if (time_limited) s << "TIME LIMIT      stopped at a whole sample pass; the image holds every sample until then\n";
  if (interrupted) s << "INTERRUPTED     the image holds the samples completed before the interrupt\n";
  return s.str();
}

}  // namespace aw
