// OpenCL device selection, program builds and buffers, with errors a user can act on.
#pragma once

#define CL_HPP_TARGET_OPENCL_VERSION 120
#define CL_HPP_MINIMUM_OPENCL_VERSION 120
#define CL_HPP_ENABLE_EXCEPTIONS
#include <CL/opencl.hpp>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace aw {

// Any OpenCL problem: no platform, bad device index, build failure (with the log), an
// allocation the device cannot hold. what() is the complete user-facing message.
class ClError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct DeviceInfo {
  int index = 0;  // global index across platforms, what --device takes
  std::string platform;
  std::string name;
  std::string type;  // "CPU", "GPU", ...
  std::string version;
  std::string driver;  // CL_DRIVER_VERSION (what the device-speed cache is keyed on, with the rest)
  unsigned compute_units = 0;
  // CL_DEVICE_NATIVE_VECTOR_WIDTH_FLOAT: floats per SIMD register (8 with AVX2, 16 with
  // AVX-512 on a CPU); what the lane program's narrow stages are built at (wavefront.cpp).
  unsigned native_float_width = 0;
  uint64_t global_mem = 0;
  uint64_t max_alloc = 0;
  // CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT of CL_DEVICE_SINGLE_FP_CONFIG: the device can divide
  // and take square roots correctly rounded when a program asks (device_build_options).
  bool correctly_rounded_divide_sqrt = false;
  cl::Device device;
};

// All devices of all platforms, in platform order. Throws ClError (with how to install PoCL)
// when there is no OpenCL platform at all.
std::vector<DeviceInfo> list_devices();
std::string describe_devices(const std::vector<DeviceInfo>& devices);

// What --device names: an index from --list-devices ("1"), or a case-insensitive substring of
// the platform, device name, type and version ("pocl": PoCL's version string names it;
// "intel", "gpu") that matches exactly one device. Throws ClError naming `what` (the flag or
// variable) and the value, listing the devices when the index is out of range or the
// substring matches none or several (then it lists those).
int resolve_device(const std::string& spec, const std::vector<DeviceInfo>& devices,
                   const std::string& what = "--device");

// The device a render gets when none is asked for: $ARCHWAVE_DEVICE (an index or a name, as
// --device takes; the test suite sets "pocl", the device it is defined on, so that another
// OpenCL runtime installed beside PoCL does not change what the tests run on), else index 0.
// The CLI does not pass it blind: with no --device it resolves the fastest device first
// (host/render/device_choice.h).
constexpr int kDefaultDevice = -1;

// The options a program is built with on `device`: `options` plus
// -cl-fp32-correctly-rounded-divide-sqrt where the device offers it, so that every device
// divides and takes roots as the host does (docs/devices.md, "The tests on that GPU").
std::string device_build_options(const DeviceInfo& device, const std::string& options);

// One device with a context and an in-order queue.
class ClRuntime {
 public:
  // device_index: from --list-devices, or kDefaultDevice.
  explicit ClRuntime(int device_index);
  const DeviceInfo& info() const { return info_; }
  cl::Context& context() { return context_; }
  cl::CommandQueue& queue() { return queue_; }

  // Builds a program from assembled source; on failure throws ClError carrying the build log.
  // Adds the wall time of the build (cold or cached) to *seconds when given, so that a caller
  // building several programs gets their sum.
  // Uses the disk cache of compiled programs (host/cl/kernel_cache.h) where the runtime has
  // none of its own.
  // The device's own options are added (device_build_options).
  cl::Program build(const std::string& source, const std::string& options, double* seconds = nullptr);
  // How the last build() got its program: "binary cache hit", "compiled (binary cache miss)",
  // "PoCL's cache" (PoCL compiles or reuses its own), ... (the render stats show it).
  const std::string& last_build() const { return last_build_; }

  // A device buffer of `bytes` (at least 1 byte, OpenCL forbids empty buffers). Refuses,
  // with the sizes, what exceeds the device's largest single allocation. `what` names the
  // buffer in messages.
  cl::Buffer buffer(const char* what, size_t bytes, cl_mem_flags flags = CL_MEM_READ_WRITE,
                    const void* init = nullptr);
  // Bytes of every buffer made by buffer() so far (released ones included): the device
  // memory a render asked for, reported in the stats.
  uint64_t allocated_bytes() const { return allocated_bytes_; }

 private:
  DeviceInfo info_;
  std::string last_build_;
  uint64_t allocated_bytes_ = 0;
  cl::Context context_;
  cl::CommandQueue queue_;
};

std::string cl_error_name(cl_int err);
std::string format_bytes(uint64_t bytes);

}  // namespace aw
