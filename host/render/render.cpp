#include "host/render/render.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "host/cl/cl_runtime.h"
#include "host/film/progress.h"

namespace aw {

uint32_t RenderResult::min_spp() const {
  if (count.empty()) return 0;
  return *std::min_element(count.begin(), count.end());
}

Image RenderResult::image(const Scene& scene) const {
  Image img;
  img.width = width;
  img.height = height;
  img.rgb.resize(sum.size());
  for (size_t p = 0; p < count.size(); ++p) {
    float inv = count[p] ? 1.0f / float(count[p]) : 0.0f;
    for (int c = 0; c < 3; ++c) img.rgb[p * 3 + c] = sum[p * 3 + c] * inv;
  }
  // Exposure is applied here so the EXR holds exposed radiance (docs/scene-format.md,
  // camera.exposure): x k, and in photographic mode white balance and vignetting.
  apply_exposure(scene.camera, width, height, img.rgb.data());
  img.int_attrs["spp"] = int(min_spp());
  img.int_attrs["spp_requested"] = scene.render.spp;
  img.int_attrs["seed"] = int(scene.render.seed);
  img.int_attrs["max_depth"] = scene.render.max_depth;
  img.string_attrs["archwave:version"] = ARCHWAVE_VERSION;
  img.string_attrs["archwave:renderer"] = stats.renderer;
  img.string_attrs["archwave:device"] = stats.device;
  img.string_attrs["archwave:scene"] = scene.path;
  if (stats.interrupted) img.string_attrs["archwave:interrupted"] = "yes";
  return img;
}

std::string RenderStats::summary() const {
  std::ostringstream s;
  char buf[256];
  s << "renderer        " << renderer << " on " << device << "\n";
  if (!device_choice.empty()) s << "device choice   " << device_choice << "\n";
  if (!kernel_features.empty()) s << "kernels         " << kernel_features << "\n";
  std::snprintf(buf, sizeof buf, "time            %.3f s total (BVH %.3f s, kernel build %.3f s%s%s)\n",
                total_seconds, bvh_seconds, compile_seconds, kernel_build.empty() ? "" : ": ", kernel_build.c_str());
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
  double secs = std::max(1e-9, total_seconds - compile_seconds - bvh_seconds);
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
  if (interrupted) s << "INTERRUPTED     the image holds the samples completed before the interrupt\n";
  return s.str();
}

}  // namespace aw
