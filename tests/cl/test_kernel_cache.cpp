// The disk cache of compiled OpenCL programs (host/cl/kernel_cache.h): a stored binary comes
// back byte for byte under the same key and never under another; a damaged file is a miss;
// "0" turns the cache off; and a program built from a cached binary computes what the
// compiled one does. On PoCL (the suite's device) the runtime's own cache is used and nothing
// is written; the same test runs on Intel's runtime as ClRuntime.*@intel, where the binary
// cache is what makes the second build a hit.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "host/cl/cl_runtime.h"
#include "host/cl/kernel_cache.h"

namespace {

namespace fs = std::filesystem;

std::string fresh_dir(const std::string& name) {
  std::string d = testing::TempDir() + "/" + name + "_" + std::to_string(::getpid());
  fs::remove_all(d);
  return d;
}

// Sets an environment variable for the scope, restoring the old value.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* o = std::getenv(name)) old_ = o, had_ = true;
    setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (had_) setenv(name_, old_.c_str(), 1);
    else unsetenv(name_);
  }

 private:
  const char* name_;
  std::string old_;
  bool had_ = false;
};

TEST(KernelCache, StoresAndLoadsUnderItsKeyOnly) {
  std::string dir = fresh_dir("kc_roundtrip");
  std::vector<unsigned char> bin(10000);
  for (size_t i = 0; i < bin.size(); ++i) bin[i] = (unsigned char)(i * 7 + (i >> 8));
  bin[5] = '\n';  // binaries hold newlines and zeros: the header must not be confused by them
  bin[6] = 0;
  aw::KernelCache a(dir, "device A\nsource");
  ASSERT_TRUE(a.enabled());
  std::vector<unsigned char> got;
  EXPECT_FALSE(a.load(&got));  // nothing stored yet
  EXPECT_EQ(a.store(bin), "");
  ASSERT_TRUE(a.load(&got));
  EXPECT_EQ(got, bin);
  // Another key (another device, driver, option or source) does not see it.
  aw::KernelCache b(dir, "device B\nsource");
  EXPECT_NE(a.path(), b.path());
  EXPECT_FALSE(b.load(&got));
  // No temporary files are left beside the entry.
  size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir)) files += e.is_regular_file();
  EXPECT_EQ(files, 1u);
}

TEST(KernelCache, DamagedOrForeignFilesAreMisses) {
  std::string dir = fresh_dir("kc_damaged");
  std::vector<unsigned char> bin(4096, 0x5a), got;
  aw::KernelCache c(dir, "key");
  ASSERT_EQ(c.store(bin), "");
  std::string whole;
  {
    std::ifstream in(c.path(), std::ios::binary);
    whole.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  auto write = [&](const std::string& text) {
    std::ofstream out(c.path(), std::ios::binary | std::ios::trunc);
    out << text;
  };
  write(whole.substr(0, whole.size() - 100));  // truncated
  EXPECT_FALSE(c.load(&got));
  std::string flipped = whole;
  flipped[flipped.size() - 10] ^= 1;  // one bit of the binary
  write(flipped);
  EXPECT_FALSE(c.load(&got));
  write("not a cache file at all\n");
  EXPECT_FALSE(c.load(&got));
  write("");
  EXPECT_FALSE(c.load(&got));
  write(whole);  // and the intact file still loads
  EXPECT_TRUE(c.load(&got));
  EXPECT_EQ(got, bin);
}

TEST(KernelCache, DirectoryFromTheEnvironment) {
  {
    ScopedEnv e("ARCHWAVE_KERNEL_CACHE", "/some/where");
    EXPECT_EQ(aw::kernel_cache_dir(), "/some/where");
  }
  {
    ScopedEnv e("ARCHWAVE_KERNEL_CACHE", "0");
    EXPECT_EQ(aw::kernel_cache_dir(), "");
    EXPECT_FALSE(aw::KernelCache(aw::kernel_cache_dir(), "k").enabled());
  }
  {
    ScopedEnv e("ARCHWAVE_KERNEL_CACHE", "");
    ScopedEnv x("XDG_CACHE_HOME", "/xdg");
    EXPECT_EQ(aw::kernel_cache_dir(), "/xdg/archwave/kernels");
  }
  // An unwritable place is reported, not thrown.
  aw::KernelCache c("/proc/archwave-cannot-write-here", "k");
  EXPECT_NE(c.store(std::vector<unsigned char>(16, 1)), "");
}

TEST(ClRuntime, ProgramFromTheBinaryCacheComputesTheSame) {
  std::string dir = fresh_dir("kc_runtime");
  ScopedEnv e("ARCHWAVE_KERNEL_CACHE", dir);
  const std::string src =
      "__kernel void k(__global float* x) { uint i = get_global_id(0); x[i] = sqrt((float)i) * 3.0f + 1.0f; }\n";
  const std::string opts = "-cl-std=CL1.2 -DAW_KERNEL_CACHE_TEST=" + std::to_string(::getpid());
  auto run = [&](aw::ClRuntime& rt, cl::Program& p) {
    cl::Buffer b = rt.buffer("x", 64 * sizeof(float));
    cl::Kernel k(p, "k");
    k.setArg(0, b);
    rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(64), cl::NDRange(16));
    std::vector<float> out(64);
    rt.queue().enqueueReadBuffer(b, CL_TRUE, 0, 64 * sizeof(float), out.data());
    return out;
  };
  aw::ClRuntime rt1(aw::kDefaultDevice);
  cl::Program p1 = rt1.build(src, opts);
  std::string first = rt1.last_build();
  std::vector<float> want = run(rt1, p1);
  aw::ClRuntime rt2(aw::kDefaultDevice);
  cl::Program p2 = rt2.build(src, opts);
  std::string second = rt2.last_build();
  EXPECT_EQ(run(rt2, p2), want);
  if (rt1.info().platform.find("Portable Computing Language") != std::string::npos) {
    // PoCL caches its own compiled kernels; archwave's cache stays out of its way.
    EXPECT_EQ(first, "PoCL's cache");
    EXPECT_EQ(second, "PoCL's cache");
    EXPECT_FALSE(fs::exists(dir));
  } else {
    EXPECT_EQ(first, "compiled (binary cache miss)");
    EXPECT_EQ(second, "binary cache hit");
  }
}

}  // namespace
