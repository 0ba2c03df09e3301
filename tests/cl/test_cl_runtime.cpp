// The OpenCL layer's promises: a failed build prints the build log with kernels/<file>:<line>,
// an allocation larger than the device allows is refused with both sizes, and no platform at
// all says how to install PoCL.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "host/cl/cl_runtime.h"
#include "host/cl/kernel_source.h"

namespace {

TEST(ClRuntime, ListsAtLeastOneDevice) {
  auto devices = aw::list_devices();
  ASSERT_FALSE(devices.empty());
  EXPECT_EQ(devices[0].index, 0);
  EXPECT_GT(devices[0].max_alloc, 0u);
  EXPECT_NE(aw::describe_devices(devices).find("[0]"), std::string::npos);
}

TEST(ClRuntime, BuildFailureCarriesTheLogWithFileAndLine) {
  aw::ClRuntime rt(aw::kDefaultDevice);
  std::string src = "#line 1 \"kernels/broken.cl\"\n__kernel void k(__global float* x) {\n  x[0] = undefined_name;\n}\n";
  try {
    rt.build(src, "-cl-std=CL1.2");
    FAIL() << "the build should fail";
  } catch (const aw::ClError& e) {
    std::string m = e.what();
    EXPECT_NE(m.find("build log"), std::string::npos) << m;
    EXPECT_NE(m.find("undefined_name"), std::string::npos) << m;
    EXPECT_NE(m.find("kernels/broken.cl:2"), std::string::npos) << m;
  }
}

// A render builds up to three programs (kernels.cl, and kernels_lanes.cl at two widths), all
// with the render's compile_seconds: each build adds its time there. When each one overwrote
// it, the first programs' build (60-90 ms on Intel's runtime from the binary cache) was left
// in render_seconds and lowered the race's samples/s (docs/performance.md, "Render time
// without the kernel build").
TEST(ClRuntime, BuildAddsItsTimeToTheCallersSum) {
  aw::ClRuntime rt(aw::kDefaultDevice);
  const std::string src = "__kernel void k(__global float* x) { x[get_global_id(0)] = 1.0f; }\n";
  double seconds = 1000.0;  // what the caller counted before
  rt.build(src, "-cl-std=CL1.2", &seconds);
  const double after_one = seconds;
  EXPECT_GT(after_one, 1000.0);
  rt.build(src, "-cl-std=CL1.2 -DSECOND", &seconds);
  EXPECT_GT(seconds, after_one);
}

// NVIDIA's OpenCL compiler ignores `#line` (measured on an H200, driver 580: the log said
// "<kernel>:3:10" for line 2 of kernels/broken.cl). The log then names the raw line, and
// annotate_build_log adds the file and line it comes from. The log below is that one.
TEST(ClRuntime, BuildLogPositionsInTheRawSourceNameTheKernelFile) {
  const std::string src = "#line 1 \"kernels/broken.cl\"\n__kernel void k(__global float* x) {\n  x[0] = undefined_name;\n}\n";
  const std::string log =
      "<kernel>:3:10: error: use of undeclared identifier 'undefined_name'\n  x[0] = undefined_name;\n         ^\n";
  const std::string m = aw::annotate_build_log(src, log);
  EXPECT_NE(m.find("<kernel>:3:10 [kernels/broken.cl:2:10]: error: use of undeclared identifier"), std::string::npos) << m;
  EXPECT_NE(m.find("  x[0] = undefined_name;\n         ^"), std::string::npos) << m;  // the rest untouched

  // Through nested files: a line of the included header and a line after the include.
  const std::string nested =
      "#line 1 \"kernels/a.cl\"\nint a1;\n#line 1 \"kernels/common/b.h\"\nint b1;\nint b2;\n#line 3 \"kernels/a.cl\"\nint a3;\n";
  EXPECT_EQ(aw::assembled_source_location(nested, 2), "kernels/a.cl:1");
  EXPECT_EQ(aw::assembled_source_location(nested, 5), "kernels/common/b.h:2");
  EXPECT_EQ(aw::assembled_source_location(nested, 7), "kernels/a.cl:3");
  EXPECT_EQ(aw::assembled_source_location(nested, 1), "");   // a marker is no source line
  EXPECT_EQ(aw::assembled_source_location(nested, 8), "");   // past the end
  EXPECT_EQ(aw::assembled_source_location(nested, 0), "");
  EXPECT_EQ(aw::annotate_build_log(nested, "<source>:5:3: warning: x\n<kernel>:99:1: error: y\n"),
            "<source>:5:3 [kernels/common/b.h:2:3]: warning: x\n<kernel>:99:1: error: y\n");
  EXPECT_EQ(aw::annotate_build_log(nested, "<kernel>:4: note\n"), "<kernel>:4 [kernels/common/b.h:1]: note\n");
  // A compiler that honours #line (PoCL, Intel) names the file itself: nothing is added.
  const std::string pocl = "kernels/broken.cl:2:10: error: use of undeclared identifier 'undefined_name'\n";
  EXPECT_EQ(aw::annotate_build_log(src, pocl), pocl);
  // Numbers too long for a line are left alone rather than thrown on.
  EXPECT_EQ(aw::annotate_build_log(src, "<kernel>:99999999999999999999:1"), "<kernel>:99999999999999999999:1");
}

// Every device divides and takes square roots as the host does where it offers to
// (device_build_options adds -cl-fp32-correctly-rounded-divide-sqrt): bit for bit over random,
// tiny and huge operands (normal ones: a device may flush subnormals, CL_FP_DENORM). A device
// that does not offer it is held to the spec's bounds instead (OpenCL 1.2 §7.4: 2.5 ulp for
// x / y, 3 ulp for sqrt).
TEST(ClRuntime, DivisionAndSqrtAreCorrectlyRoundedWhereTheDeviceOffersIt) {
  aw::ClRuntime rt(aw::kDefaultDevice);
  const bool offered = rt.info().correctly_rounded_divide_sqrt;
  EXPECT_EQ(aw::device_build_options(rt.info(), "-cl-std=CL1.2").find("-cl-fp32-correctly-rounded-divide-sqrt") !=
                std::string::npos,
            offered);
  const std::string src =
      "__kernel void k(__global const float* a, __global const float* b, __global float* q, __global float* r) {\n"
      "  uint i = get_global_id(0); q[i] = a[i] / b[i]; r[i] = sqrt(a[i]); }\n";
  cl::Program p = rt.build(src, "-cl-std=CL1.2");
  const size_t n = 1 << 16;
  std::vector<float> a(n), b(n);
  std::mt19937 rng(20261204);
  std::uniform_real_distribution<float> mant(1.0f, 2.0f);
  std::uniform_int_distribution<int> ex(-60, 60);
  for (size_t i = 0; i < n; ++i) {
    // Operands over 120 binades, every 64th one near the bottom (a) or the top (b) of the range.
    a[i] = std::ldexp(mant(rng), ex(rng));
    b[i] = std::ldexp(mant(rng), ex(rng));
    if (i % 64 == 0) a[i] = std::ldexp(mant(rng), -126);
    if (i % 64 == 1) b[i] = std::ldexp(mant(rng), 120);
  }
  cl::Buffer ba = rt.buffer("a", n * 4, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, a.data());
  cl::Buffer bb = rt.buffer("b", n * 4, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, b.data());
  cl::Buffer bq = rt.buffer("q", n * 4), br = rt.buffer("r", n * 4);
  cl::Kernel k(p, "k");
  k.setArg(0, ba), k.setArg(1, bb), k.setArg(2, bq), k.setArg(3, br);
  rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(n), cl::NDRange(64));
  std::vector<float> q(n), r(n);
  rt.queue().enqueueReadBuffer(bq, CL_TRUE, 0, n * 4, q.data());
  rt.queue().enqueueReadBuffer(br, CL_TRUE, 0, n * 4, r.data());
  auto ulps = [](float x, float y) {  // distance in representable floats (same sign here)
    int32_t ix, iy;
    std::memcpy(&ix, &x, 4), std::memcpy(&iy, &y, 4);
    return std::abs(int64_t(ix) - int64_t(iy));
  };
  int64_t worst_q = 0, worst_r = 0;
  size_t off_q = 0, off_r = 0;
  for (size_t i = 0; i < n; ++i) {
    const float hq = a[i] / b[i], hr = std::sqrt(a[i]);
    // Quotients are compared only where normal (see above).
    if (std::fpclassify(hq) == FP_NORMAL) {
      int64_t d = ulps(q[i], hq);
      worst_q = std::max(worst_q, d), off_q += d != 0;
    }
    int64_t d = ulps(r[i], hr);
    worst_r = std::max(worst_r, d), off_r += d != 0;
  }
  const std::string what = rt.info().name + " (" + rt.info().platform + "), correct rounding " +
                           (offered ? "offered" : "not offered") + ": x / y " + std::to_string(off_q) +
                           " results off, at most " + std::to_string(worst_q) + " ulp; sqrt " + std::to_string(off_r) +
                           " off, at most " + std::to_string(worst_r) + " ulp";
  if (offered) {
    EXPECT_EQ(worst_q, 0) << what;
    EXPECT_EQ(worst_r, 0) << what;
  } else {
    EXPECT_LE(worst_q, 3) << what;  // 2.5 ulp, counted in whole floats
    EXPECT_LE(worst_r, 3) << what;
  }
  std::printf("[ info     ] %s\n", what.c_str());
}

