// The command line as a user meets it: exit codes, messages, nothing written on error, and an
// interrupted render that keeps what it has. Runs the real binary.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "host/film/image_io.h"
#include "host/render/film_state.h"

namespace fs = std::filesystem;

namespace {

std::string src(const std::string& rel) { return std::string(ARCHWAVE_SOURCE_DIR) + "/" + rel; }

// ctest runs each test as its own process, several at once: every file a test writes lives
// in a directory of its own process.
std::string scratch() {
  static const std::string dir = [] {
    std::string d = testing::TempDir() + "/archwave_cli_" + std::to_string(getpid());
    fs::create_directories(d);
    return d;
  }();
  return dir;
}

struct CliRun {
  int code;
  std::string err;
};

// Runs archwave with `args`, capturing stderr; returns the exit code.
// `env`: assignments put before the command ("NAME=value ...").
CliRun run(const std::string& args, const std::string& env = "") {
  std::string errfile = scratch() + "/archwave_stderr.txt";
  std::string cmd = (env.empty() ? "" : env + " ") + std::string(ARCHWAVE_BINARY) + " " + args + " 2>" + errfile + " >/dev/null";
  int status = std::system(cmd.c_str());
  std::ifstream in(errfile);
  std::string err((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, err};
}

std::string write_scene(const std::string& name, const std::string& json) {
  std::string dir = scratch() + "/cli_scenes";
  fs::create_directories(dir);
  std::string p = dir + "/" + name;
  std::ofstream(p) << json;
  return p;
}

const char* kMinimal = R"({
  "render": { "width": 8, "height": 8, "spp": 1 },
  "materials": { "m": { "diffuse": { "color": [0.5, 0.5, 0.5] } } },
  "objects": [ { "shape": "sphere", "center": [0, 1, 0], "radius": 0.5, "material": "m" } ]
})";

struct BadCase {
  const char* name;
  const char* json;
  const char* fragment;  // must appear in the message
};

// One malformed scene per kind of mistake; each must fail with exit code 3, name the file and
// position, and write nothing.
const BadCase kBad[] = {
    {"bad_json.json", "{\n  \"render\": { \"width\": 8,, }\n}", "bad_json.json:2:"},
    {"wrong_type.json", "{\n  \"render\": { \"spp\": \"many\" }\n}", "render.spp"},
    {"unknown_key.json", "{\n  \"render\": { \"sppp\": 4 }\n}", "sppp"},
    {"unknown_material_key.json",
     "{\n \"materials\": { \"m\": { \"diffuse\": { \"colour\": [1,1,1] } } }\n}", "materials.m.diffuse.colour"},
    {"missing_mesh.json",
     "{\n \"materials\": { \"m\": {} },\n \"objects\": [ { \"shape\": \"mesh\", \"file\": \"nope/missing.obj\", "
     "\"material\": \"m\" } ]\n}",
     "nope/missing.obj"},
    {"unknown_material.json",
     "{\n \"materials\": { \"m\": {} },\n \"objects\": [ { \"shape\": \"sphere\", \"material\": \"glass\" } ]\n}",
     "glass"},
    {"zero_size.json", "{\n  \"render\": { \"width\": 0 }\n}", "render.width"},
    {"negative_spp.json", "{\n  \"render\": { \"spp\": -4 }\n}", "render.spp"},
};

TEST(CliBadInput, EachMalformedSceneFailsWithItsMessageAndWritesNothing) {
  for (const BadCase& c : kBad) {
    std::string scene = write_scene(c.name, c.json);
    std::string out = scratch() + "/should_not_exist.exr";
    fs::remove(out);
    CliRun r = run(scene + " -o " + out);
    EXPECT_EQ(r.code, 3) << c.name << ": " << r.err;
    EXPECT_NE(r.err.find(c.fragment), std::string::npos) << c.name << ": message was: " << r.err;
    EXPECT_NE(r.err.find(c.name), std::string::npos) << c.name << ": message does not name the file: " << r.err;
    EXPECT_FALSE(fs::exists(out)) << c.name;
    EXPECT_FALSE(fs::exists(fs::path(out).replace_extension(".png"))) << c.name;
  }
}

