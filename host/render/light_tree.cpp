#include "host/render/light_tree.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <stdexcept>

#include <glm/glm.hpp>

namespace aw {

namespace {

const double kPi = 3.14159265358979323846;

// A light's or a node's bounds (Conty Estevez & Kulla 2018, Sec. 4.1): box, power, and the
// orientation cone: the emitters' normals lie within theta_o of `axis`, and each emits within
// theta_e of its normal.
struct Bounds {
  glm::dvec3 lo{std::numeric_limits<double>::max()}, hi{-std::numeric_limits<double>::max()};
  double power = 0.0;
  glm::dvec3 axis{0.0, 0.0, 1.0};
  double theta_o = 0.0, theta_e = 0.0;
  bool empty = true;
};

glm::dvec3 d3(const float* v) { return glm::dvec3(v[0], v[1], v[2]); }

void grow(Bounds* b, glm::dvec3 p) {
  b->lo = glm::min(b->lo, p);
  b->hi = glm::max(b->hi, p);
}

Bounds light_bounds(const LightGpu& l, double power) {
  Bounds b;
  b.empty = false;
  b.power = power;
  const glm::dvec3 p = d3(l.p), u = d3(l.u), v = d3(l.v), n = d3(l.n);
  b.theta_e = kPi / 2;  // every finite emitter here is Lambertian (or a point): a hemisphere per normal
  b.theta_o = kPi;      // all directions, unless one-sided below
  switch (l.type) {
    case AW_LIGHT_POINT:
      grow(&b, p);
      break;
    case AW_LIGHT_SPHERE:
      grow(&b, p - glm::dvec3(l.radius));
      grow(&b, p + glm::dvec3(l.radius));
      break;
    case AW_LIGHT_QUAD:
      for (glm::dvec3 q : {p, p + u, p + v, p + u + v}) grow(&b, q);
      break;
    case AW_LIGHT_DISK: {
      // The disk's extent along each axis: radius * sqrt(1 - n_i^2).
      const glm::dvec3 e = double(l.radius) * glm::sqrt(glm::max(glm::dvec3(0.0), glm::dvec3(1.0) - n * n));
      grow(&b, p - e);
      grow(&b, p + e);
      break;
    }
    case AW_LIGHT_TRIANGLE:
      for (glm::dvec3 q : {p, p + u, p + v}) grow(&b, q);
      break;
    default:
      throw std::logic_error("light tree: a light at infinity cannot be in the tree");
  }
  if ((l.type == AW_LIGHT_QUAD || l.type == AW_LIGHT_DISK) && !(l.flags & AW_LIGHT_TWO_SIDED)) {
    b.axis = n;
    b.theta_o = 0.0;
  }
  return b;
}

double angle_between(glm::dvec3 a, glm::dvec3 b) {
  // Numerically robust for nearly parallel vectors (PBR 4th ed., AngleBetween).
  if (glm::dot(a, b) < 0.0) return kPi - 2.0 * std::asin(std::min(1.0, glm::length(a + b) / 2.0));
  return 2.0 * std::asin(std::min(1.0, glm::length(b - a) / 2.0));
}

// The smallest cone holding two cones (PBR 4th ed., Sec. 9.3 DirectionCone::Union, in angles).
void cone_union(const Bounds& a, const Bounds& b, glm::dvec3* axis, double* theta_o) {
  const double td = angle_between(a.axis, b.axis);
  if (std::min(td + b.theta_o, kPi) <= a.theta_o) {
    *axis = a.axis;
    *theta_o = a.theta_o;
    return;
  }
  if (std::min(td + a.theta_o, kPi) <= b.theta_o) {
    *axis = b.axis;
    *theta_o = b.theta_o;
    return;
  }
  const double to = (a.theta_o + td + b.theta_o) / 2.0;
  const glm::dvec3 wr = glm::cross(a.axis, b.axis);
  if (to >= kPi || glm::dot(wr, wr) == 0.0) {
    *axis = a.axis;
    *theta_o = kPi;
    return;
  }
  // Rotate a's axis towards b's by to - theta_a (Rodrigues' formula about wr).
  const double r = to - a.theta_o;
  const glm::dvec3 k = glm::normalize(wr);
  *axis = glm::normalize(a.axis * std::cos(r) + glm::cross(k, a.axis) * std::sin(r) +
                         k * glm::dot(k, a.axis) * (1.0 - std::cos(r)));
  *theta_o = to;
}

Bounds merge(const Bounds& a, const Bounds& b) {
  if (a.empty) return b;
  if (b.empty) return a;
  Bounds m;
  m.empty = false;
  m.lo = glm::min(a.lo, b.lo);
  m.hi = glm::max(a.hi, b.hi);
  m.power = a.power + b.power;
  m.theta_e = std::max(a.theta_e, b.theta_e);
  cone_union(a, b, &m.axis, &m.theta_o);
  return m;
}

// The orientation measure M_Omega of Conty Estevez & Kulla 2018, Sec. 4.4 (Eq. 1), the
// integral of cos over the directions a cone of normals (theta_o) emitting within theta_e of
// each reaches: the "angular" part of their surface area orientation heuristic.
double orientation_measure(double theta_o, double theta_e) {
  const double tw = std::min(theta_o + theta_e, kPi);
  const double so = std::sin(theta_o), co = std::cos(theta_o);
  return 2.0 * kPi * (1.0 - co) +
         kPi / 2.0 * (2.0 * tw * so - std::cos(theta_o - 2.0 * tw) - 2.0 * theta_o * so + co);
}

double surface_area(const Bounds& b) {
  const glm::dvec3 d = glm::max(b.hi - b.lo, glm::dvec3(0.0));
  return 2.0 * (d.x * d.y + d.y * d.z + d.z * d.x);
}

// The surface area orientation heuristic's cost of a child (Sec. 4.4, Eq. 2 without the
// regularising factor for thin boxes): power x box area x orientation measure. Zero-area boxes
// (points, coplanar lights) still compare by power and orientation.
double saoh_cost(const Bounds& b) {
  if (b.empty) return 0.0;
  return b.power * (surface_area(b) + 1e-12) * orientation_measure(b.theta_o, b.theta_e);
}

struct Builder {
  std::vector<LightGpu>* lights;
  std::vector<Bounds> bounds;        // per light in [first, end)
  std::vector<glm::dvec3> centroid;  // per light
  std::vector<LightTreeNode> nodes;
  uint32_t first = 0;