TEST(ClRuntime, AssembledKernelsPointErrorsAtTheRealFile) {
  // The embedded sources expand includes with #line markers: every line of the assembled
  // source maps back to kernels/<file>. Check that a line of a nested header is attributed
  // to that header.
  std::string s = aw::assemble_kernel_source("integrator/kernels.cl", "");
  EXPECT_NE(s.find("#line 1 \"kernels/common/compat.h\""), std::string::npos);
  EXPECT_NE(s.find("#line 1 \"kernels/bvh/traverse.h\""), std::string::npos);
  // Each header appears once even though several files include it.
  size_t first = s.find("#line 1 \"kernels/common/compat.h\"");
  EXPECT_EQ(s.find("#line 1 \"kernels/common/compat.h\"", first + 1), std::string::npos);
  // Loading from disk gives the same text as the embedded copy.
  EXPECT_EQ(s, aw::assemble_kernel_source("integrator/kernels.cl", std::string(ARCHWAVE_SOURCE_DIR) + "/kernels"));
  EXPECT_THROW(aw::assemble_kernel_source("no/such.cl", ""), std::runtime_error);
}

TEST(ClRuntime, OversizedAllocationIsRefusedWithTheSizes) {
  aw::ClRuntime rt(aw::kDefaultDevice);
  size_t too_big = size_t(rt.info().max_alloc) + 4096;
  try {
    rt.buffer("test buffer", too_big);
    FAIL() << "allocation should be refused";
  } catch (const aw::ClError& e) {
    std::string m = e.what();
    EXPECT_NE(m.find("test buffer"), std::string::npos) << m;
    EXPECT_NE(m.find(aw::format_bytes(too_big)), std::string::npos) << m;
    EXPECT_NE(m.find(aw::format_bytes(rt.info().max_alloc)), std::string::npos) << m;
  }
}

