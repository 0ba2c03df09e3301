// The Slurm recipe end to end (issue 15, docs/production.md#slurm): a one-node cluster on
// loopback (scripts/slurm/local_cluster.sh: munged with a generated key, slurmctld, slurmd,
// every file inside the build tree), a 4-task job array of parts and the dependent merge job
// (scripts/slurm/submit.sh), waited for with a bounded timeout; the merged frame must equal
// the single-process render bit for bit. Every daemon started is stopped, also on failure.
// Installs Debian's slurm-wlm and munge when missing (root); skipped, and reported so, where
// that is not possible.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "host/film/image_io.h"
#include "host/render/film_state.h"

namespace fs = std::filesystem;

namespace {

std::string src(const std::string& rel) { return std::string(ARCHWAVE_SOURCE_DIR) + "/" + rel; }

// Runs a shell command; returns its exit code and its output (stdout and stderr).
int sh(const std::string& cmd, std::string* out = nullptr) {
  std::string full = "(" + cmd + ") 2>&1";
  FILE* p = popen(full.c_str(), "r");
  if (!p) return -1;
  std::string text;
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) text.append(buf, n);
  int status = pclose(p);
  if (out) *out = text;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The cluster's lifetime: stopped in the destructor, whatever the test's outcome.
struct Cluster {
  std::string dir, conf;
  bool started = false;
  explicit Cluster(std::string d) : dir(std::move(d)) {}
  ~Cluster() {
    if (started) sh("bash " + src("scripts/slurm/local_cluster.sh") + " stop " + dir);
  }
};

bool same_pixels(const aw::Image& a, const aw::Image& b) {
  return a.width == b.width && a.height == b.height && a.rgb.size() == b.rgb.size() &&
         std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

TEST(Slurm, JobArrayOfPartsAndMergeEqualTheSingleRenderBitForBit) {
  std::string log;
  int rc = sh("bash " + src("scripts/slurm/local_cluster.sh") + " install", &log);
  if (rc == 77) GTEST_SKIP() << "Slurm and munge are not installed and cannot be (not root): " << log;
  ASSERT_EQ(rc, 0) << log;

  const std::string dir = fs::absolute(fs::path(ARCHWAVE_BINARY).parent_path() / ("slurm-test-" + std::to_string(getpid())));
  fs::remove_all(dir);
  Cluster cluster(dir + "/cluster");
  rc = sh("bash " + src("scripts/slurm/local_cluster.sh") + " start " + cluster.dir, &log);
  cluster.started = true;
  ASSERT_EQ(rc, 0) << log;
  const std::string env = "SLURM_CONF=" + cluster.dir + "/slurm.conf ";

  const std::string scene = src("scenes/cornell.json");
  const std::string args = "--width 48 --height 32 --device pocl -q";
  for (const char* split : {"samples", "tiles"}) {
    SCOPED_TRACE(split);
    const std::string out = dir + "/" + split + "/frame.exr";
    fs::create_directories(dir + "/" + split);
    std::string ids;
    rc = sh(env + "bash " + src("scripts/slurm/submit.sh") + " " + scene + " " + out + " --parts 4 --spp 6 --split " + split +
                " --archwave " + ARCHWAVE_BINARY + " -- " + args,
            &ids);
    ASSERT_EQ(rc, 0) << ids;
    unsigned array = 0, merge = 0;
    ASSERT_EQ(std::sscanf(ids.c_str(), "%u %u", &array, &merge), 2) << ids;
    // Bounded wait: the merge job leaves the queue (done, failed or cancelled).
    const auto t0 = std::chrono::steady_clock::now();
    std::string state;
    for (;;) {
      sh(env + "scontrol show job " + std::to_string(merge) + " | grep -o 'JobState=[A-Z_]*'", &state);
      if (state.find("COMPLETED") != std::string::npos || state.find("FAILED") != std::string::npos ||
          state.find("CANCELLED") != std::string::npos || state.find("TIMEOUT") != std::string::npos)
        break;
      ASSERT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 180.0)
          << "the jobs did not finish within 180 s; " << state << "\n"
          << read_text(cluster.dir + "/logs/slurmctld.log");
      std::this_thread::sleep_for(std::chrono::milliseconds(250));
    }
    std::string tasks;
    sh(env + "scontrol show job " + std::to_string(array) + " | grep -o 'JobState=[A-Z_]*'", &tasks);
    ASSERT_NE(state.find("COMPLETED"), std::string::npos)
        << state << "; array tasks: " << tasks << "\nmerge log:\n"
        << read_text(dir + "/" + split + "/frame.parts/logs/merge_" + std::to_string(merge) + ".log");
    // Four array tasks, each with its own log and part.
    for (int i = 0; i < 4; ++i) {
      char part[64];
      std::snprintf(part, sizeof part, "/frame.parts/part_%04d.exr", i);
      EXPECT_TRUE(fs::exists(dir + "/" + split + part)) << part;
      EXPECT_TRUE(fs::exists(dir + "/" + split + "/frame.parts/logs/part_" + std::to_string(array) + "_" +
                             std::to_string(i) + ".log"));
    }
    // The same frame in one process.
    const std::string single = dir + "/" + split + "/single.exr";
    rc = sh(std::string(ARCHWAVE_BINARY) + " " + scene + " --spp 6 " + args + " -o " + single, &log);
    ASSERT_EQ(rc, 0) << log;
    const aw::Image merged = aw::read_exr(out), whole = aw::read_exr(single);
    EXPECT_TRUE(same_pixels(merged, whole)) << "the merged frame differs from the single render";
    EXPECT_EQ(aw::read_film_state(out).min_spp(), 6u);
  }
}

}  // namespace
