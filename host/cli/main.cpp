// archwave: the command line.
//
// Exit codes (docs/cli.md): 0 success; 1 internal error; 2 bad command line; 3 scene error;
// 4 OpenCL/device error (a device failing mid-render writes its film so far first); 5 output
// cannot be written; 130 interrupted (what was rendered is written first).
#include <CLI/CLI.hpp>

#include <unistd.h>

#include <atomic>
#include <cctype>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "host/cl/cl_runtime.h"
#include "host/cl/kernel_source.h"
#include "host/film/image_io.h"
#include "host/film/progress.h"
#include "host/render/device_choice.h"
#include "host/render/film_state.h"
#include "host/render/render.h"
#include "host/render/stats_json.h"
#include "host/scene/export_obj.h"
#include "host/scene/scene.h"

namespace {

enum ExitCode { kOk = 0, kInternal = 1, kUsage = 2, kScene = 3, kDevice = 4, kOutput = 5, kInterrupted = 130 };

std::atomic<bool> g_cancel{false};

extern "C" void on_sigint(int) {
  // First ^C: finish the paths in flight and write what is done. Second: default action.
  g_cancel.store(true);
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
}

std::string default_output(const std::string& scene) {
  return std::filesystem::path(scene).stem().string() + ".exr";
}

// Fails before rendering, not after an hour of it, when the output cannot be written.
void check_output_writable(const std::string& path) {
  namespace fs = std::filesystem;
  fs::path dir = fs::path(path).parent_path();
  if (dir.empty()) dir = ".";
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw aw::OutputError("cannot write \"" + path + "\": directory \"" + dir.string() + "\" does not exist");
  if (::access(dir.c_str(), W_OK) != 0)
    throw aw::OutputError("cannot write \"" + path + "\": directory \"" + dir.string() + "\" is not writable");
}

}  // namespace

// "123", "500M", "8G", "1.5G" (powers of 1024) -> bytes; -1 for anything else.
static double parse_size(const std::string& s) {
  if (s.empty()) return -1;
  char* end = nullptr;
  double v = std::strtod(s.c_str(), &end);
  if (end == s.c_str() || !(v >= 0) || !std::isfinite(v)) return -1;
  std::string unit(end);
  for (char& c : unit) c = char(std::toupper(static_cast<unsigned char>(c)));
  if (unit == "B") unit.clear();
  if (!unit.empty() && unit.back() == 'B') unit.pop_back();  // "8GB" as "8G"
  if (unit == "K") v *= 1024.0;
  else if (unit == "M") v *= 1024.0 * 1024.0;
  else if (unit == "G") v *= 1024.0 * 1024.0 * 1024.0;
  else if (!unit.empty()) return -1;
  return v < 1.8e19 ? std::floor(v) : -1;
}

// Parses the command line: -1 to go on, else the exit code (0 after --help, kUsage on an error,
// which CLI11 has printed).
static int parse_command_line(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? kOk : kUsage;
  }
  return -1;
}

// The EXR and its PNG preview beside it. The EXR already holds radiance x exposure; the preview
// adds only the sRGB curve.
static void write_image(const std::string& output, const aw::Image& img) {
  aw::write_exr(output, img);
  aw::write_png_preview(aw::png_path_for(output), img, 1.0f);
}

// Inside a catch: prints the exception's message after `prog` and returns its exit code.
static int exit_code_for_exception(const char* prog) {
  try {
    throw;
  } catch (const aw::SceneError& e) {
    std::cerr << prog << ": " << e.what() << "\n";
    return kScene;
  } catch (const aw::ClError& e) {
    std::cerr << prog << ": " << e.what() << "\n";
    return kDevice;
  } catch (const aw::OutputError& e) {
    std::cerr << prog << ": " << e.what() << "\n";
    return kOutput;
  } catch (const std::exception& e) {
    std::cerr << prog << ": internal error: " << e.what() << "\n";
    return kInternal;
  } catch (...) {
    std::cerr << prog << ": internal error: an exception of unknown type\n";
    return kInternal;
  }
}

// "a,b,c,d" -> four numbers (false for anything else).
static bool parse_four(const std::string& s, double out[4]) {
  const char* p = s.c_str();
  for (int i = 0; i < 4; ++i) {
    char* end = nullptr;
    out[i] = std::strtod(p, &end);
    if (end == p || !std::isfinite(out[i])) return false;
    p = end;
    if (i < 3) {
      if (*p != ',') return false;
      ++p;
    }
  }
  return *p == '\0';
}

