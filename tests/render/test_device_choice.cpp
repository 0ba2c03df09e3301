// The CLI's default device (issue 12): $ARCHWAVE_DEVICE first, else the fastest measured
// device, from a cache keyed on the device and driver (host/render/device_choice.h).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "host/render/device_choice.h"

namespace {

aw::DeviceInfo fake(int index, const std::string& name) {
  aw::DeviceInfo d;
  d.index = index;
  d.platform = "Platform " + name;
  d.name = name;
  d.version = "OpenCL 3.0";
  d.driver = "1.0";
  return d;
}

aw::DeviceSpeed speed(const aw::DeviceInfo& d, double s, const std::string& error = "") {
  aw::DeviceSpeed e;
  e.key = aw::device_speed_key(d);
  e.msamples_per_s = s;
  e.error = error;
  return e;
}

std::string temp_path(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / ("archwave-device-choice-" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

// Unsets $ARCHWAVE_DEVICE (the suite sets it) for one test, and restores it.
struct NoDeviceVariable {
  std::string saved;
  bool had = false;
  NoDeviceVariable() {
    if (const char* v = std::getenv("ARCHWAVE_DEVICE")) had = true, saved = v;
    unsetenv("ARCHWAVE_DEVICE");
  }
  ~NoDeviceVariable() {
    if (had) setenv("ARCHWAVE_DEVICE", saved.c_str(), 1);
  }
};

TEST(DefaultDevice, FastestMeasuredDeviceWinsAndAFailedOneNever) {
  std::vector<aw::DeviceInfo> devs = {fake(0, "intel"), fake(1, "pocl"), fake(2, "gpu")};
  auto c = aw::pick_fastest(devs, {speed(devs[0], 0.3), speed(devs[1], 0.5), speed(devs[2], 9.0, "build failed")}, "C");
  EXPECT_EQ(c.index, 1);
  EXPECT_NE(c.how.find("[0] 0.3, [1] 0.5, [2] failed"), std::string::npos) << c.how;
  // Ties go to the lower index; a driver update changes the key, so the old figure no longer counts.
  EXPECT_EQ(aw::pick_fastest(devs, {speed(devs[0], 0.5), speed(devs[1], 0.5)}, "C").index, 0);
  aw::DeviceInfo updated = devs[1];
  updated.driver = "2.0";
  EXPECT_NE(aw::device_speed_key(updated), aw::device_speed_key(devs[1]));
  EXPECT_EQ(aw::pick_fastest({devs[0], updated}, {speed(devs[0], 0.3), speed(devs[1], 0.5)}, "C").index, 0);
  EXPECT_THROW(aw::pick_fastest(devs, {speed(devs[0], 0.0, "x")}, "C"), aw::ClError);
}

// The key names the kernels it measured: the embedded source's hash (the same as the source
// tree's), which changes with any kernel file.
TEST(DefaultDevice, KeyFollowsTheKernelSource) {
  auto d = fake(0, "x");
  const std::string tree = std::string(ARCHWAVE_SOURCE_DIR) + "/kernels";
  const std::string h = aw::kernel_source_hash("");
  EXPECT_EQ(h.size(), 16u);
  EXPECT_EQ(h, aw::kernel_source_hash(tree));
  EXPECT_NE(aw::device_speed_key(d).find(" | kernels " + h), std::string::npos) << aw::device_speed_key(d);
  namespace fs = std::filesystem;
  const std::string copy = temp_path("kernels_copy");
  fs::remove_all(copy);
  fs::copy(tree, copy, fs::copy_options::recursive);
  {
    std::ofstream f(copy + "/common/rng.h", std::ios::app);
    f << "\n// changed\n";
  }
  EXPECT_NE(aw::kernel_source_hash(copy), h);
  fs::remove_all(copy);
}

TEST(DefaultDevice, CacheRoundTripsAndABrokenFileIsMeasuredAgainWithAWarning) {
  std::string path = temp_path("speeds.json");
  auto d = fake(0, "x");
  aw::write_device_cache(path, {speed(d, 1.25), speed(fake(1, "y"), 0.0, "no")});
  std::ostringstream log;
  auto back = aw::read_device_cache(path, log);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0].key, aw::device_speed_key(d));
  EXPECT_DOUBLE_EQ(back[0].msamples_per_s, 1.25);
  EXPECT_EQ(back[1].error, "no");
  EXPECT_TRUE(log.str().empty());
  std::ofstream(path) << "{\"devices\": [ {\"key\": 3";
  EXPECT_TRUE(aw::read_device_cache(path, log).empty());
  EXPECT_NE(log.str().find("the device-speed cache " + path + " cannot be read"), std::string::npos) << log.str();
  EXPECT_TRUE(aw::read_device_cache(temp_path("missing.json"), log).empty());
  EXPECT_THROW(aw::write_device_cache("/proc/no/such/dir/speeds.json", {}), aw::ClError);
}

TEST(DefaultDevice, ArchwaveDeviceVariableDecides) {
  // The suite's own setting (pocl): no measurement, and the stats say why.
  ASSERT_NE(std::getenv("ARCHWAVE_DEVICE"), nullptr);
  std::ostringstream log;
  auto c = aw::choose_default_device(temp_path("unused.json"), false, log);
  EXPECT_EQ(c.how, std::string("$ARCHWAVE_DEVICE=") + std::getenv("ARCHWAVE_DEVICE"));
  EXPECT_NE(aw::list_devices()[size_t(c.index)].version.find("PoCL"), std::string::npos);
  EXPECT_TRUE(log.str().empty());
}

TEST(DefaultDevice, MeasuresEveryDeviceOnceThenReadsTheCache) {
  NoDeviceVariable unset;
  auto devices = aw::list_devices();
  std::string path = temp_path("measured.json");
  std::filesystem::remove(path);
  std::ostringstream log;
  auto c = aw::choose_default_device(path, false, log);
  if (devices.size() == 1) {
    EXPECT_EQ(c.how, "the only OpenCL device");
    EXPECT_GT(aw::measure_device_speed(0), 0.0);  // the measurement itself still works
    return;
  }
  auto cached = aw::read_device_cache(path, log);
  ASSERT_EQ(cached.size(), devices.size()) << log.str();
  for (const auto& s : cached) EXPECT_TRUE(s.error.empty() ? s.msamples_per_s > 0 : true) << s.key;
  EXPECT_EQ(c.index, aw::pick_fastest(devices, cached, path).index);
  std::ostringstream again;
  EXPECT_EQ(aw::choose_default_device(path, false, again).index, c.index);
  EXPECT_TRUE(again.str().empty()) << again.str();  // nothing measured the second time
}

}  // namespace
