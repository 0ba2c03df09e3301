// A disk cache of compiled OpenCL programs (device binaries), so that a render on a device
// whose runtime keeps no cache of its own does not compile the kernels again every time.
//
// Why: Intel's CPU runtime compiles the wavefront's program from source on every run (2.4 s
// for the Cornell box's specialised build, 4.4 s for the glass/GGX spheres on 2 cores), longer
// than the render of a preview; PoCL caches its compiled kernels itself ($POCL_CACHE_DIR).
// Intel's runtime returns a final, target-specific binary from clGetProgramInfo
// (CL_PROGRAM_BINARIES) and accepts it back through clCreateProgramWithBinary without compiling
// (its developer reference, "Final Kernel Binary Save/Load"); so does every conformant runtime
// in some form. Measured in docs/performance.md ("Kernel binary cache").
//
// Where: $ARCHWAVE_KERNEL_CACHE (a directory; "0" or "off" turns the cache off), else
// $XDG_CACHE_HOME/archwave/kernels, else $HOME/.cache/archwave/kernels. One file per program:
// its name is a hash of the key (platform, device, device and driver versions, build options,
// the whole source); the file repeats a second hash of the key and carries the binary's size
// and checksum, so a stale, truncated or foreign file is a miss, never a wrong program. Files
// are written to a unique temporary name and renamed, so concurrent renders (ctest -j) never
// read half a file. A cache that cannot be read or written costs a compile, not the render.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace aw {

// The cache directory by the rule above; "" when the cache is off.
std::string kernel_cache_dir();

// FNV-1a over n bytes (Fowler, Noll & Vo; 64-bit offset basis and prime), continuing from `h`.
// Stable across runs and builds, unlike std::hash.
uint64_t fnv1a64(const void* data, size_t n, uint64_t h = 0xcbf29ce484222325ull);
inline uint64_t fnv1a64(const std::string& s, uint64_t h = 0xcbf29ce484222325ull) {
  return fnv1a64(s.data(), s.size(), h);
}
// v as 16 lower-case hex digits.
std::string hex16(uint64_t v);

class KernelCache {
 public:
  // `key` names everything the binary depends on; dir "" = off.
  KernelCache(std::string dir, const std::string& key);
  bool enabled() const { return !dir_.empty(); }
  const std::string& path() const { return path_; }

  // The cached binary, or false (no file, or one that fails any check).
  bool load(std::vector<unsigned char>* binary) const;
  // Writes the binary; returns "" or why it could not (the caller warns and goes on).
  std::string store(const std::vector<unsigned char>& binary) const;

 private:
  std::string dir_, path_;
  uint64_t check_ = 0;  // the key's second hash, stored in the file
};

}  // namespace aw