// `archwave merge PART.exr ... -o OUT.exr` (docs/production.md).
static int merge_main(int argc, char** argv) {
  CLI::App app{"archwave merge - combine the parts of one render (--sample-range, --pixel-bounds, --crop-window) into one "
               "image.\nParts over the same pixels add their samples; parts over other pixels are stitched. Exit codes: 0 ok, "
               "2 bad command line, 3 parts that do not belong together, 5 a file cannot be read or written."};
  std::vector<std::string> inputs;
  std::string output;
  bool quiet = false;
  app.add_option("parts", inputs, "EXR files archwave wrote with their film state")->required();
  app.add_option("-o,--output", output, "The merged EXR (with its film state; the PNG preview goes beside it)")->required();
  app.add_flag("-q,--quiet", quiet, "Only errors");
  if (int rc = parse_command_line(app, argc, argv); rc >= 0) return rc;
  try {
    check_output_writable(output);
    std::vector<aw::FilmState> parts;
    for (const std::string& in : inputs) parts.push_back(aw::read_film_state(in));
    std::string report;
    std::vector<std::string> warnings;
    bool resumable = true;
    aw::FilmState merged = aw::merge_films(parts, inputs, &report, &warnings, &resumable);
    for (const auto& w : warnings) std::cerr << "archwave merge: warning: " << w << "\n";
    write_image(output, aw::film_image(merged, resumable));
    if (!quiet) std::cerr << report << "\nwrote " << output << " and " << aw::png_path_for(output) << "\n";
    return kOk;
  } catch (...) {
    return exit_code_for_exception("archwave merge");
  }
}

