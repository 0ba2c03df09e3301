// Solid-angle sampling of rectangular quad lights (kernels/lights/lights.h: Urena, Fajardo &
// King 2013): the samples follow the pdf that MIS reads (a chi-square test of where they
// land against the solid angle of each part of the light, computed by quadrature), the pdf
// integrates to one, and the estimate has the mean of area sampling. And the lights on lanes:
// 16 paths per work-item, each with its own light of any type, equal the host's one-path C++
// bit for bit (LightLanes); the lanes' sine and cosine are accurate (LaneMath).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

#include "kernels/integrator/light_select.h"
#include "kernels/lights/lights.h"
#include "tests/lobes/lobe_harness.h"

namespace {

LightGpu quad_light(glm::vec3 corner, glm::vec3 eu, glm::vec3 ev, bool rectangle) {
  LightGpu l;
  std::memset(&l, 0, sizeof l);
  l.type = AW_LIGHT_QUAD;
  l.flags = AW_LIGHT_TWO_SIDED | (rectangle ? AW_LIGHT_RECTANGLE : 0u);
  store_f3(l.p, corner);
  store_f3(l.u, eu);
  store_f3(l.v, ev);
  glm::vec3 c = glm::cross(eu, ev);
  l.area = glm::length(c);
  store_f3(l.n, c / l.area);
  store_f3(l.radiance, glm::vec3(1.0f));
  l.select_pdf = 1.0f;
  return l;
}

// Solid angle of the part [a0, a1] x [b0, b1] (in edge fractions) of the light seen from o:
// midpoint quadrature of cos_l / d^2 dA, in double.
double solid_angle(const LightGpu& l, glm::dvec3 o, double a0, double a1, double b0, double b1, int m = 48) {
  glm::dvec3 p(l.p[0], l.p[1], l.p[2]), eu(l.u[0], l.u[1], l.u[2]), ev(l.v[0], l.v[1], l.v[2]);
  glm::dvec3 n = glm::normalize(glm::cross(eu, ev));
  double area = glm::length(glm::cross(eu, ev)) * (a1 - a0) * (b1 - b0) / (m * m), s = 0.0;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      glm::dvec3 y = p + (a0 + (a1 - a0) * (i + 0.5) / m) * eu + (b0 + (b1 - b0) * (j + 0.5) / m) * ev;
      glm::dvec3 d = y - o;
      double d2 = glm::dot(d, d);
      s += std::fabs(glm::dot(n, d)) / (d2 * std::sqrt(d2)) * area;
    }
  return s;
}

// Upper 1e-3 quantile of chi-square with k degrees of freedom (Wilson & Hilferty 1931).
double chi2_critical_1e3(int k) {
  double z = 3.0902, h = 2.0 / (9.0 * k);
  return k * std::pow(1.0 - h + z * std::sqrt(h), 3.0);
}

TEST(SphericalRectangle, SamplesFollowTheSolidAngle) {
  const LightGpu l = quad_light({-0.5f, 0.0f, -0.3f}, {1.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.6f}, true);
  for (glm::vec3 o : {glm::vec3(0.2f, -0.4f, 0.1f), glm::vec3(-0.3f, -0.2f, 0.4f), glm::vec3(0.0f, 0.5f, 0.0f)}) {
    SphRect r;
    ASSERT_TRUE(light_quad_by_solid_angle(light_load(&l, 1u, 0u), o, &r));
    const int g = 8, n = 200000;
    std::vector<double> expect(g * g);
    double total = 0.0;
    for (int i = 0; i < g; ++i)
      for (int j = 0; j < g; ++j) total += expect[i * g + j] = solid_angle(l, o, double(i) / g, double(i + 1) / g,
                                                                          double(j) / g, double(j + 1) / g);
    EXPECT_NEAR(r.S, total, 2e-4 * total);  // the pdf 1/S integrates to one over the light
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> U(0.0f, 0.99999994f);
    std::vector<double> count(g * g, 0.0);
    for (int k = 0; k < n; ++k) {
      LightSample s = light_sample(light_load(&l, 1u, 0u), o, float2(U(rng), U(rng)));
      ASSERT_GT(s.pdf, 0.0f);
      ASSERT_FLOAT_EQ(s.pdf, 1.0f / r.S);
      ASSERT_FLOAT_EQ(light_pdf(light_load(&l, 1u, 0u), o, s.wi, s.dist), s.pdf);  // what MIS reads for the same direction
      glm::vec3 y = o + s.dist * s.wi - glm::vec3(-0.5f, 0.0f, -0.3f);
      int a = std::min(g - 1, std::max(0, int(y.x / 1.0f * g))), b = std::min(g - 1, std::max(0, int(y.z / 0.6f * g)));
      ASSERT_NEAR(y.y, 0.0f, 1e-4f);  // on the light's plane
      count[a * g + b] += 1.0;
    }
    double chi2 = 0.0;
    for (int c = 0; c < g * g; ++c) {
      double e = n * expect[c] / total;
      chi2 += (count[c] - e) * (count[c] - e) / e;
    }
    EXPECT_LT(chi2, chi2_critical_1e3(g * g - 1)) << "eye at " << o.x << " " << o.y << " " << o.z;
  }
}

