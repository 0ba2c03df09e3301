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

// The file and line that line `line` (1-based) of an assembled source comes from, as
// "kernels/<file>:<line>", read off the source's `#line` markers; "" before the first marker
// or past the end.
std::string assembled_source_location(const std::string& source, long line);

// A build log with every position a compiler gave in the raw source ("<kernel>:3:10", the
// form NVIDIA's OpenCL compiler writes: measured on an H200, driver 580, it ignores `#line`)
// followed by where that line comes from: "<kernel>:3:10 [kernels/broken.cl:2:10]". Positions
// already given as a file name (PoCL, Intel: they honour `#line`) are left as they are.
std::string annotate_build_log(const std::string& source, const std::string& log);

}  // namespace aw
