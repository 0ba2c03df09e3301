// Helpers shared by the render tests.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <string>

namespace aw_test {

// Writes `json` to a new scene file named after `prefix`, this process and a counter, and
// returns its path. Unique per process: ctest runs test cases as parallel processes, and
// fixed names raced.
inline std::string write_temp_scene(const std::string& prefix, const std::string& json) {
  static int n = 0;
  std::string path = testing::TempDir() + "/" + prefix + "_" + std::to_string(getpid()) + "_" + std::to_string(n++) + ".json";
  std::ofstream(path) << json;
  return path;
}

}  // namespace aw_test
