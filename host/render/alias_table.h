// Walker's alias table (Walker 1977, ACM TOMS 3(3)) built by Vose's algorithm (Vose 1991,
// "A linear algorithm for generating random numbers with a given distribution", IEEE TSE
// 17(9), Sec. III), in double precision: bin i keeps its own outcome with probability q[i]
// and gives alias[i] otherwise, so drawing a uniform bin and one comparison samples the
// distribution in O(1). The sampling side is light_pick (kernels/lights/lights.h).
#pragma once

#include <cstdint>
#include <vector>

namespace aw {

struct AliasTable {
  std::vector<float> q;
  std::vector<uint32_t> alias;
};

// From non-negative weights. All zero (or none positive): every bin keeps itself, a uniform
// choice, which is harmless where the weights' owners then contribute nothing.
inline AliasTable build_alias_table(const std::vector<double>& weights) {
  const size_t n = weights.size();
  AliasTable t;
  t.q.assign(n, 1.0f);
  t.alias.resize(n);
  for (size_t i = 0; i < n; ++i) t.alias[i] = uint32_t(i);
  double total = 0.0;
  for (double w : weights) total += w > 0.0 ? w : 0.0;
  if (!(total > 0.0)) return t;
  // Scaled so that the mean bin holds 1; "small" bins hold less than 1 and are topped up by
  // a "large" one, which keeps the rest.
  std::vector<double> p(n);
  std::vector<uint32_t> small, large;
  for (size_t i = 0; i < n; ++i) {
    p[i] = (weights[i] > 0.0 ? weights[i] : 0.0) * double(n) / total;
    (p[i] < 1.0 ? small : large).push_back(uint32_t(i));
  }
  while (!small.empty() && !large.empty()) {
    uint32_t s = small.back(), l = large.back();
    small.pop_back();
    t.q[s] = float(p[s]);
    t.alias[s] = l;
    p[l] = (p[l] + p[s]) - 1.0;
    if (p[l] < 1.0) {
      large.pop_back();
      small.push_back(l);
    }
  }
  // What is left holds 1 up to round-off: it keeps itself.
  for (uint32_t i : large) t.q[i] = 1.0f;
  for (uint32_t i : small) t.q[i] = 1.0f;
  return t;
}

}  // namespace aw
