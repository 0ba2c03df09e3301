// Does anything beat area sampling for disk lights? (issue 11: "for disks, measure whether
// anything beats area sampling"). The candidate: the disk's bounding square sampled by solid
// angle with the quad lights' spherical-rectangle code (kernels/lights/lights.h, Urena et al.
// 2013), a point outside the disk counting zero (no rejection loop, so a sample stays a pure
// function of its two random numbers and its density is 1/S over the disk's part of the
// square's solid angle). Against: area sampling of the disk (concentric map, Shirley & Chiu
// 1997), what lights.h does today.
//
// The estimate: irradiance at a point p a height h below a one-sided unit disk (radius 1,
// facing p), offset sideways by x, on a surface facing the disk: E = ∫ L cos(theta_p) dw with
// L = 1. For each estimator, N = 2^20 samples (std::mt19937, fixed seed): its mean (both must
// agree with each other within 5 standard errors, checked), its relative variance
// var / mean^2 per sample, and its time per sample on one host core (the kernels' code
// compiled as C++). Efficiency = 1 / (relative variance x time); the table prints the square's
// efficiency over area sampling's (> 1: the square wins).
//
// Usage: bench_disk_sampling [--out FILE]   (docs/performance.md, "Disk lights")
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "kernels/common/sampling.h"
#include "kernels/lights/lights.h"

namespace {

struct Stats {
  double mean = 0, relvar = 0, ns = 0;
};

// One estimator over n samples: f(u) -> the sample's value.
template <class F>
Stats run(F f, int n) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<float> uni(0.0f, 1.0f);
  std::vector<float2> us(static_cast<size_t>(n));
  for (auto& u : us) u = make_float2(std::min(uni(rng), 0.99999994f), std::min(uni(rng), 0.99999994f));
  double s = 0, s2 = 0;
  auto t0 = std::chrono::steady_clock::now();
  for (const float2& u : us) {
    double v = f(u);
    s += v;
    s2 += v * v;
  }
  double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  Stats st;
  st.mean = s / n;
  double var = s2 / n - st.mean * st.mean;
  st.relvar = var / (st.mean * st.mean);
  st.ns = secs * 1e9 / n;
  return st;
}

}  // namespace

int main(int argc, char** argv) {
  std::string out;
  for (int i = 1; i < argc; ++i)
    if (!std::strcmp(argv[i], "--out") && i + 1 < argc) out = argv[++i];
  const int n = 1 << 20;
  const float3 c = make_float3(0.0f, 0.0f, 0.0f), nl = make_float3(0.0f, 0.0f, -1.0f);  // faces -z
  const float r = 1.0f, area = M_PI_F;
  std::string text =
      "| height h / radius | offset x / radius | square's solid angle (sr) | area: relative variance | "
      "square by solid angle: relative variance | area: ns/sample | square: ns/sample | "
      "square's efficiency ÷ area's |\n|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  bool ok = true;
  for (float h : {0.05f, 0.2f, 0.5f, 1.0f, 2.0f, 5.0f})
    for (float x : {0.0f, 1.5f}) {
      const float3 p = make_float3(x, 0.0f, -h), np = make_float3(0.0f, 0.0f, 1.0f);
      auto area_est = [&](float2 u) -> double {
        float2 d = sample_concentric_disk(u);
        float3 y = c + r * make_float3(d.x, d.y, 0.0f);
        float3 w = y - p;
        float d2 = dot(w, w);
        w = w / std::sqrt(d2);
        float cp = dot(w, np), cl = -dot(w, nl);
        return (cp > 0.0f && cl > 0.0f) ? double(cp * cl / d2 * area) : 0.0;
      };
      SphRect sq = sph_rect_make(make_float3(-r, -r, 0.0f), make_float3(2 * r, 0, 0), make_float3(0, 2 * r, 0), p);
      auto square_est = [&](float2 u) -> double {
        // Built per sample, as light_sample builds it per shading point: its cost is timed.
        SphRect q = sph_rect_make(make_float3(-r, -r, 0.0f), make_float3(2 * r, 0, 0), make_float3(0, 2 * r, 0), p);
        float3 y = sph_rect_sample(&q, u);
        if (y.x * y.x + y.y * y.y > r * r) return 0.0;
        float3 w = normalize(y - p);
        float cp = dot(w, np);
        return cp > 0.0f ? double(cp * q.S) : 0.0;
      };
      Stats a = run(area_est, n), b = run(square_est, n);
      double se = std::sqrt((a.relvar * a.mean * a.mean + b.relvar * b.mean * b.mean) / n);
      if (std::fabs(a.mean - b.mean) > 5.0 * se) {
        std::fprintf(stderr, "bench_disk_sampling: means disagree at h %g x %g: %.6g vs %.6g (5 se %.3g)\n", h, x,
                     a.mean, b.mean, 5 * se);
        ok = false;
      }
      char row[512];
      std::snprintf(row, sizeof row, "| %g | %g | %.3g | %.3g | %.3g | %.3g | %.3g | %.3g |\n", h, x, sq.S, a.relvar,
                    b.relvar, a.ns, b.ns, (a.relvar * a.ns) / (b.relvar * b.ns));
      text += row;
    }
  std::fputs(text.c_str(), stdout);
  if (!out.empty()) {
    std::FILE* f = std::fopen(out.c_str(), "w");
    if (!f || std::fputs(text.c_str(), f) < 0 || std::fclose(f) != 0) {
      std::fprintf(stderr, "bench_disk_sampling: cannot write %s\n", out.c_str());
      return 5;
    }
  }
  return ok ? 0 : 1;
}
