// bench_render [SCENE.json] [--spp N] [--width W --height H] [--device I|NAME] [--out FILE]
// (default device: pocl, the device the measured tables are defined on)
// End-to-end throughput of the two renderers on the same scene, side by side in one run:
// samples/s and rays/s of the wavefront (OpenCL) and of the host scalar path (Embree rays,
// all cores), plus the wavefront's per-stage time breakdown. Kernel compilation is excluded
// (a warm-up render fills PoCL's cache first) and reported separately.
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "host/render/render.h"
#include "host/scene/scene.h"

namespace {

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown CPU";
}

}  // namespace

int main(int argc, char** argv) {
  std::string scene_path = std::string(ARCHWAVE_SOURCE_DIR) + "/scenes/cornell.json";
  std::string spp = "32", width = "400", height = "400", out;
  std::string device = "pocl";  // an index or a name, as archwave --device takes them
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto next = [&]() -> std::string { return i + 1 < argc ? argv[++i] : ""; };
    if (a == "--spp") spp = next();
    else if (a == "--width") width = next();
    else if (a == "--height") height = next();
    else if (a == "--device") device = next();
    else if (a == "--out") out = next();
    else scene_path = a;
  }
  try {
    aw::Scene scene = aw::load_scene(scene_path, {"render.spp=" + spp, "render.width=" + width, "render.height=" + height});
    aw::RenderOptions o;
    o.device = aw::resolve_device(device, aw::list_devices());
    aw::Scene warm = aw::load_scene(scene_path, {"render.spp=1", "render.width=16", "render.height=16"});
    aw::RenderResult w0 = aw::render_wavefront(warm, o);  // compile (or load from cache)
    aw::RenderResult w = aw::render_wavefront(scene, o);
    aw::RenderResult s = aw::render_scalar(scene, o);
    double tw = w.stats.path_seconds(), ts = s.stats.path_seconds();
    std::ostringstream t;
    t << "Scene `" << scene_path.substr(scene_path.find_last_of('/') + 1) << "`, " << width << "x" << height << ", "
      << spp << " spp. Machine: " << cpu_model() << ", " << std::thread::hardware_concurrency()
      << " hardware threads. Device: " << w.stats.device << ". Kernel build (cold or cached): "
      << w0.stats.compile_seconds << " s.\n\n";
    t << "| renderer | time (s) | Msamples/s | Mrays/s (closest + shadow) | ratio to scalar |\n|---|---|---|---|---|\n";
    char buf[256];
    auto row = [&](const char* name, const aw::RenderResult& r, double secs) {
      std::snprintf(buf, sizeof buf, "| %s | %.3f | %.3f | %.2f | %.2f |\n", name, secs,
                    double(r.stats.samples) / secs * 1e-6,
                    double(r.stats.closest_rays + r.stats.shadow_rays) / secs * 1e-6, ts / secs);
      t << buf;
    };
    row("wavefront (OpenCL)", w, tw);
    row("scalar (host, Embree)", s, ts);
    t << "\nWavefront stages (one shading kernel per lobe; items = paths, pixels for film_accumulate):\n\n"
         "| stage | time (s) | share | items | M items/s |\n|---|---|---|---|---|\n";
    double sum = 0.0;
    for (auto& st : w.stats.stage_seconds) sum += st.second;
    for (size_t i = 0; i < w.stats.stage_seconds.size(); ++i) {
      const auto& st = w.stats.stage_seconds[i];
      uint64_t items = i < w.stats.stage_items.size() ? w.stats.stage_items[i] : 0;
      std::snprintf(buf, sizeof buf, "| %s | %.3f | %.1f%% | %llu | %.2f |\n", st.first.c_str(), st.second,
                    100.0 * st.second / sum, (unsigned long long)items, double(items) / st.second * 1e-6);
      t << buf;
    }
    std::snprintf(buf, sizeof buf, "\nPath pool: %.1f MiB (%zu bytes per path state).\n",
                  double(w.stats.state_bytes) / (1 << 20), w.stats.state_bytes / std::max<size_t>(1, w.stats.pool_size));
    t << buf;
    std::fputs(t.str().c_str(), stdout);
    if (!out.empty()) std::ofstream(out) << t.str();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_render: %s\n", e.what());
    return 1;
  }
  return 0;
}
