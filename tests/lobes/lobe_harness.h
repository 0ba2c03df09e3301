// Test harness shared by every lobe test (tests/lobes, tests/lobes_long). Header-only, C++17,
// GoogleTest. The checks follow Mitsuba 3's and pbrt-v4's BSDF tests; the lobe contract they
// check is kernels/lobes/lobe.h.
//
// USAGE
//   #include "tests/lobes/lobe_harness.h"
//   using namespace aw::lobe_test;
//
//   // 1. Bind a lobe's parameters into three callables (local frame, +z = normal):
//   LobeFns fns{
//       [=](float3 wo, float3 wi) { return lobe_x_eval(params, wo, wi); },   // f * |cos_i|
//       [=](float3 wo, float3 wi) { return lobe_x_pdf(params, wo, wi); },    // solid angle
//       [=](float3 wo, float2 u) { return lobe_x_sample(params, wo, u); }};
//   float3 wo = direction_from_theta_deg(60.0);        // or direction_from_cos_phi(z, phi)
//
//   // 2. Chi-square goodness of fit of `sample` against `pdf` over the WHOLE sphere:
//   ChiSquareConfig cfg;
//   cfg.samples = lobe_test_samples(1000000);          // 1e6 with ARCHWAVE_FULL_BUDGET=1, else 1e5
//   cfg.n_cases = 12;                                  // cases in this test: Sidak correction
//   ++cfg.seed;                                        // a distinct seed per case (independence)
//   cfg.expect_unit_mass = true;                       // pdf integrates to 1 (never fails)
//   EXPECT_TRUE(chi_square_passes(fns, wo, cfg));      // message: statistic, dof, p, worst cells
//                                                      // (ARCHWAVE_LOBE_VERBOSE=1 prints passes)
//   // Lobes too narrow for the whole-sphere bins (alpha ~ 0.01): the same test through a zoom
//   // that magnifies the lobe (see "Zoomed chi-square" below for the two zooms):
//   EXPECT_TRUE(chi_square_passes(lobe_zoomed(fns, wo), wo, cfg));   // cfg.bin_in_theta = true
//
//   // 3. The other checks (each returns a ::testing::AssertionResult with a readable message):
//   EXPECT_TRUE(sample_matches_eval_pdf(fns, wo, 10000, /*seed*/ 3));   // weight = eval/pdf, pdf
//   EXPECT_TRUE(eval_pdf_sample_finite(fns, 20000, 4));  // no NaN/Inf/negatives, incl. z = 0
//   EXPECT_TRUE(reciprocal(fns, 10000, 5));               // f(wo, wi) = f(wi, wo), reflection
//   EXPECT_TRUE(white_furnace(fns, wo, 200000, 6, /*lossless*/ true));  // E <= 1 (= 1)
//   AlbedoEstimate e = albedo_by_sampling(fns, wo, n, seed);  // + albedo_near(e, expected)
//   AlbedoEstimate q = albedo_by_quadrature(fns, wo);  // deterministic, smooth lobes only
//
//   // 4. Host vs device: a probe kernel under kernels/tests/ with the signature
//   //    __kernel void probe(uint n, __global const float* in, __global float* out)
//   //    (re-run `cmake -S . -B build` after adding a .cl so it is embedded):
//   std::vector<float> dev = run_device_probe("tests/probe_x.cl", "probe", in, 4, n_items);
//   EXPECT_TRUE(host_matches_device(host, dev, kHostDeviceRelTol, kHostDeviceAbsFloor, "what"));
//   // probe_column(v, stride, k) picks one output; host_matches_device_squared compares a
//   // sampled z = sqrt(1 - x^2 - y^2) through z^2 (see there why).
//
// SIGNIFICANCE. Every chi-square test case is run at alpha_case = 1 - (1 - 0.01)^(1/n_cases)
// (Sidak), so a whole test (all of its n_cases together) rejects a CORRECT lobe with
// probability 0.01. Seeds are fixed (std::mt19937), so a given build is deterministic: a
// failure does not come and go between runs, only when code changes.
//
// BUDGET. lobe_test_samples(full) = full when the environment has ARCHWAVE_FULL_BUDGET=1, else
// full / 10 (CI's default). Call it with the full count the issue asks for (>= 1e6 per case).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "host/cl/cl_runtime.h"
#include "host/cl/kernel_source.h"
#include "kernels/common/compat.h"
#include "kernels/lobes/lobe.h"

namespace aw {
namespace lobe_test {

// ------------------------------------------------------------------------------------------
// The lobe under test.
// ------------------------------------------------------------------------------------------
struct LobeFns {
  std::function<float3(float3 wo, float3 wi)> eval;       // f * |cos theta_i|
  std::function<float(float3 wo, float3 wi)> pdf;         // solid-angle density of sample
  std::function<LobeSample(float3 wo, float2 u)> sample;  // explicit random numbers
};

// ------------------------------------------------------------------------------------------
// Budget, random numbers, directions.
// ------------------------------------------------------------------------------------------
inline bool full_budget() {
  const char* v = std::getenv("ARCHWAVE_FULL_BUDGET");
  return v && std::string(v) == "1";
}

// `full` with ARCHWAVE_FULL_BUDGET=1, else full / 10 (at least 1).
inline size_t lobe_test_samples(size_t full) { return full_budget() ? full : std::max<size_t>(full / 10, 1); }

// Uniform floats in [0, 1) from the top 24 bits of mt19937 (std::uniform_real_distribution<float>
// can round up to 1.0 on some standard libraries; a lobe must never see u = 1).
class Uniform {
 public:
  explicit Uniform(uint32_t seed) : rng_(seed) {}
  float next() { return float(rng_() >> 8) * (1.0f / 16777216.0f); }
  float2 next2() {
    float a = next();
    float b = next();
    return make_float2(a, b);
  }