// Irradiance-like estimate E = integral of L cos_p over the light, by solid-angle sampling and
// by area sampling (the same light without the rectangle flag): the same mean, the quadrature
// value, within 4 standard errors; and solid-angle sampling has the smaller variance close to
// the light, which is why it is there.
TEST(SphericalRectangle, SameMeanAsAreaSamplingAndLessVariance) {
  const glm::vec3 o(0.3f, -0.25f, 0.1f), np(0.0f, 1.0f, 0.0f);
  double exact = 0.0;
  {
    glm::dvec3 od(o), p(-0.5, 0.0, -0.3);
    const int m = 400;
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j) {
        glm::dvec3 y = p + glm::dvec3((i + 0.5) / m, 0.0, 0.6 * (j + 0.5) / m);
        glm::dvec3 d = y - od;
        double d2 = glm::dot(d, d), dl = std::sqrt(d2);
        exact += (d.y / dl) * (d.y / dl) / d2 * (0.6 / (m * m));  // cos_p cos_l / d^2 dA
      }
  }
  double mean[2], var[2];
  for (int rect = 0; rect < 2; ++rect) {
    const LightGpu l = quad_light({-0.5f, 0.0f, -0.3f}, {1.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.6f}, rect == 1);
    std::mt19937 rng(5 + rect);
    std::uniform_real_distribution<float> U(0.0f, 0.99999994f);
    const int n = 400000;
    double s = 0.0, s2 = 0.0;
    for (int k = 0; k < n; ++k) {
      LightSample ls = light_sample(light_load(&l, 1u, 0u), o, float2(U(rng), U(rng)));
      double v = ls.pdf > 0.0f ? double(ls.le.x) * std::max(0.0f, glm::dot(ls.wi, np)) / ls.pdf : 0.0;
      s += v;
      s2 += v * v;
    }
    mean[rect] = s / n;
    var[rect] = s2 / n - mean[rect] * mean[rect];
    EXPECT_NEAR(mean[rect], exact, 4.0 * std::sqrt(var[rect] / n)) << (rect ? "solid angle" : "area");
  }
  std::printf("E = %.6f: area sampling %.6f (variance %.4g), solid angle %.6f (variance %.4g)\n", exact, mean[0],
              var[0], mean[1], var[1]);
  EXPECT_LT(var[1], 0.5 * var[0]);
}