TEST(CliBadInput, MissingSceneFileNamesThePath) {
  CliRun r = run(src("scenes/does_not_exist.json") + " -o " + scratch() + "/x.exr");
  EXPECT_EQ(r.code, 3);
  EXPECT_NE(r.err.find("does_not_exist.json"), std::string::npos) << r.err;
}

TEST(CliBadInput, FlagsAreValidatedLikeSceneKeys) {
  std::string scene = write_scene("ok.json", kMinimal);
  for (const char* flags : {"--spp -1", "--spp 0", "--width 0", "--height -3", "--spp many", "-D render.gi=7"}) {
    CliRun r = run(scene + " -o " + scratch() + "/x.exr " + flags);
    EXPECT_EQ(r.code, 3) << flags << ": " << r.err;
    EXPECT_NE(r.err.find("command line"), std::string::npos) << flags << ": " << r.err;
  }
}

TEST(CliBadInput, UnknownFlagIsAUsageError) {
  CliRun r = run("--no-such-flag");
  EXPECT_EQ(r.code, 2) << r.err;
}

TEST(CliBadInput, BadDenseFractionIsAUsageErrorNamingTheFlag) {
  std::string scene = write_scene("ok.json", kMinimal);
  for (const char* value : {"-1", "half"}) {
    CliRun r = run(scene + " -o " + scratch() + "/x.exr --dense-fraction " + value);
    EXPECT_EQ(r.code, 2) << value << ": " << r.err;
    EXPECT_NE(r.err.find("--dense-fraction"), std::string::npos) << value << ": " << r.err;
  }
}

TEST(CliBadInput, BadNarrowLanesIsAUsageErrorNamingTheFlag) {
  std::string scene = write_scene("ok.json", kMinimal);
  for (const char* value : {"4", "32", "wide"}) {
    CliRun r = run(scene + " -o " + scratch() + "/x.exr --narrow-lanes " + value);
    EXPECT_EQ(r.code, 2) << value << ": " << r.err;
    EXPECT_NE(r.err.find("--narrow-lanes"), std::string::npos) << value << ": " << r.err;
  }
}