 private:
  std::mt19937 rng_;
};

// Unit direction with cos(theta) = z and azimuth phi (double math, rounded once to float).
inline float3 direction_from_cos_phi(double z, double phi) {
  z = std::min(1.0, std::max(-1.0, z));
  double s = std::sqrt(std::max(0.0, 1.0 - z * z));
  return make_float3(float(s * std::cos(phi)), float(s * std::sin(phi)), float(z));
}

// Direction at polar angle theta (degrees, from +z) and azimuth phi (degrees). The default
// azimuth is deliberately not a multiple of the bin width.
inline float3 direction_from_theta_deg(double theta_deg, double phi_deg = 33.0) {
  const double d2r = 3.14159265358979323846 / 180.0;
  double z = std::cos(theta_deg * d2r);
  if (theta_deg == 90.0) z = 0.0;  // cos(pi/2) in double is 6e-17, not the exact horizon
  return direction_from_cos_phi(z, phi_deg * d2r);
}

inline float3 uniform_sphere(float2 u) {
  return direction_from_cos_phi(1.0 - 2.0 * double(u.x), 2.0 * 3.14159265358979323846 * double(u.y));
}

inline std::string fmt3(float3 v) {
  char b[128];
  std::snprintf(b, sizeof b, "(%.9g, %.9g, %.9g)", double(v.x), double(v.y), double(v.z));
  return b;
}

// ------------------------------------------------------------------------------------------
// Statistics.
// ------------------------------------------------------------------------------------------

// Sidak: the per-case significance that keeps the family-wise rate at alpha for n independent
// cases, alpha_case = 1 - (1 - alpha)^(1/n).
inline double sidak_alpha(double alpha, int n_cases) {
  return 1.0 - std::pow(1.0 - alpha, 1.0 / double(std::max(1, n_cases)));
}

// Regularised upper incomplete gamma Q(a, x) = Gamma(a, x) / Gamma(a). Two classical expansions
// (as described in Numerical Recipes, 3rd ed., Sec. 6.2; written here from the formulas):
//  - x < a + 1: the power series gamma(a, x) = e^-x x^a sum_n x^n / (a (a+1) ... (a+n)),
//    which converges fast there; Q = 1 - P;
//  - otherwise: the continued fraction
//    Gamma(a, x) = e^-x x^a (1/(x+1-a-) 1(1-a)/(x+3-a-) 2(2-a)/(x+5-a-) ...),
//    evaluated with the modified Lentz method (Lentz 1976; Thompson & Barnett 1986).
inline double regularized_gamma_q(double a, double x) {
  if (!(a > 0.0) || x < 0.0 || std::isnan(x)) return std::numeric_limits<double>::quiet_NaN();
  if (x == 0.0) return 1.0;
  if (std::isinf(x)) return 0.0;
  const double log_prefactor = -x + a * std::log(x) - std::lgamma(a);
  const double eps = 1e-15;
  if (x < a + 1.0) {
    double term = 1.0 / a;
    double sum = term;
    for (int n = 1; n < 100000; ++n) {
      term *= x / (a + double(n));
      sum += term;
      if (std::fabs(term) < std::fabs(sum) * eps) break;
    }
    double p = sum * std::exp(log_prefactor);
    return std::min(1.0, std::max(0.0, 1.0 - p));
  }
  const double tiny = 1e-300;
  double b = x + 1.0 - a;
  double c = 1.0 / tiny;
  double d = 1.0 / b;
  double h = d;
  for (int i = 1; i < 100000; ++i) {
    double an = -double(i) * (double(i) - a);
    b += 2.0;
    d = an * d + b;
    if (std::fabs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1.0 / d;
    double delta = d * c;
    h *= delta;
    if (std::fabs(delta - 1.0) < eps) break;
  }
  return std::min(1.0, std::max(0.0, std::exp(log_prefactor) * h));
}

// P(X >= statistic) for X ~ chi-square with dof degrees of freedom: Q(dof/2, statistic/2).
inline double chi_square_p_value(double statistic, int dof) {
  if (dof <= 0) return 1.0;
  return regularized_gamma_q(0.5 * double(dof), 0.5 * statistic);
}

// Pearson's chi-square of observed against expected counts over discrete cells (a histogram
// the caller already binned: texels, lights), cells expecting fewer than min_expected pooled
// into one, the usual validity rule. Cells expecting 0 must be left out by the caller.
struct PooledChiSquare {
  double statistic = 0.0;
  int dof = -1;
  double p_value = 1.0;
};
inline PooledChiSquare pooled_chi_square(const std::vector<double>& observed, const std::vector<double>& expected,
                                         double min_expected = 5.0) {
  PooledChiSquare r;
  double pooled_o = 0.0, pooled_e = 0.0;
  for (size_t i = 0; i < observed.size(); ++i) {
    const double o = observed[i], e = expected[i];
    if (e < min_expected) {
      pooled_o += o;
      pooled_e += e;
      continue;
    }
    r.statistic += (o - e) * (o - e) / e;
    ++r.dof;
  }
  if (pooled_e > 0.0) {
    r.statistic += (pooled_o - pooled_e) * (pooled_o - pooled_e) / pooled_e;
    ++r.dof;
  }
  r.p_value = chi_square_p_value(r.statistic, r.dof);
  return r;
}

// Adaptive Simpson quadrature (Kuncir 1962; the |S2 - S1| <= 15 eps acceptance and the
// Richardson term (S2 - S1) / 15 of Lyness 1969). min_depth forces a few subdivisions before
// the first acceptance so that a peak narrower than the interval is not stepped over.
namespace detail {
template <class F>
double simpson_rec(const F& f, double a, double b, double fa, double fm, double fb, double whole, double eps,
                   int depth, int min_depth, int max_depth) {
  double m = 0.5 * (a + b);
  double lm = 0.5 * (a + m);
  double rm = 0.5 * (m + b);
  double flm = f(lm);
  double frm = f(rm);
  double left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
  double right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
  double delta = left + right - whole;
  if (depth >= max_depth || (depth >= min_depth && std::fabs(delta) <= 15.0 * eps)) {
    return left + right + delta / 15.0;
  }
  return simpson_rec(f, a, m, fa, flm, fm, left, 0.5 * eps, depth + 1, min_depth, max_depth) +
         simpson_rec(f, m, b, fm, frm, fb, right, 0.5 * eps, depth + 1, min_depth, max_depth);
}
}  // namespace detail

template <class F>
double adaptive_simpson(const F& f, double a, double b, double eps, int min_depth = 2, int max_depth = 12) {
  double fa = f(a);
  double fm = f(0.5 * (a + b));
  double fb = f(b);
  double whole = (b - a) / 6.0 * (fa + 4.0 * fm + fb);
  return detail::simpson_rec(f, a, b, fa, fm, fb, whole, eps, 0, min_depth, max_depth);
}

// ------------------------------------------------------------------------------------------
// Chi-square goodness of fit of sample() against pdf() over the whole sphere.
// ------------------------------------------------------------------------------------------
struct ChiSquareConfig {
  size_t samples = 100000;  // use lobe_test_samples(full)
  int theta_bins = 20;      // over the whole sphere (even: z = 0 / theta = 90 deg is a bin edge)
  int phi_bins = 40;
  // false: bins uniform in cos(theta) (equal solid angle); true: uniform in theta (finer near
  // the poles, for lobes peaked around the normal).
  bool bin_in_theta = false;
  uint32_t seed = 7;
  int n_cases = 1;     // number of chi-square cases in the calling test (Sidak correction)
  double alpha = 0.01;  // family-wise significance level
  double min_expected = 5.0;  // cells below this are pooled
  // The pdf integrates to 1 over the sphere (the lobe never fails to sample). When false, the
  // missing mass must show up as failed samples (flags 0): that "no sample" count is a cell of
  // the test, with expected count N * (1 - integral of pdf).
  bool expect_unit_mass = true;
  double mass_tolerance = 2e-3;   // |integral - 1| allowed for the quadrature
  // Failed samples tolerated where the pdf says the lobe always samples (float round-off at
  // the boundary of the warp's domain); a real hole in the sampler fails far more often.
  double max_null_fraction = 1e-5;
  double integration_eps = 1e-7;  // absolute quadrature tolerance per bin (probability units)
  // Adaptive Simpson depth per dimension and bin: min_depth d forces 2^d + 1 points across the
  // bin before any acceptance (raise it for lobes narrower than a bin / 2^d); max_depth caps
  // the refinement at discontinuities.
  int integration_min_depth = 2;
  int integration_max_depth = 12;
};

struct ChiSquareResult {
  bool passed = false;
  double statistic = 0.0;
  int dof = 0;
  double p_value = 0.0;
  double alpha_case = 0.0;
  double pdf_integral = 0.0;
  size_t samples = 0;
  size_t null_samples = 0;   // flags 0 or pdf 0
  size_t delta_samples = 0;  // AW_LOBE_SPECULAR: chi-square does not apply
  size_t invalid_samples = 0;
  std::string message;  // why it failed, plus a summary line
};

namespace detail {

struct BinGrid {
  int nt, np;
  bool theta;
  // Bin index of a direction, row-major (t, phi).
  int bin_of(float3 w) const {
    double z = std::min(1.0, std::max(-1.0, double(w.z)));
    double t;  // in [0, 1]
    if (theta) {
      t = std::acos(z) / 3.14159265358979323846;
    } else {
      t = 0.5 * (1.0 - z);  // t = 0 at +z, 1 at -z, like theta
    }
    int it = std::min(nt - 1, std::max(0, int(std::floor(t * nt))));
    double phi = std::atan2(double(w.y), double(w.x));
    if (phi < 0.0) phi += 2.0 * 3.14159265358979323846;
    int ip = std::min(np - 1, std::max(0, int(std::floor(phi / (2.0 * 3.14159265358979323846) * np))));
    return it * np + ip;
  }
  // The bin's (cos theta or theta) and phi ranges, for messages.
  std::string describe(int bin) const {
    int it = bin / np, ip = bin % np;
    char b[160];
    if (theta) {
      std::snprintf(b, sizeof b, "theta [%.1f, %.1f] deg, phi [%.1f, %.1f] deg", 180.0 * it / nt,
                    180.0 * (it + 1) / nt, 360.0 * ip / np, 360.0 * (ip + 1) / np);
    } else {
      std::snprintf(b, sizeof b, "cos theta [%.3f, %.3f], phi [%.1f, %.1f] deg", 1.0 - 2.0 * (it + 1) / nt,
                    1.0 - 2.0 * it / nt, 360.0 * ip / np, 360.0 * (ip + 1) / np);
    }
    return b;
  }
  // Integral of pdf over the bin (solid angle), nested adaptive Simpson.
  double integrate(const std::function<float(float3, float3)>& pdf, float3 wo, int bin, double eps,
                   int min_depth = 2, int max_depth = 12) const {
    const double pi = 3.14159265358979323846;
    int it = bin / np, ip = bin % np;
    double p0 = 2.0 * pi * ip / np, p1 = 2.0 * pi * (ip + 1) / np;
    double t0, t1;
    if (theta) {
      t0 = pi * it / nt;
      t1 = pi * (it + 1) / nt;
    } else {
      t0 = 1.0 - 2.0 * (it + 1) / nt;  // z range, ascending
      t1 = 1.0 - 2.0 * it / nt;
    }
    const bool th = theta;
    const double inner_eps = 0.1 * eps / (t1 - t0);
    auto row = [&](double t) {
      double z = th ? std::cos(t) : t;
      double jac = th ? std::sin(t) : 1.0;  // d omega = sin theta d theta d phi = dz d phi
      if (jac == 0.0) return 0.0;
      auto f = [&](double phi) {
        float p = pdf(wo, direction_from_cos_phi(z, phi));
        return std::isfinite(p) ? double(p) : 0.0;  // non-finite values are reported elsewhere
      };
      return jac * adaptive_simpson(f, p0, p1, inner_eps, min_depth, max_depth);
    };
    return adaptive_simpson(row, t0, t1, eps, min_depth, max_depth);
  }
};

}  // namespace detail

inline ChiSquareResult run_chi_square(const LobeFns& fns, float3 wo, const ChiSquareConfig& cfg) {
  ChiSquareResult r;
  r.samples = cfg.samples;
  r.alpha_case = sidak_alpha(cfg.alpha, cfg.n_cases);
  detail::BinGrid grid{cfg.theta_bins, cfg.phi_bins, cfg.bin_in_theta};
  const int nbins = cfg.theta_bins * cfg.phi_bins;
  std::ostringstream why;

  // Observed: histogram of sampled directions.
  std::vector<double> observed(size_t(nbins), 0.0);
  Uniform uni(cfg.seed);
  std::string first_invalid;
  for (size_t i = 0; i < cfg.samples; ++i) {
    float2 u = uni.next2();
    LobeSample s = fns.sample(wo, u);
    if (s.flags == 0u || s.pdf == 0.0f) {
      ++r.null_samples;
      continue;
    }
    if (s.flags & AW_LOBE_SPECULAR) {
      ++r.delta_samples;
      continue;
    }
    float len = std::sqrt(s.wi.x * s.wi.x + s.wi.y * s.wi.y + s.wi.z * s.wi.z);
    bool ok = finite3(s.wi) && std::fabs(len - 1.0f) < 1e-4f && std::isfinite(s.pdf) && s.pdf > 0.0f &&
              finite3(s.weight) && s.weight.x >= 0.0f && s.weight.y >= 0.0f && s.weight.z >= 0.0f;
    if (!ok) {
      if (r.invalid_samples == 0) {
        first_invalid = "u = (" + std::to_string(u.x) + ", " + std::to_string(u.y) + "): wi " + fmt3(s.wi) +
                        " weight " + fmt3(s.weight) + " pdf " + std::to_string(s.pdf);
      }
      ++r.invalid_samples;
      continue;
    }
    observed[size_t(grid.bin_of(s.wi))] += 1.0;
  }

  // Expected: N times the integral of the pdf over each bin.
  std::vector<double> expected(size_t(nbins), 0.0);
  double mass = 0.0;
  for (int b = 0; b < nbins; ++b) {
    double m = grid.integrate(fns.pdf, wo, b, cfg.integration_eps, cfg.integration_min_depth,
                              cfg.integration_max_depth);
    mass += m;
    expected[size_t(b)] = m * double(cfg.samples);
  }
  r.pdf_integral = mass;

  bool ok = true;
  if (r.invalid_samples > 0) {
    ok = false;
    why << r.invalid_samples << " invalid samples (non-unit/non-finite wi, non-finite or negative weight, "
        << "non-finite pdf); first: " << first_invalid << "\n";
  }
  if (r.delta_samples > 0) {
    ok = false;
    why << r.delta_samples << " delta (AW_LOBE_SPECULAR) samples: chi-square does not apply to delta lobes\n";
  }
  if (mass > 1.0 + cfg.mass_tolerance) {
    ok = false;
    why << "pdf integrates to " << mass << " > 1 over the sphere\n";
  }
  if (cfg.expect_unit_mass && mass < 1.0 - cfg.mass_tolerance) {
    ok = false;
    why << "pdf integrates to " << mass << " < 1, but the lobe is expected to always sample\n";
  }

  // Cells: every bin plus the "no sample" cell. A cell with zero expected count but samples
  // in it means the sampler produces directions the pdf calls impossible.
  struct Cell {
    double e, o;
    int bin;  // -1 = the no-sample cell
  };
  std::vector<Cell> cells;
  for (int b = 0; b < nbins; ++b) {
    double e = expected[size_t(b)], o = observed[size_t(b)];
    if (e == 0.0) {
      if (o > 0.0) {
        ok = false;
        why << o << " samples where the pdf is 0: " << grid.describe(b) << "\n";
      }
      continue;
    }
    cells.push_back({e, o, b});
  }
  // The no-sample cell. Float warps fail on a set of measure zero (e.g. a cosine sample that
  // rounds onto the horizon, pdf 0), so a lobe that "always samples" may still fail with a
  // tiny frequency: up to max_null_fraction is accepted and left out of the statistic.
  const double null_fraction = double(r.null_samples) / double(std::max<size_t>(cfg.samples, 1));
  if (cfg.expect_unit_mass) {
    if (null_fraction > cfg.max_null_fraction) {
      ok = false;
      why << r.null_samples << " failed samples (flags 0 or pdf 0), but the pdf integrates to 1 (allowed "
          << cfg.max_null_fraction << " of the samples)\n";
    }
  } else {
    cells.push_back({std::max(0.0, 1.0 - mass) * double(cfg.samples), double(r.null_samples), -1});
    if (cells.back().e == 0.0) {
      if (null_fraction > cfg.max_null_fraction) {
        ok = false;
        why << r.null_samples << " failed samples, but the pdf integrates to " << mass << "\n";
      }
      cells.pop_back();
    }
  }

  // Pool cells with expected count < min_expected (ascending order, as pbrt-v4's chi2 test).
  std::sort(cells.begin(), cells.end(), [](const Cell& a, const Cell& b) { return a.e < b.e; });
  std::vector<Cell> pooled;
  Cell pool{0.0, 0.0, -2};
  size_t k = 0;
  for (; k < cells.size() && cells[k].e < cfg.min_expected; ++k) {
    pool.e += cells[k].e;
    pool.o += cells[k].o;
  }
  for (; k < cells.size(); ++k) pooled.push_back(cells[k]);
  if (pool.e > 0.0) {
    if (pool.e < cfg.min_expected && !pooled.empty()) {
      pooled.front().e += pool.e;  // still too small: merge into the smallest regular cell
      pooled.front().o += pool.o;
      pooled.front().bin = -2;
    } else {
      pooled.push_back(pool);
    }
  }

  double stat = 0.0;
  for (const Cell& c : pooled) stat += (c.o - c.e) * (c.o - c.e) / c.e;
  r.statistic = stat;
  r.dof = int(pooled.size()) - 1;
  r.p_value = chi_square_p_value(stat, r.dof);
  if (r.dof > 0 && !(r.p_value >= r.alpha_case)) {
    ok = false;
    why << "chi-square rejects: the sampled histogram does not follow the pdf. Largest contributions:\n";
    std::vector<Cell> worst = pooled;
    std::sort(worst.begin(), worst.end(), [](const Cell& a, const Cell& b) {
      return (a.o - a.e) * (a.o - a.e) / a.e > (b.o - b.e) * (b.o - b.e) / b.e;
    });
    for (size_t i = 0; i < std::min<size_t>(6, worst.size()); ++i) {
      const Cell& c = worst[i];
      std::string where = c.bin >= 0 ? grid.describe(c.bin) : c.bin == -1 ? "no-sample cell" : "pooled cells";
      char b[256];
      std::snprintf(b, sizeof b, "  %s: observed %.0f, expected %.2f\n", where.c_str(), c.o, c.e);
      why << b;
    }
  }
  r.passed = ok;
  char s[256];
  std::snprintf(s, sizeof s,
                "chi2 = %.2f, dof = %d, p = %.4g (alpha_case %.3g), pdf integral %.6f, %zu samples, %zu failed",
                stat, r.dof, r.p_value, r.alpha_case, mass, r.samples, r.null_samples);
  r.message = why.str() + s;
  return r;
}

inline bool verbose() {
  const char* v = std::getenv("ARCHWAVE_LOBE_VERBOSE");
  return v && std::string(v) == "1";
}

// With ARCHWAVE_LOBE_VERBOSE=1 the summary line of passing cases is printed too.
inline ::testing::AssertionResult chi_square_passes(const LobeFns& fns, float3 wo, const ChiSquareConfig& cfg) {
  ChiSquareResult r = run_chi_square(fns, wo, cfg);
  if (verbose()) std::printf("  [chi2] wo %s: %s\n", fmt3(wo).c_str(), r.message.c_str());
  if (r.passed) return ::testing::AssertionSuccess() << "wo " << fmt3(wo) << ": " << r.message;
  return ::testing::AssertionFailure() << "wo " << fmt3(wo) << ": " << r.message;
}

// ------------------------------------------------------------------------------------------
// Zoomed chi-square for narrow lobes.
//
// At glossiness 0.9 (alpha = 0.01) a lobe is a few milliradians wide: on the bins above it
// falls into one or two cells, where chi-square has no degrees of freedom left and the
// per-cell quadrature can step over the peak. Goodness of fit is invariant under a bijection
// of the sphere, so such lobes are tested through a zoom: a map that magnifies the
// neighbourhood of a centre c by k. Samples are mapped forward, and the pdf is the original one
// at the pre-image divided by the map's area ratio, so a sampler/pdf mismatch survives the zoom
// intact. The map: in a frame with +z = c, the stereographic radius r = tan(psi / 2) of the
// polar angle psi about c is scaled by k (tan(psi' / 2) = k tan(psi / 2), a conformal
// scaling), azimuth unchanged. The sphere's area element in these coordinates is
// 4 r dr dphi / (1 + r^2)^2, so the area ratio is
//   d omega' / d omega = k^2 (1 + r^2)^2 / (1 + k^2 r^2)^2.
//
// USAGE
//   // centre and k chosen from the lobe's own samples (the transmission tests):
//   ChiSquareConfig cfg;  ...; cfg.expect_unit_mass = false; cfg.bin_in_theta = true;
//   EXPECT_TRUE(chi_square_passes(lobe_zoomed(fns, wo), wo, cfg));
//   // a given centre and k (the reflection tests zoom about the mirror direction):
//   MirrorZoom z = make_mirror_zoom(make_float3(-wo.x, -wo.y, wo.z), 0.2 / alpha);
//   ChiSquareResult r = run_chi_square(mirror_zoomed(fns, wo, z), wo, cfg);
//
// The same map is written twice, Zoom (tan / atan of the polar angle, with the centre and k
// picked by lobe_zoom) and MirrorZoom (the rational form r = sin / (1 + cos)): the two round
// differently, and their frames differ at |c.x| = 0.9 exactly, so merging them would move
// every zoomed sample by a rounding error and change the seeded statistics of the tests that
// use each. Kept apart, with the test families that were calibrated on them.
// ------------------------------------------------------------------------------------------
struct Zoom {
  double c[3], t[3], b[3];  // orthonormal frame, c = the lobe's centre
  double k;
};

inline Zoom make_zoom(float3 centre, double k) {
  Zoom z;
  double n = std::sqrt(double(centre.x) * centre.x + double(centre.y) * centre.y + double(centre.z) * centre.z);
  z.c[0] = centre.x / n;
  z.c[1] = centre.y / n;
  z.c[2] = centre.z / n;
  // Any vector not parallel to c, Gram-Schmidt, then b = c x t.
  double a[3] = {1.0, 0.0, 0.0};
  if (std::fabs(z.c[0]) > 0.9) a[0] = 0.0, a[1] = 1.0;
  double d = a[0] * z.c[0] + a[1] * z.c[1] + a[2] * z.c[2];
  for (int i = 0; i < 3; ++i) z.t[i] = a[i] - d * z.c[i];
  double tn = std::sqrt(z.t[0] * z.t[0] + z.t[1] * z.t[1] + z.t[2] * z.t[2]);
  for (int i = 0; i < 3; ++i) z.t[i] /= tn;
  z.b[0] = z.c[1] * z.t[2] - z.c[2] * z.t[1];
  z.b[1] = z.c[2] * z.t[0] - z.c[0] * z.t[2];
  z.b[2] = z.c[0] * z.t[1] - z.c[1] * z.t[0];
  z.k = k;
  return z;
}

// Maps w by the zoom with factor kk (k forward, 1/k inverse); *jac = d omega' / d omega.
inline float3 zoom_map(const Zoom& z, float3 w, double kk, double* jac) {
  const double v[3] = {w.x, w.y, w.z};
  double lx = v[0] * z.t[0] + v[1] * z.t[1] + v[2] * z.t[2];
  double ly = v[0] * z.b[0] + v[1] * z.b[1] + v[2] * z.b[2];
  double lz = v[0] * z.c[0] + v[1] * z.c[1] + v[2] * z.c[2];
  double s = std::sqrt(lx * lx + ly * ly);
  double psi = std::atan2(s, lz);  // accurate for small angles, unlike acos
  double t = std::tan(0.5 * psi);
  double psi2 = 2.0 * std::atan(kk * t);
  double t2 = kk * t;
  *jac = kk * kk * (1.0 + t * t) * (1.0 + t * t) / ((1.0 + t2 * t2) * (1.0 + t2 * t2));
  if (std::isinf(t)) *jac = 1.0 / (kk * kk);  // the antipode of c
  double cx = s > 0.0 ? lx / s : 1.0, cy = s > 0.0 ? ly / s : 0.0;
  double sp = std::sin(psi2), cp = std::cos(psi2);
  double o[3];
  for (int i = 0; i < 3; ++i) o[i] = sp * (cx * z.t[i] + cy * z.b[i]) + cp * z.c[i];
  return make_float3(float(o[0]), float(o[1]), float(o[2]));
}

// The lobe seen through the zoom (sample and pdf only: what chi-square uses; eval is 0).
inline LobeFns zoomed(const LobeFns& f, const Zoom& z) {
  LobeFns g;
  g.eval = [](float3, float3) { return make_float3(0.0f, 0.0f, 0.0f); };
  g.pdf = [f, z](float3 wo, float3 wz) {
    double jac_inv;  // d omega / d omega' at wz
    float3 w = zoom_map(z, wz, 1.0 / z.k, &jac_inv);
    return float(double(f.pdf(wo, w)) * jac_inv);
  };
  g.sample = [f, z](float3 wo, float2 u) {
    LobeSample s = f.sample(wo, u);
    if (s.flags != 0u && !(s.flags & AW_LOBE_SPECULAR)) {
      double jac;
      s.wi = zoom_map(z, s.wi, z.k, &jac);
      s.pdf = float(double(s.pdf) / jac);
    }
    return s;
  };
  return g;
}

// The zoom for a lobe, chosen from its own samples (any choice is valid, since the test is
// invariant under the map; this one spreads the lobe over many bins): centre = the normalised
// mean of up to 256 successful samples, and k such that the median angular distance psi_m
// from the centre maps to 60 deg: k tan(psi_m / 2) = tan(30 deg), k in [1, 1e4]. A lobe that
// never samples gets the identity (k = 1). Draws from its own generator (seed 99), never from
// the chi-square's.
inline Zoom lobe_zoom(const LobeFns& f, float3 wo) {
  Uniform uni(99u);
  std::vector<float3> ws;
  for (int i = 0; i < (1 << 18) && ws.size() < 256; ++i) {
    LobeSample s = f.sample(wo, uni.next2());
    if (s.flags != 0u && !(s.flags & AW_LOBE_SPECULAR)) ws.push_back(s.wi);
  }
  double m[3] = {0.0, 0.0, 0.0};
  for (float3 w : ws) {
    m[0] += w.x;
    m[1] += w.y;
    m[2] += w.z;
  }
  double n = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
  if (ws.empty() || !(n > 0.0)) return make_zoom(make_float3(0.0f, 0.0f, -1.0f), 1.0);
  float3 c = make_float3(float(m[0] / n), float(m[1] / n), float(m[2] / n));
  std::vector<double> psi;
  for (float3 w : ws) {
    double cx = double(w.y) * c.z - double(w.z) * c.y, cy = double(w.z) * c.x - double(w.x) * c.z,
           cz = double(w.x) * c.y - double(w.y) * c.x;
    psi.push_back(std::atan2(std::sqrt(cx * cx + cy * cy + cz * cz), double(dot(w, c))));
  }
  std::nth_element(psi.begin(), psi.begin() + psi.size() / 2, psi.end());
  double t = std::tan(0.5 * psi[psi.size() / 2]);
  double k = t > 0.0 ? std::tan(3.14159265358979323846 / 6.0) / t : 1e4;
  return make_zoom(c, std::min(1e4, std::max(1.0, k)));
}

// The lobe through its own zoom: zoomed(f, lobe_zoom(f, wo)).
inline LobeFns lobe_zoomed(const LobeFns& f, float3 wo) { return zoomed(f, lobe_zoom(f, wo)); }

// The zoom about a given centre m (the reflection tests use the mirror direction), in the
// rational form: see above why it is not merged with Zoom.
struct MirrorZoom {
  double t[3], b[3], m[3];
  double k;
};

inline MirrorZoom make_mirror_zoom(float3 center, double k) {
  MirrorZoom z;
  double m[3] = {center.x, center.y, center.z};
  double len = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
  for (double& c : m) c /= len;
  double a[3] = {std::fabs(m[0]) < 0.9 ? 1.0 : 0.0, std::fabs(m[0]) < 0.9 ? 0.0 : 1.0, 0.0};
  double d = a[0] * m[0] + a[1] * m[1] + a[2] * m[2];
  double t[3] = {a[0] - d * m[0], a[1] - d * m[1], a[2] - d * m[2]};
  double tl = std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
  for (double& c : t) c /= tl;
  double b[3] = {m[1] * t[2] - m[2] * t[1], m[2] * t[0] - m[0] * t[2], m[0] * t[1] - m[1] * t[0]};
  for (int i = 0; i < 3; ++i) {
    z.t[i] = t[i];
    z.b[i] = b[i];
    z.m[i] = m[i];
  }
  z.k = k;
  return z;
}

// Radius scaling on the unit sphere in local coordinates (x, y, zc): r = sin / (1 + cos).
inline void mirror_zoom_scale(double x, double y, double zc, double k, double out[3], double* r_in) {
  double s = std::sqrt(x * x + y * y);
  double r = zc > -1.0 ? s / (1.0 + zc) : 1e300;
  *r_in = r;
  double r2 = std::min(k * r, 1e150);
  double cs = (1.0 - r2 * r2) / (1.0 + r2 * r2), sn = 2.0 * r2 / (1.0 + r2 * r2);
  double cp = s > 0.0 ? x / s : 1.0, sp = s > 0.0 ? y / s : 0.0;
  out[0] = sn * cp;
  out[1] = sn * sp;
  out[2] = cs;
}

// world direction -> zoomed direction (coordinates in the zoom frame, +z = m)
inline float3 mirror_zoom_forward(const MirrorZoom& z, float3 w, double* area_ratio) {
  double x = w.x * z.t[0] + w.y * z.t[1] + w.z * z.t[2];
  double y = w.x * z.b[0] + w.y * z.b[1] + w.z * z.b[2];
  double c = w.x * z.m[0] + w.y * z.m[1] + w.z * z.m[2];
  double n = std::sqrt(x * x + y * y + c * c);
  double o[3], r;
  mirror_zoom_scale(x / n, y / n, c / n, z.k, o, &r);
  double q = (1.0 + r * r) / (1.0 + z.k * z.k * r * r);
  *area_ratio = z.k * z.k * q * q;  // dOmega'' / dOmega
  return make_float3(float(o[0]), float(o[1]), float(o[2]));
}

// zoomed direction -> world direction
inline float3 mirror_zoom_inverse(const MirrorZoom& z, float3 w, double* area_ratio) {
  double o[3], r2;
  double n = std::sqrt(double(w.x) * w.x + double(w.y) * w.y + double(w.z) * w.z);
  mirror_zoom_scale(w.x / n, w.y / n, w.z / n, 1.0 / z.k, o, &r2);
  double r = r2 / z.k;
  double q = (1.0 + r * r) / (1.0 + z.k * z.k * r * r);
  *area_ratio = z.k * z.k * q * q;
  double v[3];
  for (int i = 0; i < 3; ++i) v[i] = o[0] * z.t[i] + o[1] * z.b[i] + o[2] * z.m[i];
  return make_float3(float(v[0]), float(v[1]), float(v[2]));
}

// The lobe at the fixed wo seen through the zoom (eval is passed through unchanged; the
// chi-square test does not use it).
inline LobeFns mirror_zoomed(const LobeFns& f, float3 wo, const MirrorZoom& z) {
  return LobeFns{f.eval,
                 [f, wo, z](float3, float3 w) {
                   double ratio;
                   float3 wi = mirror_zoom_inverse(z, w, &ratio);
                   return float(double(f.pdf(wo, wi)) / ratio);
                 },
                 [f, wo, z](float3, float2 u) {
                   LobeSample s = f.sample(wo, u);
                   if (s.flags == 0u || (s.flags & AW_LOBE_SPECULAR)) return s;
                   double ratio;
                   s.wi = mirror_zoom_forward(z, s.wi, &ratio);
                   s.pdf = float(double(s.pdf) / ratio);
                   return s;
                 }};
}

// ------------------------------------------------------------------------------------------
// eval / pdf / sample consistency and robustness.
// ------------------------------------------------------------------------------------------

// |a - b| / max(|a|, |b|, abs_floor); NaN or Inf on either side counts as infinitely different.
inline double relative_difference(double a, double b, double abs_floor) {
  if (!std::isfinite(a) || !std::isfinite(b)) return (a == b) ? 0.0 : std::numeric_limits<double>::infinity();
  double scale = std::max(std::max(std::fabs(a), std::fabs(b)), abs_floor);
  return std::fabs(a - b) / scale;
}

// For non-delta samples from wo: sample.pdf == pdf(wo, wi) and sample.weight == eval / pdf
// within rel_tol (abs_floor for values near 0); failed samples have weight 0 and pdf 0.
inline ::testing::AssertionResult sample_matches_eval_pdf(const LobeFns& fns, float3 wo, size_t n, uint32_t seed,
                                                          double rel_tol = 1e-4, double abs_floor = 1e-6) {
  Uniform uni(seed);
  size_t bad = 0, checked = 0;
  double worst = 0.0;
  std::ostringstream first;
  for (size_t i = 0; i < n; ++i) {
    float2 u = uni.next2();
    LobeSample s = fns.sample(wo, u);
    if (s.flags == 0u) {
      if (s.pdf != 0.0f || s.weight.x != 0.0f || s.weight.y != 0.0f || s.weight.z != 0.0f) {
        if (bad++ == 0) first << "failed sample (flags 0) with pdf " << s.pdf << " weight " << fmt3(s.weight);
      }
      continue;
    }
    if (s.flags & AW_LOBE_SPECULAR) continue;
    ++checked;
    float p = fns.pdf(wo, s.wi);
    float3 e = fns.eval(wo, s.wi);
    double d = relative_difference(s.pdf, p, abs_floor);
    double dw = 0.0;
    const float ev[3] = {e.x, e.y, e.z};
    const float wv[3] = {s.weight.x, s.weight.y, s.weight.z};
    for (int c = 0; c < 3; ++c) {
      double expect = p > 0.0f ? double(ev[c]) / double(p) : std::numeric_limits<double>::infinity();
      dw = std::max(dw, relative_difference(wv[c], expect, abs_floor));
    }
    worst = std::max(worst, std::max(d, dw));
    if (!(p > 0.0f) || d > rel_tol || dw > rel_tol) {
      if (bad++ == 0) {
        first << "u = (" << u.x << ", " << u.y << "): wi " << fmt3(s.wi) << " sample.pdf " << s.pdf << " pdf() " << p
              << " sample.weight " << fmt3(s.weight) << " eval " << fmt3(e);
      }
    }
  }
  if (bad == 0) {
    return ::testing::AssertionSuccess() << checked << " samples, worst relative difference " << worst;
  }
  return ::testing::AssertionFailure() << "wo " << fmt3(wo) << ": " << bad << " of " << n
                                       << " samples disagree with eval/pdf (tolerance " << rel_tol
                                       << "); first: " << first.str();
}

// Directions a lobe must survive: exact horizon, near-horizon, poles, subnormal z, mirrored
// and opposite pairs, plus uniformly random ones.
inline std::vector<float3> extreme_directions() {
  std::vector<float3> d;
  const float zs[] = {0.0f, -0.0f, 1e-38f, 1e-30f, 1e-12f, 1e-7f, 1e-4f, 1e-2f, 0.5f, 0.999999f, 1.0f};
  const float phis[] = {0.0f, 0.7f, 1.5707964f, 3.1415927f, 4.4f};
  for (float z : zs) {
    for (float phi : phis) {
      d.push_back(direction_from_cos_phi(z, phi));
      d.push_back(direction_from_cos_phi(-z, phi));
    }
  }
  // Exactly z = 0 with exact unit x/y components.
  d.push_back(make_float3(1.0f, 0.0f, 0.0f));
  d.push_back(make_float3(0.0f, 1.0f, 0.0f));
  d.push_back(make_float3(0.0f, 0.0f, 1.0f));
  d.push_back(make_float3(0.0f, 0.0f, -1.0f));
  return d;
}

// eval and pdf finite and >= 0 for every pair of extreme and random directions (both
// hemispheres); sample finite with a unit wi (or a clean failure) for extreme wo and u.
inline ::testing::AssertionResult eval_pdf_sample_finite(const LobeFns& fns, size_t n_random, uint32_t seed) {
  Uniform uni(seed);
  std::vector<float3> dirs = extreme_directions();
  std::vector<std::pair<float3, float3>> pairs;
  for (float3 a : dirs) {
    for (float3 b : dirs) pairs.push_back({a, b});
    pairs.push_back({a, make_float3(-a.x, -a.y, a.z)});  // mirror
    pairs.push_back({a, make_float3(-a.x, -a.y, -a.z)}); // opposite
  }
  for (size_t i = 0; i < n_random; ++i) {
    float3 a = uniform_sphere(uni.next2());
    float3 b = uniform_sphere(uni.next2());
    if (i % 4 == 1) a.z *= 1e-4f;  // grazing (not exactly unit; within 1e-4)
    if (i % 4 == 2) b.z *= 1e-4f;
    pairs.push_back({a, b});
  }
  size_t bad = 0;
  std::ostringstream first;
  auto report = [&](const std::string& what) {
    if (bad++ < 3) first << "\n  " << what;
  };
  for (const auto& pr : pairs) {
    float3 e = fns.eval(pr.first, pr.second);
    float p = fns.pdf(pr.first, pr.second);
    if (!finite3(e) || e.x < 0.0f || e.y < 0.0f || e.z < 0.0f || !std::isfinite(p) || p < 0.0f) {
      report("eval/pdf at wo " + fmt3(pr.first) + " wi " + fmt3(pr.second) + ": eval " + fmt3(e) + " pdf " +
             std::to_string(p));
    }
  }
  std::vector<float2> us = {make_float2(0.0f, 0.0f), make_float2(0.5f, 0.5f), make_float2(0.0f, 0.9999999f),
                            make_float2(0.9999999f, 0.0f), make_float2(0.9999999f, 0.9999999f),
                            make_float2(0.5f, 0.0f), make_float2(0.25f, 0.75f)};
  for (int i = 0; i < 64; ++i) us.push_back(uni.next2());
  for (float3 wo : dirs) {
    for (float2 u : us) {
      LobeSample s = fns.sample(wo, u);
      if (s.flags == 0u) {
        if (s.pdf != 0.0f || s.weight.x != 0.0f || s.weight.y != 0.0f || s.weight.z != 0.0f) {
          report("failed sample with non-zero pdf/weight at wo " + fmt3(wo));
        }
        continue;
      }
      float len = std::sqrt(s.wi.x * s.wi.x + s.wi.y * s.wi.y + s.wi.z * s.wi.z);
      bool delta = (s.flags & AW_LOBE_SPECULAR) != 0u;
      bool pdf_ok = delta ? !(std::isnan(s.pdf)) && s.pdf > 0.0f : std::isfinite(s.pdf) && s.pdf > 0.0f;
      if (!finite3(s.wi) || std::fabs(len - 1.0f) > 1e-4f || !pdf_ok || !finite3(s.weight) || s.weight.x < 0.0f ||
          s.weight.y < 0.0f || s.weight.z < 0.0f) {
        report("sample at wo " + fmt3(wo) + " u (" + std::to_string(u.x) + ", " + std::to_string(u.y) + "): wi " +
               fmt3(s.wi) + " weight " + fmt3(s.weight) + " pdf " + std::to_string(s.pdf));
      }
    }
  }
  if (bad == 0) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << bad << " non-finite, negative or malformed results:" << first.str();
}

// Reciprocity of a reflection lobe: f(wo, wi) = eval(wo, wi)/|wi.z| equals f(wi, wo) =
// eval(wi, wo)/|wo.z|. Directions are drawn with |z| >= min_cos to keep the division by cos
// well conditioned. With `transmission`, wi is on the other side (for diffuse transmission,
// which is reciprocal too; rough refraction is not, by the 1/eta^2 factor).
inline ::testing::AssertionResult reciprocal(const LobeFns& fns, size_t n, uint32_t seed, double rel_tol = 1e-4,
                                             double abs_floor = 1e-7, bool transmission = false,
                                             double min_cos = 1e-2) {
  Uniform uni(seed);
  size_t bad = 0, nonzero = 0;
  double worst = 0.0;
  std::ostringstream first;
  const double pi = 3.14159265358979323846;
  for (size_t i = 0; i < n; ++i) {
    float2 a = uni.next2(), b = uni.next2();
    float3 wo = direction_from_cos_phi(min_cos + (1.0 - min_cos) * a.x, 2.0 * pi * a.y);
    float3 wi = direction_from_cos_phi(min_cos + (1.0 - min_cos) * b.x, 2.0 * pi * b.y);
    if (transmission) wi.z = -wi.z;
    float3 e1 = fns.eval(wo, wi), e2 = fns.eval(wi, wo);
    const float v1[3] = {e1.x / std::fabs(wi.z), e1.y / std::fabs(wi.z), e1.z / std::fabs(wi.z)};
    const float v2[3] = {e2.x / std::fabs(wo.z), e2.y / std::fabs(wo.z), e2.z / std::fabs(wo.z)};
    for (int c = 0; c < 3; ++c) {
      if (v1[c] != 0.0f || v2[c] != 0.0f) ++nonzero;
      double d = relative_difference(v1[c], v2[c], abs_floor);
      worst = std::max(worst, d);
      if (d > rel_tol && bad++ == 0) {
        first << "wo " << fmt3(wo) << " wi " << fmt3(wi) << ": f(wo, wi) " << v1[c] << " f(wi, wo) " << v2[c];
      }
    }
  }
  if (nonzero == 0) return ::testing::AssertionFailure() << "reciprocity: the lobe is zero everywhere tested";
  if (bad == 0) return ::testing::AssertionSuccess() << "worst relative difference " << worst;
  return ::testing::AssertionFailure() << bad << " of " << 3 * n << " channel values not reciprocal (tolerance "
                                       << rel_tol << "); first: " << first.str();
}

// ------------------------------------------------------------------------------------------
// White furnace: directional albedo E(wo) = integral of f |cos| over the sphere.
// ------------------------------------------------------------------------------------------
struct AlbedoEstimate {
  double mean[3] = {0, 0, 0};
  double stderr_[3] = {0, 0, 0};  // standard error of the mean
  size_t n = 0;
  std::string how;
};

namespace detail {
// Adds one per-channel value w to the running sums of w and w^2.
inline void add(double* sum, double* sum2, const double* w) {
  for (int c = 0; c < 3; ++c) {
    sum[c] += w[c];
    sum2[c] += w[c] * w[c];
  }
}

inline void accumulate(AlbedoEstimate& a, const double* sum, const double* sum2, size_t n) {
  a.n = n;
  for (int c = 0; c < 3; ++c) {
    double m = sum[c] / double(n);
    double var = std::max(0.0, sum2[c] / double(n) - m * m);
    a.mean[c] = m;
    a.stderr_[c] = std::sqrt(var / double(std::max<size_t>(n - 1, 1)));
  }
}
}  // namespace detail

// E = mean of sample.weight over u (failed samples contribute 0; delta samples their weight).
inline AlbedoEstimate albedo_by_sampling(const LobeFns& fns, float3 wo, size_t n, uint32_t seed) {
  Uniform uni(seed);
  double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
  for (size_t i = 0; i < n; ++i) {
    LobeSample s = fns.sample(wo, uni.next2());
    if (s.flags == 0u) continue;
    const double w[3] = {s.weight.x, s.weight.y, s.weight.z};
    detail::add(sum, sum2, w);
  }
  AlbedoEstimate a;
  detail::accumulate(a, sum, sum2, n);
  a.how = "sampling";
  return a;
}

// E = mean of 4 pi eval(wo, wi) for wi uniform on the sphere: independent of sample() and
// pdf(). Useless for delta lobes (eval is 0 there).
inline AlbedoEstimate albedo_by_uniform_sphere(const LobeFns& fns, float3 wo, size_t n, uint32_t seed) {
  Uniform uni(seed);
  double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
  const double four_pi = 4.0 * 3.14159265358979323846;
  for (size_t i = 0; i < n; ++i) {
    float3 e = fns.eval(wo, uniform_sphere(uni.next2()));
    const double w[3] = {four_pi * e.x, four_pi * e.y, four_pi * e.z};
    detail::add(sum, sum2, w);
  }
  AlbedoEstimate a;
  detail::accumulate(a, sum, sum2, n);
  a.how = "uniform sphere";
  return a;
}

// E = the integral of eval over the sphere by deterministic quadrature (the chi-square bins,
// nested adaptive Simpson in each): stderr 0, accurate to ~1e-6 for smooth lobes, so a
// lossless lobe can be held to a tight tolerance. Not for delta or very narrow lobes.
inline AlbedoEstimate albedo_by_quadrature(const LobeFns& fns, float3 wo, int theta_bins = 10, int phi_bins = 20,
                                           double eps_per_bin = 1e-8) {
  detail::BinGrid grid{theta_bins, phi_bins, false};
  AlbedoEstimate a;
  for (int c = 0; c < 3; ++c) {
    std::function<float(float3, float3)> channel = [&](float3 o, float3 i) {
      float3 e = fns.eval(o, i);
      return c == 0 ? e.x : c == 1 ? e.y : e.z;
    };
    double sum = 0.0;
    for (int b = 0; b < theta_bins * phi_bins; ++b) sum += grid.integrate(channel, wo, b, eps_per_bin);
    a.mean[c] = sum;
  }
  a.n = 0;
  a.how = "quadrature";
  return a;
}

inline std::string describe(const AlbedoEstimate& a) {
  char b[256];
  std::snprintf(b, sizeof b, "E (%s, n = %zu) = (%.6f, %.6f, %.6f) +- (%.2g, %.2g, %.2g)", a.how.c_str(), a.n,
                a.mean[0], a.mean[1], a.mean[2], a.stderr_[0], a.stderr_[1], a.stderr_[2]);
  return b;
}

// E <= bound + k_sigma * stderr + eps in every channel.
inline ::testing::AssertionResult albedo_at_most(const AlbedoEstimate& a, double bound = 1.0, double k_sigma = 4.0,
                                                 double eps = 1e-6) {
  for (int c = 0; c < 3; ++c) {
    if (!(a.mean[c] <= bound + k_sigma * a.stderr_[c] + eps)) {
      return ::testing::AssertionFailure() << describe(a) << " exceeds " << bound << " in channel " << c;
    }
  }
  return ::testing::AssertionSuccess() << describe(a);
}

// |E - expected| <= k_sigma * stderr + eps in every channel.
inline ::testing::AssertionResult albedo_near(const AlbedoEstimate& a, float3 expected, double k_sigma = 4.0,
                                              double eps = 1e-5) {
  const double ex[3] = {expected.x, expected.y, expected.z};
  for (int c = 0; c < 3; ++c) {
    if (!(std::fabs(a.mean[c] - ex[c]) <= k_sigma * a.stderr_[c] + eps)) {
      return ::testing::AssertionFailure() << describe(a) << " differs from the expected " << fmt3(expected)
                                           << " in channel " << c << " (> " << k_sigma << " sigma + " << eps << ")";
    }
  }
  return ::testing::AssertionSuccess() << describe(a);
}

// Both estimators (sampling, and uniform-sphere integration of eval unless `delta`): E <= 1
// for every lobe, and E = 1 where the lobe is lossless (call with a white lobe).
inline ::testing::AssertionResult white_furnace(const LobeFns& fns, float3 wo, size_t n, uint32_t seed, bool lossless,
                                                bool delta = false, double eps = 1e-5) {
  std::vector<AlbedoEstimate> est = {albedo_by_sampling(fns, wo, n, seed)};
  if (!delta) est.push_back(albedo_by_uniform_sphere(fns, wo, n, seed + 1000003u));
  std::ostringstream all;
  for (const AlbedoEstimate& a : est) {
    ::testing::AssertionResult r =
        lossless ? albedo_near(a, make_float3(1.0f, 1.0f, 1.0f), 4.0, eps) : albedo_at_most(a, 1.0, 4.0, eps);
    if (!r) return ::testing::AssertionFailure() << "white furnace at wo " << fmt3(wo) << ": " << r.message();
    all << describe(a) << "; ";
  }
  return ::testing::AssertionSuccess() << all.str();
}

// ------------------------------------------------------------------------------------------
// Host vs device.
// ------------------------------------------------------------------------------------------

// Host-vs-device tolerances come from measured differences, are stated per test, and are never
// widened to hide a real disagreement (docs/design.md, fact F1): 1e-5 relative here. Values
// below the floor compare absolutely (rounding near 0 has no meaningful relative size).
constexpr double kHostDeviceRelTol = 1e-5;
constexpr double kHostDeviceAbsFloor = 1e-6;

namespace detail {
// One runtime and one program per probe file for the whole test binary. Deliberately leaked:
// destroying OpenCL objects from static destructors races the ICD's own teardown.
inline ClRuntime& probe_runtime() {
  static ClRuntime* rt = new ClRuntime(aw::kDefaultDevice);
  return *rt;
}
inline cl::Program& probe_program(const std::string& file) {
  static std::map<std::string, cl::Program>* programs = new std::map<std::string, cl::Program>();
  auto it = programs->find(file);
  if (it == programs->end()) {
    ClRuntime& rt = probe_runtime();
    cl::Program p = rt.build(assemble_kernel_source(file, default_kernel_dir()), "-cl-std=CL1.2");
    it = programs->emplace(file, p).first;
  }
  return it->second;
}
}  // namespace detail

// A read-only buffer a probe kernel takes after its output (bytes, size).
struct ProbeBuffer {
  const void* data;
  size_t bytes;
};

// Runs `kernel` from kernels/<cl_file_rel_to_kernels> over n_items work items. The kernel has
// the signature (uint n, __global const float* in, __global float* out, then one __global
// pointer per entry of `extra`) and writes out[i * out_floats_per_item + k]. The output starts
// as NaN, so a slot the kernel does not write fails any comparison. Local size 64, global
// size padded to a multiple of 64.
inline std::vector<float> run_device_probe(const std::string& cl_file_rel_to_kernels, const char* kernel,
                                           const std::vector<float>& in, size_t out_floats_per_item,
                                           size_t n_items, const std::vector<ProbeBuffer>& extra = {}) {
  ClRuntime& rt = detail::probe_runtime();
  cl::Kernel k(detail::probe_program(cl_file_rel_to_kernels), kernel);
  std::vector<float> out(out_floats_per_item * n_items, std::numeric_limits<float>::quiet_NaN());
  cl::Buffer bin = rt.buffer("probe input", in.size() * sizeof(float), CL_MEM_READ_ONLY,
                             in.empty() ? nullptr : in.data());
  cl::Buffer bout = rt.buffer("probe output", out.size() * sizeof(float), CL_MEM_READ_WRITE,
                              out.empty() ? nullptr : out.data());
  k.setArg(0, cl_uint(n_items));
  k.setArg(1, bin);
  k.setArg(2, bout);
  std::vector<cl::Buffer> extra_buffers;
  for (const ProbeBuffer& e : extra) {
    // A buffer of at least 4 bytes even for an empty array (OpenCL refuses size 0).
    std::vector<uint8_t> bytes(std::max<size_t>(e.bytes, 4), 0);
    if (e.bytes) std::memcpy(bytes.data(), e.data, e.bytes);
    extra_buffers.push_back(rt.buffer("probe data", bytes.size(), CL_MEM_READ_ONLY, bytes.data()));
    k.setArg(cl_uint(3 + extra_buffers.size() - 1), extra_buffers.back());
  }
  const size_t local = 64;
  size_t global = (n_items + local - 1) / local * local;
  if (global == 0) global = local;
  rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(global), cl::NDRange(local));
  if (!out.empty()) rt.queue().enqueueReadBuffer(bout, CL_TRUE, 0, out.size() * sizeof(float), out.data());
  rt.queue().finish();
  return out;
}

// Column k of a probe's output with `stride` floats per item (to compare outputs one by one).
inline std::vector<float> probe_column(const std::vector<float>& v, size_t stride, size_t k) {
  std::vector<float> c;
  for (size_t i = k; i < v.size(); i += stride) c.push_back(v[i]);
  return c;
}

struct ProbeDiff {
  double max_rel = 0.0;  // relative_difference with the floor
  size_t worst = 0;
  size_t over = 0;  // values over the tolerance
};

inline ProbeDiff compare_probe(const std::vector<float>& host, const std::vector<float>& device, double rel_tol,
                               double abs_floor) {
  ProbeDiff d;
  for (size_t i = 0; i < std::min(host.size(), device.size()); ++i) {
    double r = relative_difference(host[i], device[i], abs_floor);
    if (std::isnan(double(host[i])) || std::isnan(double(device[i]))) r = std::numeric_limits<double>::infinity();
    if (r > rel_tol) ++d.over;
    if (r > d.max_rel) {
      d.max_rel = r;
      d.worst = i;
    }
  }
  return d;
}

// Every value within rel_tol (relative, with abs_floor). The message states the measured
// maximum, so the tolerance can be set from measurement.
inline ::testing::AssertionResult host_matches_device(const std::vector<float>& host, const std::vector<float>& device,
                                                      double rel_tol, double abs_floor, const std::string& what) {
  if (host.size() != device.size()) {
    return ::testing::AssertionFailure() << what << ": host has " << host.size() << " values, device "
                                         << device.size();
  }
  ProbeDiff d = compare_probe(host, device, rel_tol, abs_floor);
  char b[256];
  std::snprintf(b, sizeof b, "%s: %zu values, max relative difference %.3g at [%zu] (host %.9g, device %.9g)",
                what.c_str(), host.size(), d.max_rel, d.worst, host.empty() ? 0.0 : double(host[d.worst]),
                device.empty() ? 0.0 : double(device[d.worst]));
  if (d.over == 0) return ::testing::AssertionSuccess() << b;
  return ::testing::AssertionFailure() << b << "; " << d.over << " values over the tolerance " << rel_tol;
}

// For a value v computed as sqrt(1 - x^2 - y^2) (a sampled direction's z, or a pdf
// proportional to it): compares (scale * v)^2 in absolute terms. Near the horizon the sqrt
// magnifies one-ulp differences of the two math libraries' cos/sin far beyond any relative
// tolerance, while the quantity the warp actually computes, 1 - r^2, agrees to ~1e-7.
inline ::testing::AssertionResult host_matches_device_squared(const std::vector<float>& host,
                                                              const std::vector<float>& device, double scale,
                                                              double abs_tol, const std::string& what) {
  if (host.size() != device.size()) {
    return ::testing::AssertionFailure() << what << ": host has " << host.size() << " values, device "
                                         << device.size();
  }
  double worst = 0.0;
  size_t at = 0;
  for (size_t i = 0; i < host.size(); ++i) {
    double h = double(host[i]) * scale, d = double(device[i]) * scale;
    double diff = std::fabs(h * h - d * d);
    if (std::isnan(diff)) diff = std::numeric_limits<double>::infinity();
    if (diff > worst) {
      worst = diff;
      at = i;
    }
  }
  char b[256];
  std::snprintf(b, sizeof b, "%s: %zu values, max |(s host)^2 - (s device)^2| = %.3g at [%zu]", what.c_str(),
                host.size(), worst, at);
  if (worst <= abs_tol) return ::testing::AssertionSuccess() << b;
  return ::testing::AssertionFailure() << b << " > " << abs_tol;
}

}  // namespace lobe_test
}  // namespace aw