TEST(SphericalRectangle, FarLightsAndParallelogramsAreSampledByArea) {
  const LightGpu rect = quad_light({-0.5f, 0.0f, -0.5f}, {1.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}, true);
  SphRect r;
  EXPECT_TRUE(light_quad_by_solid_angle(light_load(&rect, 1u, 0u), glm::vec3(0.0f, -0.5f, 0.0f), &r));   // S = 2.06 sr
  EXPECT_FALSE(light_quad_by_solid_angle(light_load(&rect, 1u, 0u), glm::vec3(0.0f, -1.0f, 0.0f), &r));  // the bound passes (A h / d^3 = 1), S = 0.80 sr does not
  EXPECT_FALSE(light_quad_by_solid_angle(light_load(&rect, 1u, 0u), glm::vec3(0.0f, -20.0f, 0.0f), &r));  // S ~ 2.5e-3 sr
  glm::vec3 far(0.1f, -20.0f, 0.2f);
  LightSample s = light_sample(light_load(&rect, 1u, 0u), far, float2(0.3f, 0.6f));
  glm::vec3 y = far + s.dist * s.wi;
  EXPECT_NEAR(y.x, -0.2f, 1e-4f);  // the area parametrisation: corner + u edge_u + v edge_v
  EXPECT_NEAR(y.z, 0.1f, 1e-4f);
  const LightGpu skew = quad_light({-0.5f, 0.0f, -0.5f}, {1.0f, 0.0f, 0.0f}, {0.5f, 0.0f, 1.0f}, false);
  EXPECT_FALSE(light_quad_by_solid_angle(light_load(&skew, 1u, 0u), glm::vec3(0.0f, -1.0f, 0.0f), &r));
}

// The cheap bound that skips the exact solid angle (S <= A |h| / d^3, d the distance to the
// nearest point of the rectangle) never skips a rectangle the exact S would take: over
// points all around a light, the decision equals the exact one, S in (1 sr, 2 pi - 1e-2).
TEST(SphericalRectangle, TheBoundSkipsOnlyWhatTheExactSolidAngleRejects) {
  const LightGpu l = quad_light({-0.5f, 0.0f, -0.3f}, {1.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.6f}, true);
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> uni(-2.0f, 2.0f);
  int taken = 0, skipped_by_bound = 0;
  for (int i = 0; i < 20000; ++i) {
    glm::vec3 p(uni(rng), 0.5f * uni(rng), uni(rng));
    if (std::fabs(p.y) < 1e-3f) continue;
    SphRect exact = sph_rect_make(glm::vec3(-0.5f, 0.0f, -0.3f), glm::vec3(1, 0, 0), glm::vec3(0, 0, 0.6f), p);
    bool want = exact.S > AW_SPH_RECT_MIN_SOLID_ANGLE && exact.S < AW_SPH_RECT_MAX_SOLID_ANGLE && std::isfinite(exact.S);
    SphRect r;
    bool got = light_quad_by_solid_angle(light_load(&l, 1u, 0u), p, &r) != 0;
    ASSERT_EQ(got, want) << "p = " << p.x << " " << p.y << " " << p.z << ", S = " << exact.S;
    taken += got;
    // The old bound A / h^2 would have computed the exact S here:
    skipped_by_bound += !want && l.area >= AW_SPH_RECT_MIN_SOLID_ANGLE * p.y * p.y;
  }
  EXPECT_GT(taken, 100);             // the test covers both outcomes
  EXPECT_GT(skipped_by_bound, 1000);  // and many points the old bound A / h^2 let through to the exact S
}