TEST(CliBadInput, BadDeviceIndexListsDevices) {
  std::string scene = write_scene("ok.json", kMinimal);
  CliRun r = run(scene + " --device 99 -o " + scratch() + "/x.exr");
  EXPECT_EQ(r.code, 4) << r.err;
  EXPECT_NE(r.err.find("--device 99"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("[0]"), std::string::npos) << "the message should list the devices: " << r.err;
}

TEST(CliBadInput, UnknownDeviceNameListsDevices) {
  std::string scene = write_scene("ok.json", kMinimal);
  CliRun r = run(scene + " --device no-such-device -o " + scratch() + "/x.exr");
  EXPECT_EQ(r.code, 4) << r.err;
  EXPECT_NE(r.err.find("no-such-device"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("[0]"), std::string::npos) << "the message should list the devices: " << r.err;
}

// PoCL is the device the suite is defined on: it can be named.
TEST(Cli, DeviceByName) {
  std::string scene = write_scene("ok.json", kMinimal);
  CliRun r = run(scene + " --device pocl -o " + scratch() + "/byname.exr");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("Portable Computing Language"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("device choice   --device pocl\n"), std::string::npos) << r.err;
}

// With no --device the stats say which rule chose the device: here the suite's $ARCHWAVE_DEVICE
// (the measured choice is tested in tests/render/test_device_choice.cpp).
TEST(Cli, StatsSayWhyThisDevice) {
  std::string scene = write_scene("ok.json", kMinimal);
  CliRun r = run(scene + " -o " + scratch() + "/why.exr");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("device choice   $ARCHWAVE_DEVICE=pocl\n"), std::string::npos) << r.err;
  CliRun m = run("--measure-devices");
  EXPECT_EQ(m.code, 0) << m.err;
}

TEST(CliBadInput, UnwritableOutputFailsBeforeRendering) {
  std::string scene = write_scene("ok.json", kMinimal);
  CliRun r = run(scene + " -o /nonexistent_dir_archwave/x.exr");
  EXPECT_EQ(r.code, 5) << r.err;
  EXPECT_NE(r.err.find("/nonexistent_dir_archwave"), std::string::npos) << r.err;
}

TEST(Cli, HelpDocumentsEveryFlag) {
  std::string out = scratch() + "/help.txt";
  int status = std::system((std::string(ARCHWAVE_BINARY) + " --help >" + out).c_str());
  EXPECT_EQ(WEXITSTATUS(status), 0);
  std::ifstream in(out);
  std::string help((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const char* flag : {"--output", "--spp", "--seed", "--width", "--height", "--device", "--scalar",
                           "--list-devices", "--define", "--kernels", "--pool", "--quiet", "--generic-kernels",
                           "--stats-json", "--dense-fraction", "--measure-devices", "--no-lanes", "--lane-traversal",
                           "--narrow-lanes"})
    EXPECT_NE(help.find(flag), std::string::npos) << flag;
}

TEST(Cli, ListDevicesShowsPoCL) {
  CliRun r = run("--list-devices");
  EXPECT_EQ(r.code, 0);
}

TEST(Cli, RenderWritesExrAndPngWithHeader) {
  std::string scene = write_scene("ok.json", kMinimal);
  std::string out = scratch() + "/ok.exr";
  CliRun r = run(scene + " --spp 2 --seed 5 -o " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(scratch() + "/ok.png"));
  aw::Image img = aw::read_exr(out);
  EXPECT_EQ(img.width, 8);
  EXPECT_EQ(img.int_attrs["spp"], 2);
  EXPECT_EQ(img.int_attrs["seed"], 5);
  // The stats summary is printed (stage times, rays, NaN count).
  EXPECT_NE(r.err.find("Mrays/s"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("NaN/Inf samples"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("intersect_closest"), std::string::npos) << r.err;
  // Not a terminal: no progress line (no carriage returns).
  EXPECT_EQ(r.err.find('\r'), std::string::npos);
}

// --stats-json: the stats the benchmark suite reads, for both renderers, with values that
// hang together (times add up, buffers hold at least what they must, rays >= samples).
TEST(Cli, StatsJsonHoldsTheRenderStats) {
  std::string scene = write_scene("ok.json", kMinimal);
  auto render = [&](const std::string& name, const std::string& flags) {
    std::string json = scratch() + "/" + name + ".json";
    fs::remove(json);
    CliRun r = run(scene + " --spp 2 --seed 3 -q -o " + scratch() + "/" + name + ".exr --stats-json " + json + " " + flags);
    EXPECT_EQ(r.code, 0) << r.err;
    std::ifstream in(json);
    return nlohmann::json::parse(in);  // throws (fails the test) when missing or malformed
  };
  nlohmann::json w = render("stats_wavefront", "");
  EXPECT_EQ(w["renderer"], "wavefront");
  EXPECT_EQ(w["width"], 8);
  EXPECT_EQ(w["height"], 8);
  EXPECT_EQ(w["spp"], 2);
  EXPECT_EQ(w["spp_completed"], 2);
  EXPECT_EQ(w["seed"], 3);
  EXPECT_EQ(w["samples"], 8 * 8 * 2);
  EXPECT_EQ(w["interrupted"], false);
  EXPECT_TRUE(w["warnings"].is_array());
  EXPECT_FALSE(w["device"].get<std::string>().empty());
  EXPECT_NE(w["kernel_features"].get<std::string>().find("specialised"), std::string::npos);
  double total = w["total_seconds"], build = w["compile_seconds"], bvh = w["bvh_seconds"], setup = w["setup_seconds"];
  EXPECT_GT(total, 0.0);
  EXPECT_GE(build, 0.0);
  EXPECT_GE(bvh, 0.0);
  EXPECT_GT(setup, 0.0);  // the wavefront opens a device and allocates its buffers
  EXPECT_LE(build + bvh + setup, total);
  EXPECT_NEAR(double(w["render_seconds"]), total - build - bvh - setup, 1e-9);
  EXPECT_GE(w["closest_rays"].get<uint64_t>(), w["samples"].get<uint64_t>()) << "one camera ray per sample at least";
  ASSERT_TRUE(w["stages"].is_array());
  bool saw_intersect = false;
  for (const auto& s : w["stages"]) {
    EXPECT_GE(double(s["seconds"]), 0.0);
    if (s["name"] == "intersect_closest") {
      saw_intersect = true;
      EXPECT_EQ(s["items"], w["closest_rays"]);
    }
  }
  EXPECT_TRUE(saw_intersect) << w.dump(2);
  uint64_t pool = w["pool_size"], state = w["state_bytes"], tris = w["triangles"];
  uint64_t scene_b = w["scene_bytes"], film = w["film_bytes"], device = w["device_bytes"];
  EXPECT_GT(pool, 0u);
  EXPECT_GE(state, pool * 4 * 8) << "a path state is several words";
  EXPECT_EQ(w["spheres"], 1) << "the sphere is one analytic primitive";
  EXPECT_GE(scene_b, tris * 3 * 4 * 3 + 16) << "at least the vertices of every triangle and the sphere";
  EXPECT_GE(film, 8u * 8u * 16u) << "RGB sums and a count per pixel";
  EXPECT_GE(device, state + scene_b + film);

  nlohmann::json s = render("stats_scalar", "--scalar");
  EXPECT_EQ(s["renderer"], "scalar");
  EXPECT_EQ(s["samples"], 8 * 8 * 2);
  EXPECT_EQ(s["triangles"], w["triangles"]);
  EXPECT_GT(s["scene_bytes"].get<uint64_t>(), 0u);
  EXPECT_EQ(s["device_bytes"], 0);
}

TEST(CliBadInput, UnwritableStatsJsonFailsBeforeRendering) {
  std::string scene = write_scene("ok.json", kMinimal);
  std::string out = scratch() + "/stats_unwritten.exr";
  fs::remove(out);
  CliRun r = run(scene + " -o " + out + " --stats-json /nonexistent_dir_archwave/s.json");
  EXPECT_EQ(r.code, 5) << r.err;
  EXPECT_NE(r.err.find("/nonexistent_dir_archwave/s.json"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

// An interrupted render writes the samples it completed, says so, and exits 130; SIGTERM (what
// a scheduler or `kill` sends) behaves exactly like SIGINT.
void check_interrupt(int sig, const std::string& tag) {
  // Fill the kernel cache first, so the interrupt lands while rendering, not while compiling
  // (a cold build takes seconds on a loaded machine).
  ASSERT_EQ(run(src("scenes/cornell.json") + " --spp 1 --width 8 --height 8 -o " + scratch() + "/warm.exr").code, 0);
  std::string out = scratch() + "/interrupted_" + tag + ".exr";
  fs::remove(out);
  pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    std::string errf = scratch() + "/interrupted_stderr.txt";
    freopen(errf.c_str(), "w", stderr);
    execl(ARCHWAVE_BINARY, ARCHWAVE_BINARY, src("scenes/cornell.json").c_str(), "--spp", "100000", "--width", "64",
          "--height", "64", "-o", out.c_str(), (char*)nullptr);
    _exit(127);
  }
  // Let it compile and render a while (kernels are cached by other tests), then ^C.
  std::this_thread::sleep_for(std::chrono::seconds(4));
  kill(pid, sig);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  ASSERT_TRUE(fs::exists(out));
  aw::Image img = aw::read_exr(out);
  EXPECT_GT(img.int_attrs["spp"], 0) << "some samples were complete";
  EXPECT_LT(img.int_attrs["spp"], 100000);
  EXPECT_EQ(img.string_attrs["archwave:interrupted"], "yes");
  double mean = 0.0;
  for (float v : img.rgb) mean += v;
  EXPECT_GT(mean, 0.0);
}

TEST(Cli, InterruptKeepsWhatWasRendered) { check_interrupt(SIGINT, "int"); }
TEST(Cli, TerminateKeepsWhatWasRenderedLikeInterrupt) { check_interrupt(SIGTERM, "term"); }

}  // namespace

namespace {

// Memory budgets (docs/cli.md, --max-memory): a scene whose render would not fit is refused
// with the sizes before its geometry is generated (exit 3, the object's position named),
// whatever its size: 200,000 default spheres (3.2 G triangles) are refused at the first one
// that crosses the limit, not tessellated (spheres with "segments": analytic spheres are one
// primitive each, tests/render/test_spheres.cpp). A bad size is a usage error.
TEST(Cli, MaxMemoryRefusesAScenePastTheLimitBeforeGeneratingIt) {
  std::string objects;
  for (int i = 0; i < 200000; ++i)
    objects += std::string(i ? "," : "") + R"({"shape":"sphere","center":[0,0,0],"segments":[128,64],"material":"m"})";
  const std::string path = write_scene("many_spheres.json", std::string(R"({"materials":{"m":{}},"objects":[)") +
                                                                 objects + "]}");
  const auto t0 = std::chrono::steady_clock::now();
  CliRun r = run(path + " -o " + scratch() + "/never.exr --max-memory 200M");
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(r.code, 3) << r.err;
  EXPECT_NE(r.err.find("objects["), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("triangles here"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--max-memory 200M"), std::string::npos) << r.err;
  // No wall-time bound: parsing the 20 MB scene alone took 20.3 s under AddressSanitizer on a
  // loaded CI machine. That the refusal comes before the geometry is generated is what the
  // object it names proves (objects[12] below: the 13th of 200,000, none after it built); had
  // all 3.2 G triangles been generated, the run would not end within ctest's timeout.
  std::printf("[ info     ] refused in %.2f s\n", secs);
  EXPECT_FALSE(fs::exists(scratch() + "/never.exr"));
  // The film (640 x 480 x 128 B) and the path pool (64 MiB) take 106.4 MB of the 209.7 MB; 12
  // spheres of 16,128 triangles x 500 B fit in the rest, the 13th is refused.
  EXPECT_NE(r.err.find("objects[12]"), std::string::npos) << r.err;
  // A limit that is not a size.
  EXPECT_EQ(run(write_scene("m.json", kMinimal) + " --max-memory lots").code, 2);
  // 0 = no limit: the minimal scene renders.
  EXPECT_EQ(run(write_scene("m2.json", kMinimal) + " -o " + scratch() + "/m2.exr -q --max-memory 0").code, 0);
}

}  // namespace

namespace {

// Production renders through the command line (docs/production.md): parts made by separate
// processes merge into the single render bit for bit; an interrupted (SIGTERM) or time-limited
// render resumes to it bit for bit; checkpoints are never broken files; bad parts are refused.
const std::string kProdArgs = " --width 48 --height 32 --device pocl -q --no-progress";

bool same_pixels(const std::string& a, const std::string& b) {
  const aw::Image ia = aw::read_exr(a), ib = aw::read_exr(b);
  return ia.width == ib.width && ia.height == ib.height && ia.rgb.size() == ib.rgb.size() &&
         std::memcmp(ia.rgb.data(), ib.rgb.data(), ia.rgb.size() * sizeof(float)) == 0;
}

TEST(CliParts, SampleRangesAndCropsMergeIntoTheSingleRenderBitForBit) {
  const std::string scene = src("scenes/cornell.json"), d = scratch() + "/";
  ASSERT_EQ(run(scene + kProdArgs + " --spp 6 -o " + d + "whole.exr").code, 0);
  for (const char* r : {"0:1", "1:4", "4:6"}) {
    CliRun p = run(scene + kProdArgs + " --spp 6 --sample-range " + r + " -o " + d + "range_" + std::string(r).replace(1, 1, "_") + ".exr");
    ASSERT_EQ(p.code, 0) << p.err;
  }
  CliRun m = run("merge " + d + "range_4_6.exr " + d + "range_0_1.exr " + d + "range_1_4.exr -o " + d + "merged_ranges.exr");
  ASSERT_EQ(m.code, 0) << m.err;
  EXPECT_NE(m.err.find("merged 3 parts"), std::string::npos) << m.err;
  EXPECT_TRUE(same_pixels(d + "merged_ranges.exr", d + "whole.exr"));
  // Crop windows of uneven size (pbrt's rounding: 48 * 0.3 -> 15, 32 * 0.55 -> 18).
  ASSERT_EQ(run(scene + kProdArgs + " --spp 6 --crop-window 0,0.3,0,1 -o " + d + "c1.exr").code, 0);
  ASSERT_EQ(run(scene + kProdArgs + " --spp 6 --crop-window 0.3,1,0,0.55 -o " + d + "c2.exr").code, 0);
  ASSERT_EQ(run(scene + kProdArgs + " --spp 6 --pixel-bounds 15,48,18,32 -o " + d + "c3.exr").code, 0);
  const aw::Image c1 = aw::read_exr(d + "c1.exr");
  EXPECT_EQ(c1.width, 15);
  EXPECT_EQ(c1.frame_width, 48);
  ASSERT_EQ(run("merge " + d + "c1.exr " + d + "c2.exr " + d + "c3.exr -o " + d + "merged_crops.exr").code, 0);
  EXPECT_TRUE(same_pixels(d + "merged_crops.exr", d + "whole.exr"));
  // Refusals name the files: overlapping samples, another seed, not an archwave film.
  CliRun o = run("merge " + d + "range_0_1.exr " + d + "merged_ranges.exr -o " + d + "bad.exr");
  EXPECT_EQ(o.code, 3) << o.err;
  EXPECT_NE(o.err.find("overlap"), std::string::npos) << o.err;
  ASSERT_EQ(run(scene + kProdArgs + " --spp 6 --seed 9 --sample-range 1:6 -o " + d + "seed9.exr").code, 0);
  CliRun sd = run("merge " + d + "range_0_1.exr " + d + "seed9.exr -o " + d + "bad.exr");
  EXPECT_EQ(sd.code, 3) << sd.err;
  EXPECT_NE(sd.err.find("seeds differ"), std::string::npos) << sd.err;
  EXPECT_NE(sd.err.find("seed9.exr"), std::string::npos) << sd.err;
  CliRun nf = run("merge " + d + "whole.exr " + d + "range_0_1.exr -o " + d + "bad.exr");
  EXPECT_EQ(nf.code, 5) << nf.err;
  EXPECT_NE(nf.err.find("no archwave film state"), std::string::npos) << nf.err;
  EXPECT_FALSE(fs::exists(d + "bad.exr"));
  EXPECT_EQ(run("merge -o " + d + "bad.exr").code, 2);
  // Bad parts of the command line.
  for (const char* bad : {"--sample-range 4:2", "--sample-range 0:7", "--sample-range x", "--crop-window 0,2,0,1",
                          "--pixel-bounds 0,49,0,32", "--pixel-bounds 1.5,4,0,2"}) {
    CliRun b = run(scene + kProdArgs + " --spp 6 " + bad + " -o " + d + "bad.exr");
    EXPECT_EQ(b.code, 3) << bad << ": " << b.err;
    EXPECT_NE(b.err.find(std::string(bad).substr(0, std::string(bad).find(' '))), std::string::npos) << b.err;
  }
}

TEST(CliParts, TimeLimitedThenResumedIsTheSingleRenderBitForBit) {
  const std::string scene = src("scenes/cornell.json"), d = scratch() + "/";
  // 3 M samples: three batches of the default size, so the limit (checked at batch ends)
  // passes after the first.
  const std::string args = kProdArgs + " --spp 2000";
  ASSERT_EQ(run(scene + args + " -o " + d + "tl_whole.exr").code, 0);
  CliRun t = run(scene + args + " --time-limit 0.3 -o " + d + "tl_part.exr");
  ASSERT_EQ(t.code, 0) << t.err;
  const aw::Image part = aw::read_exr(d + "tl_part.exr");
  EXPECT_EQ(part.string_attrs.at("archwave:time_limited"), "yes");
  EXPECT_LT(part.int_attrs.at("spp"), 2000);
  EXPECT_NE(t.err.find("--resume"), std::string::npos) << t.err;
  CliRun r = run(scene + args + " --resume " + d + "tl_part.exr -o " + d + "tl_resumed.exr");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(same_pixels(d + "tl_resumed.exr", d + "tl_whole.exr"));
  // A resume that does not fit: another seed, the scalar path, a file that is not one.
  CliRun s = run(scene + args + " --seed 3 --resume " + d + "tl_part.exr -o " + d + "x.exr");
  EXPECT_EQ(s.code, 3) << s.err;
  EXPECT_NE(s.err.find("seed"), std::string::npos) << s.err;
  CliRun sc = run(scene + args + " --scalar --resume " + d + "tl_part.exr -o " + d + "x.exr");
  EXPECT_EQ(sc.code, 3) << sc.err;
  EXPECT_NE(sc.err.find("wavefront"), std::string::npos) << sc.err;
  CliRun nf = run(scene + args + " --resume " + d + "tl_whole.exr -o " + d + "x.exr");
  EXPECT_EQ(nf.code, 3) << nf.err;
  EXPECT_NE(nf.err.find("no archwave film state"), std::string::npos) << nf.err;
}

// SIGTERM (what Slurm sends at a job's time limit) mid-render, then --resume: bit for bit the
// uninterrupted render. The signal goes once the first checkpoint exists, so it lands while
// rendering whatever the machine's load.
TEST(CliParts, TerminatedThenResumedIsTheSingleRenderBitForBit) {
  const std::string scene = src("scenes/cornell.json"), d = scratch() + "/";
  ASSERT_EQ(run(scene + kProdArgs + " --spp 1500 -o " + d + "sig_whole.exr").code, 0);
  const std::string out = d + "sig_part.exr";
  fs::remove(out);
  pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    freopen((d + "sig_stderr.txt").c_str(), "w", stderr);
    execl(ARCHWAVE_BINARY, ARCHWAVE_BINARY, scene.c_str(), "--width", "48", "--height", "32", "--device", "pocl", "--spp",
          "1500", "--checkpoint", "0.1", "-o", out.c_str(), (char*)nullptr);
    _exit(127);
  }
  for (int i = 0; i < 600 && !fs::exists(out); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_TRUE(fs::exists(out)) << "no checkpoint within 30 s";
  kill(pid, SIGTERM);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_EQ(WEXITSTATUS(status), 130) << "the render ended before the signal; make it longer";
  const aw::Image part = aw::read_exr(out);
  EXPECT_EQ(part.string_attrs.at("archwave:interrupted"), "yes");
  EXPECT_LT(part.int_attrs.at("spp"), 1500);
  CliRun r = run(scene + kProdArgs + " --spp 1500 --resume " + out + " -o " + d + "sig_resumed.exr");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(same_pixels(d + "sig_resumed.exr", d + "sig_whole.exr"));
}

// An OpenCL error mid-render (ARCHWAVE_FAULT injects one at the Nth stage launch; a device
// lost answers nothing more): exit 4 with the call, the error code and the device named, and
// the film so far written with its state, so that --resume completes the render bit for bit
// as if nothing had happened. When the device is lost before the first snapshot, nothing is
// written (docs/production.md#a-device-lost-mid-render).
TEST(CliParts, ADeviceFailingMidRenderWritesItsFilmAndResumesBitForBit) {
  const std::string scene = src("scenes/cornell.json"), d = scratch() + "/";
  // 48 x 32 x 64 samples in batches of 4 x 1024 jobs: 24 batches of a few dozen launches each.
  const std::string args = kProdArgs + " --spp 64 --pool 1024";
  ASSERT_EQ(run(scene + args + " -o " + d + "dev_whole.exr").code, 0);
  CliRun f = run(scene + args + " -o " + d + "dev_part.exr", "ARCHWAVE_FAULT=launch:300");
  ASSERT_EQ(f.code, 4) << f.err;
  for (const char* named : {"clEnqueueNDRangeKernel", "CL_OUT_OF_RESOURCES", "rendering on ", "the film keeps",
                            "--resume " /* how to go on */})
    EXPECT_NE(f.err.find(named), std::string::npos) << named << " in: " << f.err;
  const aw::Image part = aw::read_exr(d + "dev_part.exr");
  EXPECT_GT(part.int_attrs.at("spp"), 0);
  EXPECT_LT(part.int_attrs.at("spp"), 64);
  EXPECT_NE(part.string_attrs.at("archwave:device_error").find("CL_OUT_OF_RESOURCES"), std::string::npos);
  CliRun r = run(scene + args + " --resume " + d + "dev_part.exr -o " + d + "dev_resumed.exr");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(same_pixels(d + "dev_resumed.exr", d + "dev_whole.exr"));
  // Lost at the third launch: no snapshot yet, nothing written.
  CliRun lost = run(scene + args + " -o " + d + "dev_lost.exr", "ARCHWAVE_FAULT=lost:3");
  EXPECT_EQ(lost.code, 4) << lost.err;
  EXPECT_NE(lost.err.find("no film was kept"), std::string::npos) << lost.err;
  EXPECT_NE(lost.err.find("the device no longer answers"), std::string::npos) << lost.err;
  EXPECT_FALSE(fs::exists(d + "dev_lost.exr"));
}

// Killed (SIGKILL: no handler runs) while checkpointing again and again: the file at the output
// path is always a complete film that resumes, never a torn write.
TEST(CliParts, AKilledCheckpointLeavesThePreviousOneIntact) {
  const std::string scene = src("scenes/cornell.json"), d = scratch() + "/";
  const std::string out = d + "ck.exr";
  for (int round = 0; round < 3; ++round) {
    fs::remove(out);
    pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      freopen((d + "ck_stderr.txt").c_str(), "w", stderr);
      execl(ARCHWAVE_BINARY, ARCHWAVE_BINARY, scene.c_str(), "--width", "400", "--height", "300", "--device", "pocl", "--spp",
            "100000", "--checkpoint", "0.01", "-o", out.c_str(), (char*)nullptr);
      _exit(127);
    }
    for (int i = 0; i < 600 && !fs::exists(out); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    ASSERT_TRUE(fs::exists(out));
    // Kill at a different moment of the write cycle each round.
    std::this_thread::sleep_for(std::chrono::milliseconds(150 + 97 * round));
    kill(pid, SIGKILL);
    waitpid(pid, nullptr, 0);
    EXPECT_NO_THROW({
      const aw::FilmState f = aw::read_film_state(out);
      EXPECT_EQ(f.width, 400);
    });
  }
}

}  // namespace
