// Shared by the reflection lobe's fast tests (tests/lobes/test_microfacet.cpp) and its long
// tests (tests/lobes_long/test_reflection_long.cpp): the lobe bound into LobeFns, the Fresnel
// presets, the full chi-square grid's axes, and the chi-square that zooms narrow lobes.
#pragma once

#include <algorithm>
#include <cmath>

#include "kernels/lobes/reflection.h"
#include "tests/lobes/lobe_harness.h"

namespace aw {
namespace lobe_test {

inline FresnelParams fresnel_dielectric_1_5() {
  FresnelParams f;
  f.mode = AW_FRESNEL_DIELECTRIC;
  f.eta = 1.5f;
  f.k = 0.0f;
  f.facing = 0.2f;
  f.perpendicular = 1.0f;
  f.curve = 5.0f;
  return f;
}

inline FresnelParams fresnel_conductor_gold() {  // scalar n, k of gold around 600 nm
  FresnelParams f = fresnel_dielectric_1_5();
  f.mode = AW_FRESNEL_CONDUCTOR;
  f.eta = 0.25f;
  f.k = 3.0f;
  return f;
}

inline FresnelParams fresnel_curve_default() {  // docs/material.md §1 defaults
  FresnelParams f = fresnel_dielectric_1_5();
  f.mode = AW_FRESNEL_CURVE;
  f.facing = 0.2f;
  f.perpendicular = 1.0f;
  f.curve = 5.0f;
  return f;
}

inline const char* brdf_name(uint b) {
  switch (b) {
    case AW_BRDF_BECKMANN: return "beckmann";
    case AW_BRDF_GGX: return "ggx";
    case AW_BRDF_ASHIKHMIN_SHIRLEY: return "ashikhmin_shirley";
    default: return "ashikhmin_shirley_legacy";
  }
}

inline LobeFns reflection_fns(ReflectionParams p) {
  return LobeFns{[p](float3 wo, float3 wi) { return lobe_reflection_eval(p, wo, wi); },
                 [p](float3 wo, float3 wi) { return lobe_reflection_pdf(p, wo, wi); },
                 [p](float3 wo, float2 u) { return lobe_reflection_sample(p, wo, u); }};
}

// The full grid of the material issue (run whole by the long test; the fast test picks a
// representative subset): every brdf x anisotropy x glossiness x incidence x Fresnel mode.
namespace reflection_grid {
constexpr float kAniso[] = {0.0f, -0.8f, 0.8f};
constexpr float kGloss[] = {0.05f, 0.3f, 0.6f, 0.9f};
constexpr double kTheta[] = {0.0, 45.0, 85.0};
constexpr int kFresnelModes = 3;
constexpr int kBrdfs = 4;
constexpr int kCases = kBrdfs * 3 * 4 * 3 * kFresnelModes;

// Fresnel mode k of the grid: 0 dielectric eta 1.5, 1 conductor (gold), 2 the default curve.
inline FresnelParams grid_fresnel(int k) {
  return k == 0 ? fresnel_dielectric_1_5() : k == 1 ? fresnel_conductor_gold() : fresnel_curve_default();
}

inline const char* fresnel_name(int k) { return k == 0 ? "dielectric 1.5" : k == 1 ? "conductor" : "curve"; }
}  // namespace reflection_grid

// The narrowest roughness of a reflection lobe (the equivalent alpha sqrt(2 / (n + 2)) of the
// largest Ashikhmin–Shirley exponent).
inline float narrowest_alpha(const ReflectionParams& p) {
  if (reflection_is_as(p)) return std::sqrt(2.0f / (std::max(p.as_nu, p.as_nv) + 2.0f));
  return std::min(p.mf.ax, p.mf.ay);
}

// Chi-square of a reflection lobe; lobes narrower than alpha 0.05 go through a zoom of
// k = 0.2 / alpha about the mirror direction (the narrow axis then spans ~20 deg; MirrorZoom in
// tests/lobes/lobe_harness.h).
inline ChiSquareResult reflection_chi_square(const ReflectionParams& p, float3 wo, ChiSquareConfig cfg) {
  LobeFns f = reflection_fns(p);
  float alpha = narrowest_alpha(p);
  if (alpha >= 0.05f) return run_chi_square(f, wo, cfg);
  cfg.bin_in_theta = true;
  MirrorZoom z = make_mirror_zoom(make_float3(-wo.x, -wo.y, wo.z), 0.2 / double(alpha));
  return run_chi_square(mirror_zoomed(f, wo, z), wo, cfg);
}

}  // namespace lobe_test
}  // namespace aw