  void write_node(uint32_t at, const Bounds& b) {
    LightTreeNode& nd = nodes[at];
    for (int k = 0; k < 3; ++k) {
      nd.bmin[k] = float(b.lo[k]);
      nd.bmax[k] = float(b.hi[k]);
      nd.axis[k] = float(b.axis[k]);
    }
    // Conservative in single precision: the box grows by an ulp-scale margin, the cone's
    // cosines round towards wider cones, so float importance is never zero where it should not be.
    for (int k = 0; k < 3; ++k) {
      nd.bmin[k] = std::nextafter(nd.bmin[k], -std::numeric_limits<float>::infinity());
      nd.bmax[k] = std::nextafter(nd.bmax[k], std::numeric_limits<float>::infinity());
    }
    nd.power = float(b.power);
    nd.cos_o = b.theta_o >= kPi ? -1.0f : std::max(-1.0f, float(std::cos(b.theta_o)) - 1e-6f);
    nd.cos_e = b.theta_e >= kPi ? -1.0f : std::max(-1.0f, float(std::cos(b.theta_e)) - 1e-6f);
  }

  // Builds the subtree over items[lo, hi) (light indices relative to `first`) at depth `depth`
  // with path bits `bits`; returns its bounds.
  Bounds build(std::vector<uint32_t>& items, size_t lo, size_t hi, uint32_t depth, uint32_t bits) {
    const uint32_t at = uint32_t(nodes.size());
    nodes.emplace_back();
    std::memset(&nodes[at], 0, sizeof(LightTreeNode));
    if (hi - lo == 1) {
      const uint32_t li = items[lo];
      const Bounds& b = bounds[li];
      write_node(at, b);
      nodes[at].leaf = 1u;
      nodes[at].child = first + li;
      LightGpu& l = (*lights)[first + li];
      l.tree_bits = bits;
      l.tree_depth = depth;
      return b;
    }
    size_t mid = split(items, lo, hi, depth);
    Bounds left = build(items, lo, mid, depth + 1, bits);
    nodes[at].child = uint32_t(nodes.size());
    Bounds right = build(items, mid, hi, depth + 1, bits | (1u << depth));
    Bounds b = merge(left, right);
    write_node(at, b);
    return b;
  }

