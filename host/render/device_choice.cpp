#include "host/render/device_choice.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "host/cl/kernel_cache.h"
#include "host/cl/kernel_source.h"
#include "host/film/image_io.h"
#include "host/render/render.h"
#include "host/scene/scene.h"

namespace aw {
namespace {

// The measurement's scene: the default scene (scenes/cornell.json) at 256x256 x 8 spp. Same
// features, so the kernels it builds are the ones the default render loads from the device's
// cache. Embedded so that the choice does not depend on where the binary runs from.
const char* kCalibrationScene = R"({
  "render": { "width": 256, "height": 256, "spp": 8, "seed": 0, "max_depth": 8 },
  "camera": { "position": [0, 1, 3.9], "look_at": [0, 1, 0], "up": [0, 1, 0], "fov": 37.5 },
  "environment": { "type": "constant", "color": [0, 0, 0] },
  "lights": [
    { "type": "quad", "corner": [-0.25, 1.995, -0.25], "edge_u": [0.5, 0, 0], "edge_v": [0, 0, 0.5],
      "color": [1, 0.85, 0.6], "intensity": 16 },
    { "type": "point", "position": [0.55, 1.55, 0.6], "color": [0.6, 0.7, 1.0], "intensity": 0.6 }
  ],
  "materials": {
    "white": { "diffuse": { "color": [0.73, 0.73, 0.73] }, "reflection": { "weight": 0 } },
    "red":   { "diffuse": { "color": [0.63, 0.065, 0.05] }, "reflection": { "weight": 0 } },
    "green": { "diffuse": { "color": [0.14, 0.45, 0.091] }, "reflection": { "weight": 0 } }
  },
  "objects": [
    { "shape": "quad", "corner": [-1, 0, 1], "edge_u": [2, 0, 0], "edge_v": [0, 0, -2], "material": "white" },
    { "shape": "quad", "corner": [-1, 2, -1], "edge_u": [2, 0, 0], "edge_v": [0, 0, 2], "material": "white" },
    { "shape": "quad", "corner": [-1, 0, -1], "edge_u": [2, 0, 0], "edge_v": [0, 2, 0], "material": "white" },
    { "shape": "quad", "corner": [-1, 0, 1], "edge_u": [0, 0, -2], "edge_v": [0, 2, 0], "material": "red" },
    { "shape": "quad", "corner": [1, 0, -1], "edge_u": [0, 0, 2], "edge_v": [0, 2, 0], "material": "green" },
    { "shape": "box", "min": [-0.3, 0, -0.3], "max": [0.3, 1.2, 0.3], "material": "white",
      "transform": { "rotate": [0, 17, 0], "translate": [-0.33, 0, -0.28] } },
    { "shape": "box", "min": [-0.3, 0, -0.3], "max": [0.3, 0.6, 0.3], "material": "white",
      "transform": { "rotate": [0, -17, 0], "translate": [0.33, 0, 0.3] } }
  ]
})";

std::string now_utc() {
  std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M UTC", std::gmtime(&t));
  return buf;
}

// The scene loader reads files, so the built-in scene goes through a private temporary one.
Scene calibration_scene(const std::vector<std::string>& overrides) {
  char path[] = "/tmp/archwave-calibration-XXXXXX";
  int fd = mkstemp(path);
  if (fd < 0) throw ClError("choosing a device: cannot create a temporary file in /tmp for the measurement scene");
  std::FILE* f = fdopen(fd, "w");
  std::fputs(kCalibrationScene, f);
  std::fclose(f);
  try {
    Scene s = load_scene(path, overrides);
    std::remove(path);
    return s;
  } catch (...) {
    std::remove(path);
    throw;
  }
}

const DeviceSpeed* find_speed(const std::vector<DeviceSpeed>& speeds, const DeviceInfo& d) {
  const std::string key = device_speed_key(d);
  for (const auto& s : speeds)
    if (s.key == key) return &s;
  return nullptr;
}

}  // namespace

// Best of 3 after a warm-up render that builds the kernels (what a render pays once per
// scene, not per sample).
double measure_device_speed(int index) {
  RenderOptions o;
  o.device = index;
  render_wavefront(calibration_scene({"render.width=16", "render.height=16", "render.spp=1"}), o);
  Scene scene = calibration_scene({});
  double best = 0.0;
  for (int run = 0; run < 3; ++run) {
    RenderResult r = render_wavefront(scene, o);
    double t = r.stats.path_seconds();
    if (t > 0) best = std::max(best, double(r.stats.samples) / t * 1e-6);
  }
  return best;
}

std::string kernel_source_hash(const std::string& kernel_dir) {
  return hex16(fnv1a64(assemble_kernel_source("integrator/kernels.cl", kernel_dir)));
}

std::string device_speed_key(const DeviceInfo& d) {
  // The kernels' own hash as well as the version: the figure measures the kernels, and a
  // change to them (a new build of the same version) can reorder the devices (2026-12-02:
  // three kernel changes made PoCL 15-20% faster and left Intel's runtime level).
  static const std::string kernels = kernel_source_hash("");
  return d.platform + " | " + d.name + " | " + d.version + " | " + d.driver + " | archwave " ARCHWAVE_VERSION +
         " | kernels " + kernels;
}

