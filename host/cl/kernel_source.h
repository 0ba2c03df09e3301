// Kernel sources: the files under kernels/ are embedded into the binary at build time
// (cmake/embed_kernels.cmake) and can be read from disk instead while developing.
#pragma once

#include <string>

namespace aw {

struct EmbeddedKernelFile {
  const char* path;  // relative to kernels/, e.g. "integrator/kernels.cl"
  const char* text;
};
extern const EmbeddedKernelFile kEmbeddedKernelFiles[];  // terminated by {nullptr, nullptr}

// Where kernel sources come from: "" = the embedded copy, otherwise a kernels/ directory.
// Defaults to $ARCHWAVE_KERNEL_DIR when set (or the source tree when built with
// ARCHWAVE_KERNELS_FROM_DISK=ON), so kernels can be edited without rebuilding the host.
std::string default_kernel_dir();

// Returns `entry` (a path relative to kernels/) with every `#include "..."` of another kernel
// file expanded in place, once per file, each file framed by `#line` markers so compiler
// messages name kernels/<file>:<line>. Throws std::runtime_error naming a missing file.
std::string assemble_kernel_source(const std::string& entry, const std::string& kernel_dir);

}  // namespace aw