  // Where to split items[lo, hi): the lowest SAOH cost over 12 buckets of the centroids along
  // each axis; the count median when the depth budget (32 levels) requires a balanced split or
  // the centroids coincide.
  size_t split(std::vector<uint32_t>& items, size_t lo, size_t hi, uint32_t depth) {
    const size_t n = hi - lo;
    uint32_t need = 0;
    while ((size_t(1) << need) < n) ++need;
    glm::dvec3 clo(std::numeric_limits<double>::max()), chi(-std::numeric_limits<double>::max());
    for (size_t i = lo; i < hi; ++i) {
      clo = glm::min(clo, centroid[items[i]]);
      chi = glm::max(chi, centroid[items[i]]);
    }
    const glm::dvec3 ext = chi - clo;
    int best_axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
    auto median = [&](int axis) {
      const size_t mid = lo + n / 2;
      std::nth_element(items.begin() + lo, items.begin() + mid, items.begin() + hi,
                       [&](uint32_t a, uint32_t b) { return centroid[a][axis] < centroid[b][axis]; });
      return mid;
    };
    if (depth + need >= 31 || !(ext[best_axis] > 0.0)) return median(best_axis);
    constexpr int kBuckets = 12;
    double best_cost = std::numeric_limits<double>::max();
    int best_split = -1;
    for (int axis = 0; axis < 3; ++axis) {
      if (!(ext[axis] > 0.0)) continue;
      Bounds bucket[kBuckets];
      auto bucket_of = [&](uint32_t li) {
        int k = int(kBuckets * (centroid[li][axis] - clo[axis]) / ext[axis]);
        return std::min(std::max(k, 0), kBuckets - 1);
      };
      for (size_t i = lo; i < hi; ++i) bucket[bucket_of(items[i])] = merge(bucket[bucket_of(items[i])], bounds[items[i]]);
      for (int s = 0; s < kBuckets - 1; ++s) {
        Bounds a, b;
        for (int k = 0; k <= s; ++k) a = merge(a, bucket[k]);
        for (int k = s + 1; k < kBuckets; ++k) b = merge(b, bucket[k]);
        if (a.empty || b.empty) continue;
        const double cost = saoh_cost(a) + saoh_cost(b);
        if (cost < best_cost) {
          best_cost = cost;
          best_axis = axis;
          best_split = s;
        }
      }
    }
    if (best_split < 0) return median(best_axis);
    const int axis = best_axis;
    auto it = std::partition(items.begin() + lo, items.begin() + hi, [&](uint32_t li) {
      int k = int(kBuckets * (centroid[li][axis] - clo[axis]) / ext[axis]);
      return std::min(std::max(k, 0), kBuckets - 1) <= best_split;
    });
    const size_t mid = size_t(it - items.begin());
    return (mid == lo || mid == hi) ? median(axis) : mid;
  }
};

}  // namespace

std::vector<LightTreeNode> build_light_tree(std::vector<LightGpu>& lights, uint32_t first,
                                            const std::vector<double>& power) {
  const size_t n = lights.size() - first;
  if (n == 0) return {};
  if (power.size() != n) throw std::logic_error("build_light_tree: one power per light");
  Builder b;
  b.lights = &lights;
  b.first = first;
  for (size_t i = 0; i < n; ++i) {
    b.bounds.push_back(light_bounds(lights[first + i], power[i]));
    b.centroid.push_back(0.5 * (b.bounds.back().lo + b.bounds.back().hi));
  }
  std::vector<uint32_t> items(n);
  std::iota(items.begin(), items.end(), 0u);
  b.nodes.reserve(2 * n);
  b.build(items, 0, n, 0, 0u);
  return b.nodes;
}

}  // namespace aw