TEST(ClRuntime, NoPlatformSaysHowToInstallPoCL) {
  // Point the ICD loader at an empty vendor directory: no platform at all.
  std::string dir = testing::TempDir() + "/empty_icd";
  std::system(("mkdir -p " + dir).c_str());
  std::string out = testing::TempDir() + "/noplatform.txt";
  std::string cmd = "OCL_ICD_VENDORS=" + dir + " OCL_ICD_FILENAMES= " + std::string(ARCHWAVE_BINARY) +
                    " --list-devices 2>" + out;
  int status = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(status), 4);
  std::ifstream in(out);
  std::string err((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(err.find("pocl-opencl-icd"), std::string::npos) << err;
}

}  // namespace

// --device by index or by a part of the name (resolve_device), on a made-up device list so
// that the matching rules are tested whatever this machine has.
namespace {
std::vector<aw::DeviceInfo> fake_devices() {
  std::vector<aw::DeviceInfo> v(3);
  v[0].index = 0, v[0].platform = "Intel(R) OpenCL", v[0].name = "AMD EPYC", v[0].type = "CPU";
  v[0].version = "OpenCL 3.0 (Build 0)";
  v[1].index = 1, v[1].platform = "Portable Computing Language", v[1].name = "pthread-haswell-AMD EPYC",
  v[1].type = "CPU", v[1].version = "OpenCL 3.0 PoCL HSTR: pthread-x86_64-pc-linux-gnu-haswell";
  v[2].index = 2, v[2].platform = "NVIDIA CUDA", v[2].name = "NVIDIA H200", v[2].type = "GPU";
  return v;
}
std::string resolve_error(const std::string& spec) {
  try {
    aw::resolve_device(spec, fake_devices());
  } catch (const aw::ClError& e) {
    return e.what();
  }
  return "<resolved>";
}
}  // namespace