// Every light type in one table: rectangles (one- and two-sided), a parallelogram, disks,
// spheres (points inside and outside them), triangles, a point light, soft and hard suns.
std::vector<LightGpu> lane_test_lights(std::mt19937& rng) {
  std::uniform_real_distribution<float> uni(0.0f, 1.0f);
  std::vector<LightGpu> ls;
  auto base = [&](uint32_t type) {
    LightGpu l;
    std::memset(&l, 0, sizeof l);
    l.type = type;
    store_f3(l.radiance, glm::vec3(1.0f + uni(rng), 2.0f * uni(rng), 0.5f));
    return l;
  };
  ls.push_back(quad_light({-0.5f, 0.3f, -0.5f}, {1.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}, true));
  LightGpu one_sided = quad_light({-1.0f, -0.4f, -0.2f}, {0.0f, 0.0f, 0.7f}, {1.3f, 0.0f, 0.0f}, true);
  one_sided.flags &= ~AW_LIGHT_TWO_SIDED;
  ls.push_back(one_sided);
  ls.push_back(quad_light({-0.5f, 0.0f, -0.5f}, {1.0f, 0.0f, 0.0f}, {0.5f, 0.2f, 1.0f}, false));
  for (int k = 0; k < 2; ++k) {
    LightGpu d = base(AW_LIGHT_DISK);
    store_f3(d.p, glm::vec3(0.3f * k, -0.5f, 0.2f));
    glm::vec3 n = glm::normalize(glm::vec3(0.2f, 1.0f, -0.3f * k));
    glm::vec3 t = glm::normalize(glm::cross(n, glm::vec3(1.0f, 0.0f, 0.0f))), b = glm::cross(n, t);
    store_f3(d.n, n);
    store_f3(d.u, t);
    store_f3(d.v, b);
    d.radius = 0.4f + 0.5f * k;
    d.area = float(M_PI) * d.radius * d.radius;
    d.flags = k ? AW_LIGHT_TWO_SIDED : 0u;
    ls.push_back(d);
  }
  for (int k = 0; k < 2; ++k) {
    LightGpu sp = base(AW_LIGHT_SPHERE);
    store_f3(sp.p, glm::vec3(0.2f, 0.1f * k, -0.3f));
    sp.radius = k ? 1.2f : 0.25f;  // the large one holds many of the shading points
    sp.area = 4.0f * float(M_PI) * sp.radius * sp.radius;
    ls.push_back(sp);
  }
  LightGpu tri = base(AW_LIGHT_TRIANGLE);
  glm::vec3 e1(0.8f, 0.1f, 0.0f), e2(0.1f, 0.2f, 0.9f), c = glm::cross(e1, e2);
  store_f3(tri.p, glm::vec3(-0.4f, 0.5f, -0.4f));
  store_f3(tri.u, e1);
  store_f3(tri.v, e2);
  tri.area = 0.5f * glm::length(c);
  store_f3(tri.n, glm::normalize(c));
  tri.flags = AW_LIGHT_TWO_SIDED;
  ls.push_back(tri);
  LightGpu point = base(AW_LIGHT_POINT);
  store_f3(point.p, glm::vec3(0.1f, 0.9f, 0.3f));
  ls.push_back(point);
  for (int k = 0; k < 2; ++k) {
    LightGpu sun = base(AW_LIGHT_SUN);
    store_f3(sun.n, glm::normalize(glm::vec3(0.3f, 1.0f, 0.2f * k)));
    float cos_half = k ? std::cos(0.05f) : 1.0f;  // soft, then hard
    sun.radius = cos_half;
    sun.area = 1.0f - cos_half;
    ls.push_back(sun);
  }
  std::uniform_int_distribution<uint32_t> pick(0, uint32_t(ls.size()) - 1u);
  for (LightGpu& l : ls) {  // a table to pick from (not a consistent distribution: a test of bits)
    l.alias_q = uni(rng);
    l.alias = pick(rng);
    l.select_pdf = 1.0f / float(ls.size());
  }
  return ls;
}

