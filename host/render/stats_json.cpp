#include "host/render/stats_json.h"

#include <algorithm>
#include <fstream>

#include "host/film/image_io.h"

namespace aw {

nlohmann::json stats_to_json(const RenderResult& result, const Scene& scene) {
  const RenderStats& st = result.stats;
  nlohmann::json stages = nlohmann::json::array();
  for (size_t i = 0; i < st.stage_seconds.size(); ++i) {
    stages.push_back({{"name", st.stage_seconds[i].first},
                      {"seconds", st.stage_seconds[i].second},
                      {"items", i < st.stage_items.size() ? st.stage_items[i] : 0}});
  }
  return {
      {"renderer", st.renderer},
      {"device", st.device},
      {"device_choice", st.device_choice},
      {"kernel_features", st.kernel_features},
      {"lanes", st.lanes},
      {"scene", scene.path},
      {"width", result.width},
      {"height", result.height},
      {"spp", scene.render.spp},
      {"spp_completed", result.min_spp()},
      {"seed", scene.render.seed},
      {"samples", st.samples},
      {"total_seconds", st.total_seconds},
      {"compile_seconds", st.compile_seconds},
      {"kernel_build", st.kernel_build},
      {"bvh_seconds", st.bvh_seconds},
      {"setup_seconds", st.setup_seconds},
      {"render_seconds", st.path_seconds()},
      {"stages", stages},
      {"iterations", st.iterations},
      {"closest_rays", st.closest_rays},
      {"shadow_rays", st.shadow_rays},
      {"bad_samples", st.bad_samples},
      {"pool_size", st.pool_size},
      {"state_bytes", st.state_bytes},
      {"triangles", st.triangles},
      {"spheres", st.spheres},
      {"instances", st.instances},
      {"instanced_triangles", st.instanced_triangles},
      {"scene_bytes", st.scene_bytes},
      {"film_bytes", st.film_bytes},
      {"device_bytes", st.device_bytes},
      {"warnings", st.warnings},
      {"interrupted", st.interrupted},
      {"time_limited", st.time_limited},
      {"checkpoints", st.checkpoints},
      {"resumed_samples", st.resumed_samples},
      {"film_snapshots", st.film_snapshots},
      {"snapshot_seconds", st.snapshot_seconds},
      {"part", {{"pixel_bounds", {result.x0, result.x0 + result.width, result.y0, result.y0 + result.height}},
                {"frame", {result.frame_width, result.frame_height}},
                {"sample_range", {result.sample_start, result.sample_end}}}},
  };
}

void write_stats_json(const std::string& path, const RenderResult& result, const Scene& scene) {
  std::ofstream out(path);
  if (out) out << stats_to_json(result, scene).dump(2) << "\n";
  if (!out) throw OutputError("cannot write stats to \"" + path + "\"");
}

}  // namespace aw
