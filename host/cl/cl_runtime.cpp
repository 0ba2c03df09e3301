#include "host/cl/cl_runtime.h"

#include "host/cl/kernel_cache.h"
#include "host/cl/kernel_source.h"

#include <cctype>
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <sstream>

namespace aw {

std::string format_bytes(uint64_t b) {
  std::ostringstream s;
  s.precision(3);
  if (b >= (1ull << 30)) s << double(b) / double(1ull << 30) << " GiB";
  else if (b >= (1ull << 20)) s << double(b) / double(1ull << 20) << " MiB";
  else if (b >= 1024) s << double(b) / 1024.0 << " KiB";
  else s << b << " B";
  return s.str();
}

std::string cl_error_name(cl_int err) {
  switch (err) {
    case CL_DEVICE_NOT_FOUND: return "CL_DEVICE_NOT_FOUND";
    case CL_DEVICE_NOT_AVAILABLE: return "CL_DEVICE_NOT_AVAILABLE";
    case CL_MEM_OBJECT_ALLOCATION_FAILURE: return "CL_MEM_OBJECT_ALLOCATION_FAILURE";
    case CL_OUT_OF_RESOURCES: return "CL_OUT_OF_RESOURCES";
    case CL_OUT_OF_HOST_MEMORY: return "CL_OUT_OF_HOST_MEMORY";
    case CL_BUILD_PROGRAM_FAILURE: return "CL_BUILD_PROGRAM_FAILURE";
    case CL_INVALID_VALUE: return "CL_INVALID_VALUE";
    case CL_INVALID_BUFFER_SIZE: return "CL_INVALID_BUFFER_SIZE";
    case CL_INVALID_KERNEL_ARGS: return "CL_INVALID_KERNEL_ARGS";
    case CL_INVALID_WORK_GROUP_SIZE: return "CL_INVALID_WORK_GROUP_SIZE";
    case CL_INVALID_ARG_SIZE: return "CL_INVALID_ARG_SIZE";
    case CL_PLATFORM_NOT_FOUND_KHR: return "CL_PLATFORM_NOT_FOUND_KHR (no OpenCL platform)";
    default: return "OpenCL error " + std::to_string(err);
  }
}

static const char* kInstallHint =
    "no OpenCL platform found. archwave needs an OpenCL driver: on Debian/Ubuntu install PoCL "
    "(CPU, works everywhere) with `apt-get install pocl-opencl-icd ocl-icd-libopencl1`, or your "
    "GPU vendor's OpenCL driver (NVIDIA: a line `libnvidia-opencl.so.1` in "
    "/etc/OpenCL/vendors/nvidia.icd). `clinfo -l` shows what the loader sees.";

std::vector<DeviceInfo> list_devices() {
  std::vector<cl::Platform> platforms;
  try {
    cl::Platform::get(&platforms);
  } catch (const cl::Error& e) {
    throw ClError(kInstallHint);
  }
  if (platforms.empty()) throw ClError(kInstallHint);
  std::vector<DeviceInfo> out;
  for (auto& p : platforms) {
    std::vector<cl::Device> devs;
    try {
      p.getDevices(CL_DEVICE_TYPE_ALL, &devs);
    } catch (const cl::Error&) {
      continue;  // a platform with no usable device is skipped, not fatal
    }
    for (auto& d : devs) {
      DeviceInfo i;
      i.index = int(out.size());
      i.platform = p.getInfo<CL_PLATFORM_NAME>();
      i.name = d.getInfo<CL_DEVICE_NAME>();
      cl_device_type t = d.getInfo<CL_DEVICE_TYPE>();
      i.type = (t & CL_DEVICE_TYPE_GPU) ? "GPU" : (t & CL_DEVICE_TYPE_CPU) ? "CPU" : "other";
      i.version = d.getInfo<CL_DEVICE_VERSION>();
      i.driver = d.getInfo<CL_DRIVER_VERSION>();
      i.compute_units = d.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>();
      i.native_float_width = d.getInfo<CL_DEVICE_NATIVE_VECTOR_WIDTH_FLOAT>();
      i.global_mem = d.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>();
      i.max_alloc = d.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>();
      i.correctly_rounded_divide_sqrt = (d.getInfo<CL_DEVICE_SINGLE_FP_CONFIG>() & CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT) != 0;
      i.device = d;
      out.push_back(i);
    }
  }
  if (out.empty()) throw ClError(std::string("OpenCL platforms exist but expose no device; ") + kInstallHint);
  return out;
}

int resolve_device(const std::string& spec, const std::vector<DeviceInfo>& devices, const std::string& what) {
  // "--device 3", "--device \"intel\"", or for a variable "ARCHWAVE_DEVICE=intel".
  const bool var = !what.empty() && what.back() == '=';
  const bool digits = !spec.empty() && spec.find_first_not_of("0123456789") == std::string::npos;
  const std::string label = var ? what + spec : digits ? what + " " + spec : what + " \"" + spec + "\"";
  if (digits) {
    if (spec.size() < 10) {
      int i = std::stoi(spec);
      if (i < int(devices.size())) return i;
    }
    throw ClError(label + ": no such OpenCL device; available:\n" + describe_devices(devices));
  }
  auto lower = [](std::string t) {
    for (char& c : t) c = char(std::tolower(static_cast<unsigned char>(c)));
    return t;
  };
  const std::string want = lower(spec);
  std::vector<DeviceInfo> hits;
  for (const auto& d : devices)
    if (!want.empty() && lower(d.platform + " " + d.name + " " + d.type + " " + d.version).find(want) != std::string::npos)
      hits.push_back(d);
  if (hits.size() == 1) return hits[0].index;
  // A platform's name outranks a device's: on an Intel Xeon, PoCL's device is named
  // "pthread-...-Intel(R) Xeon(R) ...", and "intel" must still name Intel's runtime (its
  // platform "Intel(R) OpenCL"), as it does on any other CPU.
  std::vector<DeviceInfo> by_platform;
  for (const auto& d : hits)
    if (lower(d.platform).find(want) != std::string::npos) by_platform.push_back(d);
  if (by_platform.size() == 1) return by_platform[0].index;
  if (hits.empty())
    throw ClError(label + ": no OpenCL device's platform, name, type or version contains it; available:\n" +
                  describe_devices(devices));
  throw ClError(label + " matches " + std::to_string(hits.size()) + " devices; give a longer name or the index:\n" +
                describe_devices(hits));
}

std::string describe_devices(const std::vector<DeviceInfo>& devices) {
  std::ostringstream s;
  for (const auto& d : devices) {
    s << "[" << d.index << "] " << d.name << "  (" << d.type << ", " << d.platform << ", " << d.version
      << ", " << d.compute_units << " compute units, " << format_bytes(d.global_mem) << " memory, "
      << format_bytes(d.max_alloc) << " max allocation)\n";
  }
  return s.str();
}

ClRuntime::ClRuntime(int device_index) {
  auto devices = list_devices();
  if (device_index == kDefaultDevice) {
    const char* env = std::getenv("ARCHWAVE_DEVICE");
    device_index = env && *env ? resolve_device(env, devices, "ARCHWAVE_DEVICE=") : 0;
  }
  if (device_index < 0 || device_index >= int(devices.size())) {
    throw ClError("--device " + std::to_string(device_index) + ": no such OpenCL device; available:\n" +
                  describe_devices(devices));
  }
  info_ = devices[size_t(device_index)];
  try {
    context_ = cl::Context(info_.device);
    queue_ = cl::CommandQueue(context_, info_.device);
  } catch (const cl::Error& e) {
    throw ClError("cannot open OpenCL device [" + std::to_string(device_index) + "] " + info_.name + ": " +
                  e.what() + " (" + cl_error_name(e.err()) + ")");
  }
}

std::string device_build_options(const DeviceInfo& device, const std::string& options) {
  // Division and sqrt correctly rounded wherever the device can (OpenCL 1.2 §5.6.4.2; without
  // the option §7.4 allows 2.5 ulp for x / y and 3 ulp for sqrt). The kernels are held to
  // compute what the host scalar path computes, and the host divides and takes roots correctly
  // rounded. Why it matters: on an H200 (driver 580, 2026-12-04) the Fresnel and refraction
  // probes came out 6e-5 and 9e-5 off the host where a difference cancels: near the zero of
  // (c - g) / (c + g), one ulp of g is 3e-5 of a 2e-3 difference. PoCL offers the option (and
  // divided correctly rounded anyway); Intel's CPU runtime does not offer it.
  if (!device.correctly_rounded_divide_sqrt || options.find("-cl-fp32-correctly-rounded-divide-sqrt") != std::string::npos)
    return options;
  return options + (options.empty() ? "" : " ") + "-cl-fp32-correctly-rounded-divide-sqrt";
}

cl::Program ClRuntime::build(const std::string& source, const std::string& requested, double* seconds) {
  std::string options = device_build_options(info_, requested);
  // Development aid: extra build options, e.g. -g so that a profile of Intel's JIT code maps to
  // source lines (scripts/intel_jit_profile.py --lines; docs/cli.md). Part of the cache key.
  if (const char* extra = std::getenv("ARCHWAVE_CL_OPTIONS"); extra && *extra) options += std::string(" ") + extra;
  auto t0 = std::chrono::steady_clock::now();
  auto done = [&](cl::Program p) {
    if (seconds) *seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return p;
  };
  // The compiled program from the disk cache (host/cl/kernel_cache.h), on every device whose
  // runtime does not cache its own: not on PoCL, which does ($POCL_CACHE_DIR), and where
  // loading its binary would only add a step.
  const bool pocl = info_.platform.find("Portable Computing Language") != std::string::npos;
  KernelCache cache(pocl ? std::string() : kernel_cache_dir(),
                    info_.platform + "\n" + info_.name + "\n" + info_.version + "\n" + info_.driver + "\n" +
                        options + "\n" + source);
  last_build_ = cache.enabled() ? "compiled (binary cache miss)" : pocl ? "PoCL's cache" : "compiled (binary cache off)";
  std::vector<unsigned char> binary;
  if (cache.load(&binary)) {
    try {
      cl::Program cached(context_, {info_.device}, cl::Program::Binaries{binary});
      cached.build({info_.device}, options.c_str());
      last_build_ = "binary cache hit";
      return done(cached);
    } catch (const cl::Error&) {
      // A binary the runtime refuses (an update it did not announce in its versions): compile.
      last_build_ = "compiled (cached binary refused)";
    }
  }
  cl::Program program(context_, source);
  try {
    program.build({info_.device}, options.c_str());
  } catch (const cl::Error& e) {
    std::string log;
    try {
      log = program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(info_.device);
    } catch (const cl::Error&) {
      log = "(no build log available)";
    }
    throw ClError("OpenCL program build failed on " + info_.name + " (" + cl_error_name(e.err()) +
                  ") with options \"" + options + "\"; build log:\n" + annotate_build_log(source, log));
  }
  // Development aid: the compiler's warnings of a successful build (PoCL only prints their count).
  if (const char* v = std::getenv("ARCHWAVE_BUILD_LOG"); v && *v && std::string(v) != "0") {
    try {
      std::cerr << "OpenCL build log (" << info_.name << "):\n"
                << program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(info_.device) << "\n";
    } catch (const cl::Error&) {
    }
  }
  if (cache.enabled()) {
    std::string why;
    try {
      auto binaries = program.getInfo<CL_PROGRAM_BINARIES>();
      if (binaries.size() == 1) why = cache.store(binaries[0]);
    } catch (const cl::Error& e) {
      why = std::string("the runtime gave no binary (") + cl_error_name(e.err()) + ")";
    }
    if (!why.empty())
      std::cerr << "archwave: warning: kernel binary cache: " << why
                << " (the next render compiles again; $ARCHWAVE_KERNEL_CACHE names another directory, 0 turns it off)\n";
  }
  return done(program);
}

cl::Buffer ClRuntime::buffer(const char* what, size_t bytes, cl_mem_flags flags, const void* init) {
  size_t n = bytes == 0 ? 4 : bytes;
  if (n > info_.max_alloc) {
    throw ClError(std::string("buffer '") + what + "' needs " + format_bytes(n) + " but " + info_.name +
                  " allows at most " + format_bytes(info_.max_alloc) +
                  " in one allocation; reduce the image size or the scene, or pick another --device");
  }
  // The device's memory as a whole: a render that would not fit is refused with the sizes
  // before the allocation that would fail (or, on a CPU device, before the host is driven
  // into swap or the kernel's OOM killer).
  if (info_.global_mem > 0 && allocated_bytes_ + n > info_.global_mem) {
    throw ClError(std::string("buffer '") + what + "' needs " + format_bytes(n) + " on top of " +
                  format_bytes(allocated_bytes_) + " already allocated, but " + info_.name + " has " +
                  format_bytes(info_.global_mem) +
                  " of global memory; reduce the image size, the path pool (--pool) or the scene, or pick another --device");
  }
  try {
    cl::Buffer b = init && bytes ? cl::Buffer(context_, flags | CL_MEM_COPY_HOST_PTR, n, const_cast<void*>(init))
                                 : cl::Buffer(context_, flags, n);
    allocated_bytes_ += n;
    return b;
  } catch (const cl::Error& e) {
    throw ClError(std::string("cannot allocate buffer '") + what + "' of " + format_bytes(n) + " on " +
                  info_.name + ": " + cl_error_name(e.err()));
  }
}

}  // namespace aw