TEST(DeviceChoice, IndexOrUniqueCaseInsensitiveSubstring) {
  const auto d = fake_devices();
  EXPECT_EQ(aw::resolve_device("0", d), 0);
  EXPECT_EQ(aw::resolve_device("2", d), 2);
  EXPECT_EQ(aw::resolve_device("intel", d), 0);
  EXPECT_EQ(aw::resolve_device("PoCL", d), 1);  // from PoCL's version string
  EXPECT_EQ(aw::resolve_device("gpu", d), 2);
  EXPECT_EQ(aw::resolve_device("h200", d), 2);
}

// On an Intel CPU PoCL's device name holds "Intel" too: the platform's name decides (seen on
// a Xeon, where ARCHWAVE_DEVICE=intel matched both CPU devices, 2026-12-03).
TEST(DeviceChoice, APlatformNameOutranksADeviceName) {
  auto d = fake_devices();
  d[0].name = "Intel(R) Xeon(R) Processor @ 2.80GHz";
  d[1].name = "pthread-skylake-avx512-Intel(R) Xeon(R) Processor @ 2.80GHz";
  EXPECT_EQ(aw::resolve_device("intel", d), 0);
  EXPECT_EQ(aw::resolve_device("pocl", d), 1);
  EXPECT_THROW(aw::resolve_device("xeon", d), aw::ClError);  // two device names, no platform: ambiguous
}

TEST(DeviceChoice, BadChoicesAreRefusedWithTheList) {
  std::string e = resolve_error("3");
  EXPECT_NE(e.find("--device 3: no such OpenCL device"), std::string::npos) << e;
  EXPECT_NE(e.find("[2] NVIDIA H200"), std::string::npos) << e;
  e = resolve_error("99999999999999");
  EXPECT_NE(e.find("no such OpenCL device"), std::string::npos) << e;
  e = resolve_error("amd");  // two CPUs: ambiguous, and the message lists only those two
  EXPECT_NE(e.find("matches 2 devices"), std::string::npos) << e;
  EXPECT_NE(e.find("[0] AMD EPYC"), std::string::npos) << e;
  EXPECT_EQ(e.find("H200"), std::string::npos) << e;
  e = resolve_error("radeon");
  EXPECT_NE(e.find("no OpenCL device's platform, name, type or version contains it"), std::string::npos) << e;
  e = resolve_error("-1");
  EXPECT_NE(e.find("-1"), std::string::npos) << e;
  EXPECT_NE(resolve_error("").find("no OpenCL device"), std::string::npos);
}

// With no device asked for, $ARCHWAVE_DEVICE decides (the suite sets "pocl"); a value that
// names no device is refused naming the variable, not silently replaced by device 0.
TEST(DeviceChoice, DefaultDeviceFollowsArchwaveDevice) {
  const char* old = std::getenv("ARCHWAVE_DEVICE");
  std::string saved = old ? old : "";
  setenv("ARCHWAVE_DEVICE", "pocl", 1);
  EXPECT_NE(aw::ClRuntime(aw::kDefaultDevice).info().version.find("PoCL"), std::string::npos);
  setenv("ARCHWAVE_DEVICE", "no-such-device", 1);
  try {
    aw::ClRuntime rt(aw::kDefaultDevice);
    ADD_FAILURE() << "a bad ARCHWAVE_DEVICE was accepted";
  } catch (const aw::ClError& e) {
    EXPECT_NE(std::string(e.what()).find("ARCHWAVE_DEVICE=no-such-device: no OpenCL device"), std::string::npos) << e.what();
  }
  if (old)
    setenv("ARCHWAVE_DEVICE", saved.c_str(), 1);
  else
    unsetenv("ARCHWAVE_DEVICE");
}