std::string default_device_cache_path() {
  if (const char* p = std::getenv("ARCHWAVE_DEVICE_CACHE"); p && *p) return p;
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return std::string(x) + "/archwave/device-speed.json";
  if (const char* h = std::getenv("HOME"); h && *h) return std::string(h) + "/.cache/archwave/device-speed.json";
  return "/tmp/archwave-device-speed.json";
}

std::vector<DeviceSpeed> read_device_cache(const std::string& path, std::ostream& log) {
  std::vector<DeviceSpeed> out;
  std::ifstream in(path);
  if (!in) return out;
  try {
    nlohmann::json j = nlohmann::json::parse(in);
    for (const auto& e : j.at("devices")) {
      DeviceSpeed s;
      s.key = e.at("key").get<std::string>();
      s.msamples_per_s = e.at("msamples_per_s").get<double>();
      s.error = e.value("error", "");
      s.measured = e.value("measured", "");
      out.push_back(s);
    }
  } catch (const std::exception& e) {
    log << "archwave: warning: the device-speed cache " << path << " cannot be read (" << e.what()
        << "); measuring the devices again\n";
    out.clear();
  }
  return out;
}

void write_device_cache(const std::string& path, const std::vector<DeviceSpeed>& speeds) {
  nlohmann::json devs = nlohmann::json::array();
  for (const auto& s : speeds)
    devs.push_back({{"key", s.key}, {"msamples_per_s", s.msamples_per_s}, {"error", s.error}, {"measured", s.measured}});
  nlohmann::json j = {{"about", "archwave's measured wavefront speed per OpenCL device, to choose the default device "
                                "(delete this file or run with --measure-devices to measure again)"},
                      {"devices", devs}};
  std::error_code ec;
  std::filesystem::create_directories(std::filesystem::path(path).parent_path(), ec);
  // Write then rename (film/image_io.h), so that two renders starting at once never read half a file.
  try {
    write_text_file("the device-speed cache", path, j.dump(2) + "\n");
  } catch (const OutputError& e) {
    throw ClError(std::string("choosing a device: ") + e.what() +
                  " (set $ARCHWAVE_DEVICE_CACHE to a writable file, or pass --device)");
  }
}

DeviceChoice choose_default_device(const std::string& cache_path, bool remeasure, std::ostream& log) {
  std::vector<DeviceInfo> devices = list_devices();
  if (const char* env = std::getenv("ARCHWAVE_DEVICE"); env && *env) {
    DeviceChoice c;
    c.index = resolve_device(env, devices, "ARCHWAVE_DEVICE=");
    c.how = std::string("$ARCHWAVE_DEVICE=") + env;
    return c;
  }
  if (devices.size() == 1) return {0, "the only OpenCL device"};

  std::vector<DeviceSpeed> cache = remeasure ? std::vector<DeviceSpeed>{} : read_device_cache(cache_path, log);
  std::vector<int> todo;
  for (const auto& d : devices)
    if (!find_speed(cache, d)) todo.push_back(d.index);
  if (!todo.empty()) {
    log << "archwave: measuring " << todo.size() << " OpenCL device" << (todo.size() > 1 ? "s" : "")
        << " once, to render on the fastest (a few seconds each; cached in " << cache_path
        << "; --device or $ARCHWAVE_DEVICE choose yourself)\n";
    for (int i : todo) {
      const DeviceInfo& d = devices[size_t(i)];
      DeviceSpeed s;
      s.key = device_speed_key(d);
      s.measured = now_utc();
      try {
        s.msamples_per_s = measure_device_speed(i);
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.3g", s.msamples_per_s);
        log << "archwave:   [" << i << "] " << d.name << " (" << d.platform << "): " << buf << " Msamples/s\n";
      } catch (const std::exception& e) {
        s.error = e.what();
        log << "archwave: warning: [" << i << "] " << d.name << " (" << d.platform
            << ") failed the measurement and is not chosen: " << e.what() << "\n";
      }
      cache.push_back(s);
    }
    // A cache that cannot be written costs the next render a measurement, not this render.
    try {
      write_device_cache(cache_path, cache);
    } catch (const ClError& e) {
      log << "archwave: warning: " << e.what() << "\n";
    }
  }

  return pick_fastest(devices, cache, cache_path);
}

DeviceChoice pick_fastest(const std::vector<DeviceInfo>& devices, const std::vector<DeviceSpeed>& speeds,
                          const std::string& cache_path) {
  int best = -1;
  double best_speed = 0.0;
  std::ostringstream all;
  for (const auto& d : devices) {
    const DeviceSpeed* s = find_speed(speeds, d);
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.3g", s ? s->msamples_per_s : 0.0);
    all << (&d == &devices.front() ? "" : ", ") << "[" << d.index << "] "
        << (!s ? "not measured" : s->error.empty() ? buf : "failed");
    if (s && s->error.empty() && s->msamples_per_s > best_speed) {
      best_speed = s->msamples_per_s;
      best = d.index;
    }
  }
  if (best < 0)
    throw ClError("no OpenCL device passed the measurement that chooses one (see " + cache_path +
                  "); pass --device to try one anyway:\n" + describe_devices(devices));
  DeviceChoice c;
  c.index = best;
  c.how = "the fastest of " + std::to_string(devices.size()) +
          " devices measured here (Msamples/s on the Cornell box: " + all.str() + "; " + cache_path + ")";
  return c;
}

}  // namespace aw