int main(int argc, char** argv) {
  if (argc >= 2 && std::string(argv[1]) == "merge") return merge_main(argc - 1, argv + 1);
  CLI::App app{
      "archwave " ARCHWAVE_VERSION
      " - OpenCL wavefront path tracer with the Architectural material.\n"
      "Renders SCENE (JSON, see docs/scene-format.md) to a float EXR and a PNG preview.\n"
      "Flags override the scene file. Exit codes: 0 ok, 2 bad command line, 3 scene error,\n"
      "4 OpenCL/device error (a device failing mid-render writes the film so far first),\n"
      "5 output error, 130 interrupted (partial image written)."};
  app.set_version_flag("--version", ARCHWAVE_VERSION);
  std::string scene_path, output, stats_json;
  // Flags are kept as text and handed to the scene loader as overrides, so "--spp -1" or
  // "--width 0" is rejected with the same message as in a scene file.
  std::string spp, width, height, seed;
  std::string device;
  int threads = 0;
  bool scalar = false, list = false, quiet = false, no_progress = false, generic = false;
  std::vector<std::string> defines;
  std::string kernel_dir = aw::default_kernel_dir();
  unsigned pool = 0;
  double dense_fraction = -1.0;
  app.add_option("scene", scene_path, "Scene file (JSON)");
  app.add_option("-o,--output", output, "Output EXR (default: <scene name>.exr); the PNG preview goes beside it");
  app.add_option("--spp", spp, "Samples per pixel (overrides render.spp)");
  app.add_option("--seed", seed, "Random seed, 0..2^32-1 (overrides render.seed)");
  app.add_option("--width", width, "Image width in pixels (overrides render.width)");
  app.add_option("--height", height, "Image height in pixels (overrides render.height)");
  app.add_option("--device", device,
                 "OpenCL device: an index from --list-devices, or a case-insensitive part of its platform, name "
                 "or type that names one device, e.g. pocl, intel, gpu (default: $ARCHWAVE_DEVICE, else the fastest "
                 "device, measured once and cached: docs/devices.md)");
  app.add_flag("--scalar", scalar, "Render with the host scalar path (Embree rays, same kernel headers)");
  app.add_flag("--list-devices", list, "List OpenCL platforms and devices, then exit");
  bool measure_devices = false;
  app.add_flag("--measure-devices", measure_devices,
               "Measure every OpenCL device's speed again for the default choice (cached; docs/devices.md); "
               "without a scene, print the choice and exit");
  app.add_flag("--generic-kernels", generic,
               "Build the kernels with every material and light feature, instead of only those the scene uses "
               "(for comparison; the default specialised build gives the same image)");
  bool no_lanes = false;
  app.add_flag("--no-lanes", no_lanes,
               "Run every stage one path per work-item; by default a CPU device runs the stages written on "
               "lanes 16 paths per work-item where the scene allows (the same image bit for bit; docs/performance.md)");
  std::string lane_traversal = "auto";
  app.add_option("--lane-traversal", lane_traversal,
                 "With lanes, trace the ray stages' rays 16 per work-item too: auto (where measured to pay on "
                 "this device for a scene of this size; docs/performance.md), on (whenever the scene allows), off")
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->take_last();
  std::string narrow_lanes = "auto";
  app.add_option("--narrow-lanes", narrow_lanes,
                 "With lanes, paths per work-item of the ray stages and classification: auto (8 on Intel's CPU "
                 "runtime where a SIMD register holds 8 floats, AVX2; else 16; docs/performance.md), 8 or 16 "
                 "(the same image bit for bit)")
      ->check(CLI::IsMember({"auto", "8", "16"}))
      ->take_last();
  app.add_option("-D,--define", defines,
                 "Set any scene key, e.g. -D render.max_depth=4 -D materials.floor.diffuse.color=[1,0,0]")
      ->take_last()
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  app.add_option("--kernels", kernel_dir,
                 "Load kernel sources from this kernels/ directory instead of the embedded copy "
                 "(development; also $ARCHWAVE_KERNEL_DIR)");
  app.add_option("--pool", pool, "Path states in flight on the device (default 65536 on Intel's CPU runtime, 262144 on other CPU devices, 1048576 on a GPU, or $ARCHWAVE_POOL)");
  app.add_option("--dense-fraction", dense_fraction,
                 "Queues holding at least this share of the path pool are consumed in slot order, one "
                 "work-item per slot (default 0.25; 0 = always, above 1 = never; for measurement, the "
                 "image does not change)")
      ->check(CLI::Validator(
          [](std::string& v) -> std::string {
            char* end = nullptr;
            double d = std::strtod(v.c_str(), &end);
            if (end == v.c_str() || *end != '\0' || !(d >= 0.0))
              return "'" + v + "' is not a share of the pool (a number >= 0: 0 = always dense, above 1 = never)";
            return {};
          },
          "F >= 0"));
  app.add_option("--threads", threads, "Threads for --scalar (default: all cores)");
  app.add_flag("--no-progress", no_progress, "No progress line (it is also off when stderr is not a terminal)");
  app.add_flag("-q,--quiet", quiet, "No stats summary");
  std::string export_geometry;
  app.add_option("--export-geometry", export_geometry,
                 "Write the scene's triangles as archwave builds them (world space, an OBJ group per "
                 "object) to this file and exit without rendering");
  std::string max_memory;
  app.add_option("--max-memory", max_memory,
                 "Refuse a scene whose render would take more memory than SIZE (bytes, or with K, M, G: "
                 "e.g. 8G), estimated object by object before its geometry is generated (default: the "
                 "memory available now, MemAvailable; 0 = no limit)")
      ->check(CLI::Validator(
          [](std::string& v) -> std::string {
            return parse_size(v) >= 0 ? std::string() : "'" + v + "' is not a size (bytes, or a number with K, M or G)";
          },
          "SIZE"));
  std::string aovs;
  app.add_option("--aovs", aovs,
                 "AOVs written as layers of the EXR beside the beauty, comma-separated: albedo, normal, depth, position, "
                 "material_id, emission, ao, diffuse, translucency, reflection, refraction, or light_groups for the last "
                 "six (overrides render.aovs; docs/production.md#aovs)");
  std::string sample_range, crop_window, pixel_bounds, resume;
  double time_limit = 0.0, checkpoint = 0.0;
  bool save_state = false;
  auto positive_seconds = CLI::Validator(
      [](std::string& v) -> std::string {
        char* end = nullptr;
        double d = std::strtod(v.c_str(), &end);
        if (end == v.c_str() || *end != '\0' || !(d > 0.0) || !std::isfinite(d)) return "'" + v + "' is not a number of seconds > 0";
        return {};
      },
      "SECONDS > 0");
  app.add_option("--sample-range", sample_range,
                 "Render only the samples START:END (0 <= START < END <= spp) of every pixel: a part of the render for "
                 "'archwave merge' (docs/production.md)");
  app.add_option("--crop-window", crop_window,
                 "Render only the pixels x0,x1,y0,y1 given as fractions of the frame (as pbrt's: pixel bounds "
                 "ceil(width * x0) .. ceil(width * x1)); the EXR's data window places them in the frame");
  app.add_option("--pixel-bounds", pixel_bounds, "Render only the pixels [x0,x1) x [y0,y1) of the frame, given as x0,x1,y0,y1");
  app.add_option("--time-limit", time_limit,
                 "Stop once SECONDS have passed, at the end of the sample pass under way, and write the image with its "
                 "true sample count and its film state (resume it with --resume)")
      ->check(positive_seconds);
  app.add_option("--checkpoint", checkpoint,
                 "Write the image and its film state every SECONDS (atomically: a crash leaves the previous one)")
      ->check(positive_seconds);
  app.add_option("--resume", resume,
                 "Continue the film in this EXR (a checkpoint, a time-limited, interrupted or --save-state render) to the "
                 "requested spp; the result is bit for bit the uninterrupted render");
  app.add_flag("--save-state", save_state,
               "Write the film state into the EXR even for a complete render of the whole frame (to resume it later with "
               "more samples or merge it)");
  app.add_option("--stats-json", stats_json,
                 "Also write the render's stats (times, stages, rays, memory) as JSON to this file");
  if (int rc = parse_command_line(app, argc, argv); rc >= 0) return rc;

  try {
    if (list) {
      std::cout << aw::describe_devices(aw::list_devices());
      return kOk;
    }
    if (measure_devices && scene_path.empty()) {
      aw::DeviceChoice c = aw::choose_default_device(aw::default_device_cache_path(), true, std::cerr);
      std::cout << "default device: [" << c.index << "], " << c.how << "\n";
      return kOk;
    }
    if (scene_path.empty()) {
      std::cerr << "archwave: no scene given (try --help)\n";
      return kUsage;
    }
    // Flags become overrides so they are validated exactly like the scene's own keys.
    std::vector<std::string> overrides = defines;
    if (app.count("--spp")) overrides.push_back("render.spp=" + spp);
    if (app.count("--seed")) overrides.push_back("render.seed=" + seed);
    if (app.count("--width")) overrides.push_back("render.width=" + width);
    if (app.count("--height")) overrides.push_back("render.height=" + height);
    if (app.count("--aovs")) overrides.push_back("render.aovs=\"" + aovs + "\"");
    aw::LoadLimits limits;
    if (app.count("--max-memory")) {
      limits.max_bytes = uint64_t(parse_size(max_memory));
      limits.source = "--max-memory " + max_memory;
    } else {
      limits.max_bytes = aw::available_memory_bytes();
      limits.source = "the memory available now";
    }
    aw::Scene scene = aw::load_scene(scene_path, overrides, limits);
    if (!export_geometry.empty()) {
      const size_t triangles = aw::write_geometry_obj(scene, export_geometry);
      std::cerr << "wrote " << export_geometry << " (" << scene.meshes.size() << " meshes, " << scene.instances.size()
                << " instances expanded and " << scene.spheres.size() << " tessellated spheres, " << triangles
                << " triangles)\n";
      return kOk;
    }

    if (output.empty()) output = default_output(scene_path);
    check_output_writable(output);
    if (!stats_json.empty()) check_output_writable(stats_json);

    aw::RenderOptions opts;
    // Parts and resumption (docs/production.md).
    std::unique_ptr<aw::RenderResult> resume_film;
    if (!resume.empty()) {
      aw::FilmState f;
      try {
        f = aw::read_film_state(resume);
      } catch (const aw::OutputError& e) {
        throw aw::SceneError(std::string("--resume: ") + e.what());
      }
      const std::string why_not = "\"" + resume + "\" cannot be resumed with this scene: ";
      if (f.seed != scene.render.seed)
        throw aw::SceneError(why_not + "its seed is " + std::to_string(f.seed) + ", the scene's " + std::to_string(scene.render.seed));
      if (f.version != ARCHWAVE_VERSION)
        throw aw::SceneError(why_not + "it was rendered by archwave " + f.version + ", this is " ARCHWAVE_VERSION +
                             " (sample values may differ between versions)");
      const std::string renderer = scalar ? "scalar" : "wavefront";
      if (f.renderer != renderer)
        throw aw::SceneError(why_not + "it was rendered by the " + f.renderer + " renderer, this render uses the " + renderer +
                             (scalar ? "" : " (add --scalar)"));
      if (f.frame_width != scene.render.width || f.frame_height != scene.render.height)
        throw aw::SceneError(why_not + "its frame is " + std::to_string(f.frame_width) + "x" + std::to_string(f.frame_height) +
                             ", the scene's " + std::to_string(scene.render.width) + "x" + std::to_string(scene.render.height));
      opts.window = aw::PixelBounds{f.x0, f.x0 + f.width, f.y0, f.y0 + f.height};
      opts.sample_start = f.sample_start;
      // A part keeps its range; a whole render continues to the scene's (or --spp's) spp.
      opts.sample_end = f.sample_end == f.spp_requested ? uint32_t(scene.render.spp) : f.sample_end;
      resume_film = std::make_unique<aw::RenderResult>(aw::film_to_result(f));
      opts.resume = resume_film.get();
    }
    if (!sample_range.empty()) {
      unsigned a = 0, b = 0;
      char tail = 0;
      if (std::sscanf(sample_range.c_str(), "%u:%u%c", &a, &b, &tail) != 2 || sample_range[0] == '-' || !(a < b) ||
          b > unsigned(scene.render.spp))
        throw aw::SceneError("--sample-range " + sample_range + ": not START:END with 0 <= START < END <= spp (" +
                             std::to_string(scene.render.spp) + ")");
      if (opts.resume && (a != opts.sample_start || b < opts.sample_end))
        throw aw::SceneError("--sample-range " + sample_range + " is not the range of \"" + resume + "\" (" +
                             std::to_string(opts.sample_start) + ":" + std::to_string(opts.sample_end) + ")");
      opts.sample_start = a;
      opts.sample_end = b;
    }
    if (!crop_window.empty() && !pixel_bounds.empty()) throw aw::SceneError("give --crop-window or --pixel-bounds, not both");
    aw::PixelBounds window;
    if (!crop_window.empty()) {
      double c[4];
      if (!parse_four(crop_window, c) || !(0.0 <= c[0] && c[0] < c[1] && c[1] <= 1.0 && 0.0 <= c[2] && c[2] < c[3] && c[3] <= 1.0))
        throw aw::SceneError("--crop-window " + crop_window + ": not x0,x1,y0,y1 with 0 <= x0 < x1 <= 1 and 0 <= y0 < y1 <= 1");
      // pbrt's rule (pbrt-v4, Film's pixel bounds from the crop window): ceil at both ends,
      // so windows that share an edge share no pixel and miss none.
      const double w = scene.render.width, h = scene.render.height;
      window = aw::PixelBounds{int(std::ceil(w * c[0])), int(std::ceil(w * c[1])), int(std::ceil(h * c[2])), int(std::ceil(h * c[3]))};
      if (window.empty()) throw aw::SceneError("--crop-window " + crop_window + " holds no pixel of the " +
                                              std::to_string(scene.render.width) + "x" + std::to_string(scene.render.height) + " frame");
    } else if (!pixel_bounds.empty()) {
      double c[4];
      if (!parse_four(pixel_bounds, c) || c[0] != std::floor(c[0]) || c[1] != std::floor(c[1]) || c[2] != std::floor(c[2]) ||
          c[3] != std::floor(c[3]) || !(0 <= c[0] && c[0] < c[1] && c[1] <= scene.render.width && 0 <= c[2] && c[2] < c[3] &&
                                        c[3] <= scene.render.height))
        throw aw::SceneError("--pixel-bounds " + pixel_bounds + ": not whole pixels x0,x1,y0,y1 with 0 <= x0 < x1 <= " +
                             std::to_string(scene.render.width) + " and 0 <= y0 < y1 <= " + std::to_string(scene.render.height));
      window = aw::PixelBounds{int(c[0]), int(c[1]), int(c[2]), int(c[3])};
    }
    if (!window.empty()) {
      if (opts.resume && (window.x0 != opts.window.x0 || window.x1 != opts.window.x1 || window.y0 != opts.window.y0 ||
                          window.y1 != opts.window.y1))
        throw aw::SceneError("the pixel bounds asked for are not those of \"" + resume + "\"");
      opts.window = window;
    }
    const bool whole_frame = opts.window.empty() || (opts.window.x0 == 0 && opts.window.y0 == 0 &&
                                                     opts.window.x1 == scene.render.width && opts.window.y1 == scene.render.height);
    const bool a_part = !whole_frame || opts.sample_start != 0 ||
                        (opts.sample_end != 0 && opts.sample_end != uint32_t(scene.render.spp));
    // The film state goes into the EXR whenever the image is, or may become, part of more.
    const bool with_state = save_state || a_part || checkpoint > 0.0 || time_limit > 0.0 || opts.resume;
    if (a_part) {
      opts.progress_label = "rendering part";
      if (!whole_frame)
        opts.progress_label += " " + std::to_string(opts.window.x0) + "," + std::to_string(opts.window.x1) + "," +
                               std::to_string(opts.window.y0) + "," + std::to_string(opts.window.y1);
      if (opts.sample_start != 0 || opts.sample_end != 0)
        opts.progress_label += " samples " + std::to_string(opts.sample_start) + ":" +
                               std::to_string(opts.sample_end ? opts.sample_end : uint32_t(scene.render.spp));
    }
    opts.time_limit = time_limit;
    opts.checkpoint_seconds = checkpoint;
    if (checkpoint > 0.0)
      opts.checkpoint = [&](const aw::RenderResult& partial) {
        aw::Image img = partial.image(scene, true);
        img.string_attrs["archwave:checkpoint"] = "yes";
        write_image(output, img);
      };
    std::string device_choice;
    if (!scalar && !device.empty()) {
      opts.device = aw::resolve_device(device, aw::list_devices());
      device_choice = "--device " + device;
    } else if (!scalar) {
      aw::DeviceChoice c = aw::choose_default_device(aw::default_device_cache_path(), measure_devices, std::cerr);
      opts.device = c.index;
      device_choice = c.how;
    }
    opts.pool_size = pool;
    opts.dense_fraction = dense_fraction;
    opts.generic_kernels = generic;
    opts.lanes = !no_lanes;
    opts.lane_traversal = lane_traversal == "on" ? 1 : lane_traversal == "off" ? 0 : -1;
    opts.narrow_lanes = narrow_lanes == "auto" ? 0 : std::stoi(narrow_lanes);
    opts.threads = threads;
    opts.kernel_dir = kernel_dir;
    opts.progress = !no_progress && aw::stderr_is_terminal();
    opts.cancel = &g_cancel;
    std::signal(SIGINT, on_sigint);
    std::signal(SIGTERM, on_sigint);

    aw::RenderResult r;
    try {
      r = scalar ? aw::render_scalar(scene, opts) : aw::render_wavefront(scene, opts);
    } catch (const aw::RenderDeviceError& e) {
      // The device failed mid-render: write what it had, with the film state, so that the
      // render resumes from it (on this device or another), then fail as a device error.
      std::cerr << "archwave: " << e.what() << "\n";
      if (!e.partial) return kDevice;
      aw::Image img = e.partial->image(scene, true);
      img.string_attrs["archwave:device_error"] = e.what();
      write_image(output, img);
      std::cerr << "archwave: wrote " << output << " with the samples completed before the error (" << e.partial->min_spp()
                << " spp in every pixel); resume with --resume " << output << "\n";
      return kDevice;
    }
    r.stats.device_choice = device_choice;
    for (const auto& w : r.stats.warnings) std::cerr << "archwave: warning: " << w << "\n";
    aw::Image img = r.image(scene, with_state || r.stats.interrupted);
    write_image(output, img);
    const std::string png = aw::png_path_for(output);
    if (!stats_json.empty()) aw::write_stats_json(stats_json, r, scene);
    if (!quiet) std::cerr << r.stats.summary();
    std::cerr << "wrote " << output << " and " << png << " (" << r.min_spp() << " spp";
    if (a_part) std::cerr << " of the samples " << r.sample_start << ":" << r.sample_end;
    std::cerr << ")\n";
    if (r.stats.time_limited)
      std::cerr << "archwave: time limit reached; resume with --resume " << output << "\n";
    if (r.stats.interrupted) {
      std::cerr << "archwave: interrupted; the image holds the samples completed so far\n";
      return kInterrupted;
    }
    return kOk;
  } catch (...) {
    return exit_code_for_exception("archwave");
  }
}