// Each lane's light, of any type, sampled, its density and emission evaluated and a light
// picked, 16 paths per work-item, against the host's C++ of the same functions at one path:
// every output bit equal. Lanes of a block mostly hold different light types (so each type's
// branch runs with the others' lanes masked off); one block in three has one light (so the
// branches taken when every lane agrees run too). Run on the whole table (more lights than
// AW_SMALL_TABLE: every field gathered per lane) and on a table of three (each field a
// broadcast per light and a select per lane, lights/lights.h).
void check_lights_on_lanes(const std::vector<LightGpu>& lights, std::mt19937& rng) {
  const uint32_t n = 8192;
  std::uniform_real_distribution<float> uni(0.0f, 1.0f), box(-1.5f, 1.5f);
  std::uniform_int_distribution<uint32_t> pick(0, uint32_t(lights.size()) - 1u);
  std::vector<float> in(12 * n);
  uint32_t block_light = 0;
  for (uint32_t i = 0; i < n; ++i) {
    if (i % 16 == 0) block_light = pick(rng);
    uint32_t li = (i / 16) % 3 == 0 ? block_light : pick(rng);
    glm::vec3 dir = glm::normalize(glm::vec3(box(rng), box(rng), box(rng)));
    float bits;
    std::memcpy(&bits, &li, 4);
    float near = i % 2 ? 0.4f : 1.0f;  // half the points close to the lights: large solid angles
    float vals[12] = {near * box(rng), near * box(rng), near * box(rng), uni(rng), uni(rng), dir.x, dir.y, dir.z,
                      0.1f + 2.0f * uni(rng), bits, uni(rng), 25.0f * (uni(rng) - 0.4f)};
    for (uint32_t k = 0; k < 12; ++k) in[k * n + i] = vals[k];
  }
  const uint32_t num = uint32_t(lights.size());
  const uint32_t outs = 16;
  std::vector<float> dev = aw::lobe_test::run_device_probe(
      "tests/probe_lanes.cl", "probe_lights_lanes", in, outs, n,
      {{lights.data(), lights.size() * sizeof(LightGpu)}, {&num, sizeof num}});
  size_t differ = 0, sampled = 0, by_solid_angle = 0;
  for (uint32_t i = 0; i < n; ++i) {
    glm::vec3 p(in[i], in[n + i], in[2 * n + i]), dir(in[5 * n + i], in[6 * n + i], in[7 * n + i]);
    uint32_t li;
    std::memcpy(&li, &in[9 * n + i], 4);
    LightL l = light_load(lights.data(), num, li);
    LightSample s = light_sample(l, p, float2(in[3 * n + i], in[4 * n + i]));
    glm::vec3 le = light_emitted(l, dir);
    uint32_t picked = light_pick(lights.data(), num, in[10 * n + i]);
    float r[outs];
    float sx, cx;
    l_sincos(in[11 * n + i], &sx, &cx);
    float fr[16] = {s.wi.x, s.wi.y, s.wi.z, s.dist, s.le.x, s.le.y, s.le.z, s.pdf, s.is_delta ? 1.0f : 0.0f,
                    light_pdf(l, p, dir, in[8 * n + i]), le.x, le.y, le.z, 0.0f, sx, cx};
    std::memcpy(r, fr, sizeof fr);
    std::memcpy(&r[13], &picked, 4);
    sampled += s.pdf > 0.0f;
    SphRect rect;
    by_solid_angle += l.type == AW_LIGHT_QUAD && light_quad_by_solid_angle(l, p, &rect);
    for (uint32_t k = 0; k < outs; ++k) {
      float d = dev[k * n + i];
      if (std::memcmp(&r[k], &d, 4) != 0 && differ++ < 10)
        ADD_FAILURE() << "output " << k << " at item " << i << " (light " << li << ", type " << lights[li].type
                      << "): host " << r[k] << ", 16 lanes " << d;
    }
  }
  EXPECT_EQ(differ, 0u);
  EXPECT_GT(sampled, n / 2);       // most samples are live ones
  EXPECT_GT(by_solid_angle, 300u);  // and the spherical rectangles ran
}

TEST(LightLanes, SixteenPathsPerWorkItemEqualTheHostBitForBit) {
  std::mt19937 rng(51205);
  const std::vector<LightGpu> lights = lane_test_lights(rng);
  ASSERT_GT(lights.size(), size_t(AW_SMALL_TABLE));  // the gathered form
  check_lights_on_lanes(lights, rng);
}

TEST(LightLanes, ASmallTableEqualsTheHostBitForBit) {
  std::mt19937 rng(61206);
  std::vector<LightGpu> all = lane_test_lights(rng), lights;
  for (const LightGpu& l : all)  // a quad (sampled by solid angle near it), a sphere, a point light
    if ((l.type == AW_LIGHT_QUAD && lights.empty()) || (l.type == AW_LIGHT_SPHERE && lights.size() == 1) ||
        (l.type == AW_LIGHT_POINT && lights.size() == 2))
      lights.push_back(l);
  ASSERT_EQ(lights.size(), 3u);
  ASSERT_LE(lights.size(), size_t(AW_SMALL_TABLE));  // the broadcast form
  std::uniform_int_distribution<uint32_t> pick(0, 2);
  for (LightGpu& l : lights) l.alias = pick(rng);  // aliases within the table
  check_lights_on_lanes(lights, rng);
}

