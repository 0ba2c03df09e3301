// Shared by the transmission lobes' fast tests (tests/lobes/test_refraction.cpp) and their long
// tests (tests/lobes_long/test_transmission_long.cpp): rough refraction
// (kernels/lobes/refraction.h) and frosted thin walls (kernels/lobes/thin_walled.h) bound into
// LobeFns, the full chi-square grid's axes, and the chi-square configuration for a lobe seen
// through its zoom (lobe_zoomed in tests/lobes/lobe_harness.h).
#pragma once

#include <cstddef>
#include <cstdint>

#include "kernels/lobes/refraction.h"
#include "kernels/lobes/thin_walled.h"
#include "tests/lobes/lobe_harness.h"

namespace aw {
namespace lobe_test {

constexpr float kEtaIn = 1.5f;          // entering glass from air
constexpr float kEtaOut = 1.0f / 1.5f;  // leaving it

inline LobeFns refraction_fns(RefractionParams p) {
  return LobeFns{[=](float3 wo, float3 wi) { return lobe_refraction_eval(p, wo, wi); },
                 [=](float3 wo, float3 wi) { return lobe_refraction_pdf(p, wo, wi); },
                 [=](float3 wo, float2 u) { return lobe_refraction_sample(p, wo, u); }};
}

// The same lobe measured as importance: eval and weight times eta^2 (undoes the radiance
// scaling; this is the quantity bounded by 1 by energy conservation).
inline LobeFns refraction_importance_fns(RefractionParams p) {
  const float s = p.eta * p.eta;
  return LobeFns{[=](float3 wo, float3 wi) { return lobe_refraction_eval(p, wo, wi) * s; },
                 [=](float3 wo, float3 wi) { return lobe_refraction_pdf(p, wo, wi); },
                 [=](float3 wo, float2 u) {
                   LobeSample r = lobe_refraction_sample(p, wo, u);
                   r.weight = r.weight * s;
                   return r;
                 }};
}

inline LobeFns thin_fns(float glossiness) {
  return LobeFns{[=](float3 wo, float3 wi) { return lobe_thin_transmission_eval(glossiness, wo, wi); },
                 [=](float3 wo, float3 wi) { return lobe_thin_transmission_pdf(glossiness, wo, wi); },
                 [=](float3 wo, float2 u) { return lobe_thin_transmission_sample(glossiness, wo, u); }};
}

inline const char* dist_name(uint d) { return d == AW_MF_GGX ? "GGX" : "Beckmann"; }

// The full grid of the material issue (run whole by the long test; the fast test picks a
// representative subset): rough refraction distribution x glossiness x eta x incidence, and
// thin walls glossiness x incidence.
namespace transmission_grid {
constexpr uint kDists[] = {AW_MF_GGX, AW_MF_BECKMANN};
constexpr float kGloss[] = {0.3f, 0.6f, 0.9f};
constexpr float kEtas[] = {kEtaIn, kEtaOut};
constexpr double kThetas[] = {0.0, 45.0, 80.0};
constexpr int kRefractionCases = 2 * 3 * 2 * 3;
constexpr int kThinCases = 3 * 3;
}  // namespace transmission_grid

// Chi-square configuration for a transmission lobe through its zoom (lobe_zoomed: centred on
// the lobe, where bins uniform in theta are finest, and magnified so that even narrow lobes
// spread over many bins). Failed samples are a cell of the test (expect_unit_mass = false).
inline ChiSquareConfig zoomed_chi_square_config(size_t samples, int n_cases, uint32_t seed) {
  ChiSquareConfig cfg;
  cfg.samples = samples;
  cfg.n_cases = n_cases;
  cfg.seed = seed;
  cfg.expect_unit_mass = false;
  cfg.bin_in_theta = true;
  return cfg;
}

}  // namespace lobe_test
}  // namespace aw
