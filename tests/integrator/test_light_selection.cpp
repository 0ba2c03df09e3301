// Light selection in O(1) (kernels/lights/lights.h, light_pick; host/render/alias_table.h):
// the alias table reproduces the power-proportional probabilities that MIS reads
// (select_pdf), and light_pick draws them.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "host/render/alias_table.h"
#include "kernels/lights/lights.h"

namespace {

// The probability of each outcome that a table implies: bin i (1/n) keeps i with q[i] and
// gives alias[i] otherwise.
std::vector<double> implied(const aw::AliasTable& t) {
  const size_t n = t.q.size();
  std::vector<double> p(n, 0.0);
  for (size_t i = 0; i < n; ++i) {
    p[i] += double(t.q[i]) / double(n);
    p[t.alias[i]] += (1.0 - double(t.q[i])) / double(n);
  }
  return p;
}

TEST(AliasTable, ReproducesTheWeights) {
  for (const std::vector<double>& w :
       {std::vector<double>{1, 2, 3, 0, 4}, std::vector<double>{5}, std::vector<double>{1e-6, 1, 1e6, 3, 3, 3, 0.5},
        std::vector<double>(100, 1.0)}) {
    aw::AliasTable t = aw::build_alias_table(w);
    double total = 0;
    for (double x : w) total += x;
    std::vector<double> p = implied(t);
    for (size_t i = 0; i < w.size(); ++i) {
      EXPECT_NEAR(p[i], w[i] / total, 1e-6) << "outcome " << i << " of " << w.size();
      EXPECT_GE(t.q[i], 0.0f);
      EXPECT_LE(t.q[i], 1.0f);
      EXPECT_LT(t.alias[i], w.size());
    }
  }
}

TEST(AliasTable, NoWeightMeansUniform) {
  aw::AliasTable t = aw::build_alias_table({0, 0, 0});
  std::vector<double> p = implied(t);
  for (double x : p) EXPECT_DOUBLE_EQ(x, 1.0 / 3.0);
}

// light_pick over a fine uniform grid of u draws each light with its probability: the grid
// is exact in [0, 1) with 2^20 points, so the frequencies match to the grid's resolution.
TEST(AliasTable, LightPickDrawsTheProbabilities) {
  const std::vector<double> w = {3, 0, 1, 6, 0.25};
  aw::AliasTable t = aw::build_alias_table(w);
  std::vector<LightGpu> lights(w.size());
  std::memset(lights.data(), 0, lights.size() * sizeof(LightGpu));
  for (size_t i = 0; i < w.size(); ++i) {
    lights[i].alias_q = t.q[i];
    lights[i].alias = t.alias[i];
  }
  const uint32_t n = 1u << 20;
  std::vector<double> freq(w.size(), 0.0);
  for (uint32_t k = 0; k < n; ++k) {
    uint32_t i = light_pick(lights.data(), uint32_t(w.size()), float(k) / float(n));
    ASSERT_LT(i, w.size());
    freq[i] += 1.0 / n;
  }
  double total = 10.25;
  for (size_t i = 0; i < w.size(); ++i) EXPECT_NEAR(freq[i], w[i] / total, 1e-5) << i;
  EXPECT_EQ(freq[1], 0.0);  // a light without power is never picked
}

}  // namespace
