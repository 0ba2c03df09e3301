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

#include "host/film/image_io.h"
#include "host/render/render.h"
#include "host/scene/scene.h"

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

// Render options without the progress line.
inline aw::RenderOptions quiet_options() {
  aw::RenderOptions o;
  o.progress = false;
  return o;
}

// The mean over pixels and channels of a render's per-pixel averages.
inline double image_mean(const aw::RenderResult& r) {
  double s = 0.0;
  for (size_t p = 0; p < r.count.size(); ++p)
    for (int c = 0; c < 3; ++c) s += double(r.sum[p * 3 + size_t(c)]) / double(r.count[p]);
  return s / double(r.count.size() * 3);
}

inline std::string source_path(const std::string& rel) { return std::string(ARCHWAVE_SOURCE_DIR) + "/" + rel; }

// A scene of the repository (with -D overrides), per pixel: the wavefront kernels against the
// scalar path (the same stage code over Embree's rays), and the specialised kernels against
// the generic build. 99% of pixels within 1e-3 relative (the rest: paths that a last-bit
// difference of the two ray casters sends elsewhere), means within 1e-3, no sample discarded.
inline void expect_kernel_matches_scalar(const std::string& scene_file, const std::vector<std::string>& overrides) {
  aw::Scene scene = aw::load_scene(source_path(scene_file), overrides);
  aw::RenderOptions o;
  o.progress = false;
  aw::RenderResult w = aw::render_wavefront(scene, o);
  aw::RenderResult s = aw::render_scalar(scene, o);
  aw::ImageDiff d = aw::compare_images(w.image(scene), s.image(scene), 1e-3, 1e-4);
  std::printf("%s: %.4f%% of pixels within 1e-3, means %.6f vs %.6f\n", scene_file.c_str(), d.frac_pixels_within * 100,
              d.mean_a, d.mean_b);
  EXPECT_GE(d.frac_pixels_within, 0.99) << scene_file;
  EXPECT_LE(d.rel_mean_diff, 1e-3) << scene_file;
  EXPECT_EQ(w.stats.bad_samples, 0u) << scene_file;
  EXPECT_EQ(s.stats.bad_samples, 0u) << scene_file;
  aw::RenderOptions g = o;
  g.generic_kernels = true;
  aw::RenderResult wg = aw::render_wavefront(scene, g);
  aw::ImageDiff dg = aw::compare_images(w.image(scene), wg.image(scene), 1e-3, 1e-4);
  EXPECT_GE(dg.frac_pixels_within, 0.99) << scene_file << " (generic kernels)";
}

}  // namespace aw_test
