// Helpers shared by the render tests.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "host/render/render.h"

namespace aw_test {

// Lambert's formula for the irradiance at the origin, normal +y, from a polygon of uniform
// radiance (its vertices v): L/2 sum_i theta_i (n . u_i), theta_i the angle edge i subtends and
// u_i the unit normal of the plane through the origin and that edge (Arvo 1995, "Applications
// of Irradiance Tensors...", Sec. 3).
inline double polygon_irradiance(const std::vector<glm::dvec3>& v, double radiance) {
  double sum = 0.0;
  for (size_t i = 0; i < v.size(); ++i) {
    glm::dvec3 a = glm::normalize(v[i]), b = glm::normalize(v[(i + 1) % v.size()]);
    double theta = std::acos(glm::clamp(glm::dot(a, b), -1.0, 1.0));
    glm::dvec3 u = glm::normalize(glm::cross(a, b));
    sum += theta * u.y;
  }
  return std::fabs(sum) * radiance / 2.0;
}

// Writes `json` to a new scene file named after `prefix`, this process and a counter, and
// returns its path. Unique per process: ctest runs test cases as parallel processes, and
// fixed names raced.
inline std::string write_temp_scene(const std::string& prefix, const std::string& json) {
  static int n = 0;
  std::string path = testing::TempDir() + "/" + prefix + "_" + std::to_string(getpid()) + "_" + std::to_string(n++) + ".json";
  std::ofstream(path) << json;
  return path;
}

// Two renders of the same scene with independent random numbers (other seeds, or another
// sampler): the z statistic of the mean per-pixel difference (summed over RGB). Pixels are
// independent, so the mean of N differences is ~normal with standard error sd / sqrt(N).
// Prints the figures under `what`.
inline double mean_difference_z(const aw::RenderResult& a, const aw::RenderResult& b, const char* what) {
  size_t n = a.count.size();
  double sum = 0.0, sum2 = 0.0;
  for (size_t p = 0; p < n; ++p) {
    double d = 0.0;
    for (int c = 0; c < 3; ++c) d += a.sum[p * 3 + c] / a.count[p] - b.sum[p * 3 + c] / b.count[p];
    sum += d;
    sum2 += d * d;
  }
  double mean = sum / n, sd = std::sqrt(std::max(0.0, sum2 / n - mean * mean));
  double z = mean / (sd / std::sqrt(double(n)));
  std::printf("%s: mean difference %.3g (sd %.3g, z %.2f)\n", what, mean, sd, z);
  return z;
}

}  // namespace aw_test
