// Which OpenCL device the CLI renders on when no --device is given (issue 12, part 1).
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "host/cl/cl_runtime.h"

namespace aw {

struct DeviceChoice {
  int index = 0;
  std::string how;  // one line for the stats: why this device
};

// One device's measured speed, as the cache holds it.
struct DeviceSpeed {
  std::string key;  // platform | name | version | driver | archwave version
  double msamples_per_s = 0.0;  // 0: the measurement failed (reason in `error`)
  std::string error;
  std::string measured;  // UTC date and time of the measurement
};

// The order of choice: $ARCHWAVE_DEVICE when set (an index or a name, as --device takes);
// else the only device; else the fastest by a measurement of archwave's own wavefront on a small
// built-in Cornell box (the default scene's content, 256x256, 8 spp, best of 3 after a warm-up
// that builds the kernels), taken once per device and cached in `cache_path` so later renders
// pay nothing. A device whose key (platform, name, version, driver, archwave version) is not in
// the cache is measured, and the cache rewritten atomically (one that cannot be written is a
// warning: the next render measures again); `remeasure` measures all again.
// A device that fails the measurement (a build error, say) is never chosen; the log says why.
// Progress goes to `log`. Throws ClError only when no device works at all.
DeviceChoice choose_default_device(const std::string& cache_path, bool remeasure, std::ostream& log);

// $XDG_CACHE_HOME/archwave/device-speed.json, else $HOME/.cache/archwave/device-speed.json;
// $ARCHWAVE_DEVICE_CACHE overrides both (the tests point it into their own directory).
std::string default_device_cache_path();

// What a measured speed is valid for: platform, device, versions, driver, archwave's version and
// a hash of the wavefront's kernel source (embedded), so that changed kernels measure again.
std::string device_speed_key(const DeviceInfo& d);
// FNV-1a hash (host/cl/kernel_cache.h) of the assembled wavefront source from kernel_dir
// ("" = the embedded copy), as 16 hex digits.
std::string kernel_source_hash(const std::string& kernel_dir);

// The measurement: the wavefront's Msamples/s on device `index` (path tracing only, BVH and
// kernel build excluded). Throws what the render throws.
double measure_device_speed(int index);

// The choice among measured devices: the fastest whose measurement did not fail (ties: the
// lower index). Throws ClError when none passed. `cache_path` is only named in the text.
DeviceChoice pick_fastest(const std::vector<DeviceInfo>& devices, const std::vector<DeviceSpeed>& speeds,
                          const std::string& cache_path);

// The cache file: {"devices": [{"key", "msamples_per_s", "error", "measured"}, ...]}. A missing
// file reads as empty; one that does not parse also reads as empty, with a warning naming it in
// `log` (the devices are then measured again and the file rewritten).
std::vector<DeviceSpeed> read_device_cache(const std::string& path, std::ostream& log);
void write_device_cache(const std::string& path, const std::vector<DeviceSpeed>& speeds);

}  // namespace aw