// Next-event estimation's choice of a light and of a point on it (shade_pick_light: the alias
// table, the sampler's dimensions, the combined density), 16 paths per work-item against the
// host, bit for bit, for one light (no pick drawn) and for the whole table.
TEST(LightLanes, PickingALightEqualsTheHostBitForBit) {
  const uint32_t n = 4096, nu = AW_SU_COUNT;
  std::mt19937 rng(51207);
  std::uniform_real_distribution<float> box(-1.0f, 1.0f);
  const std::vector<LightGpu> lights = lane_test_lights(rng);
  std::vector<float> in((nu + 3) * n, 0.0f);
  std::vector<uint32_t> su(nu * n, 0u);
  for (uint32_t i = 0; i < n; ++i) {
    su[AW_SU_pixel * n + i] = rng() % 65536u;
    su[AW_SU_sample * n + i] = rng() % 256u;
    su[AW_SU_bounce * n + i] = rng() % 6u;
    for (uint32_t k = 0; k < 3; ++k) in[(nu + k) * n + i] = box(rng);
  }
  std::memcpy(in.data(), su.data(), su.size() * 4);
  for (uint32_t num : {1u, uint32_t(lights.size())}) {
    RenderParams rp;
    std::memset(&rp, 0, sizeof rp);
    rp.sampler = AW_SAMPLER_SOBOL;
    rp.seed = 3u;
    rp.num_lights = num;
    const uint32_t outs = 11;
    std::vector<float> dev = aw::lobe_test::run_device_probe(
        "tests/probe_lanes.cl", "probe_pick_light_lanes", in, outs, n,
        {{lights.data(), lights.size() * sizeof(LightGpu)}, {&rp, sizeof rp}});
    SceneRef sc;
    std::memset(&sc, 0, sizeof sc);
    sc.lights = lights.data();
    size_t differ = 0, live = 0;
    std::vector<size_t> picked(lights.size(), 0);
    for (uint32_t i = 0; i < n; ++i) {
      PathRef ps;
      std::memset(&ps, 0, sizeof ps);
      ps.su = su.data();
      ps.pool = n;
      ps.slot = i;
      uint32_t light;
      float pdf;
      LightSample s = shade_pick_light(ps, sc, &rp, glm::vec3(in[nu * n + i], in[(nu + 1) * n + i], in[(nu + 2) * n + i]),
                                       &light, &pdf);
      live += pdf > 0.0f;
      ++picked[light];
      float fr[11] = {s.wi.x, s.wi.y, s.wi.z, s.dist, s.le.x, s.le.y, s.le.z, s.pdf, s.is_delta ? 1.0f : 0.0f, 0.0f, pdf};
      std::memcpy(&fr[9], &light, 4);
      for (uint32_t k = 0; k < outs; ++k)
        if (std::memcmp(&fr[k], &dev[k * n + i], 4) != 0 && differ++ < 10)
          ADD_FAILURE() << num << " lights, output " << k << " at item " << i << ": host " << fr[k] << ", 16 lanes "
                        << dev[k * n + i];
    }
    EXPECT_EQ(differ, 0u) << num << " lights";
    EXPECT_GT(live, n / 3) << num << " lights";
    if (num > 1) {
      for (size_t li = 0; li < lights.size(); ++li) EXPECT_GT(picked[li], 0u) << "light " << li << " never picked";
    }
  }
}

// l_sincos against double precision over the range a spherical rectangle's angles take and
// beyond (|x| <= 25), 4M points: absolute error below 2^-23 (measured: 9.2e-8 for sin, 9.1e-8
// for cos; the polynomials' own ~1 ulp of results of magnitude up to 1, plus the reduction's).
TEST(LaneMath, SinCosIsAccurate) {
  double worst_s = 0.0, worst_c = 0.0;
  const int m = 1 << 22;
  for (int i = 0; i <= m; ++i) {
    float x = -25.0f + 50.0f * float(i) / float(m);
    float s, c;
    l_sincos(x, &s, &c);
    double es = std::fabs(double(s) - std::sin(double(x)));
    double ec = std::fabs(double(c) - std::cos(double(x)));
    worst_s = std::fmax(worst_s, es);
    worst_c = std::fmax(worst_c, ec);
  }
  std::printf("l_sincos: worst error sin %.3g, cos %.3g\n", worst_s, worst_c);
  EXPECT_LT(worst_s, 1.2e-7);
  EXPECT_LT(worst_c, 1.2e-7);
}

}  // namespace
