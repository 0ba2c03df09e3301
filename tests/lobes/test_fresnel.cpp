// Fresnel reflectance (kernels/lobes/fresnel.h) against closed forms and an independent
// double-precision reference, at the extremes (cos exactly 0 and 1, eta exactly 1 and near 1,
// total internal reflection, huge extinction), and host vs device.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <vector>

#include "kernels/tests/probe_basic_lobes.cl"
#include "tests/lobes/lobe_harness.h"

namespace aw {
namespace lobe_test {
namespace {

// Textbook unpolarised dielectric Fresnel in double, through Snell's law and the angles
// (Born & Wolf, Sec. 1.5.2): an independent route to the same physics.
double reference_dielectric(double cos_i, double eta) {
  double sin_i = std::sqrt(std::max(0.0, 1.0 - cos_i * cos_i));
  double sin_t = sin_i / eta;
  if (sin_t >= 1.0) return 1.0;
  double cos_t = std::sqrt(1.0 - sin_t * sin_t);
  double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  double rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  return 0.5 * (rs * rs + rp * rp);
}

// Conductor reference in the real "a, b" form (Born & Wolf, Ch. 14; written with
// a^2 + b^2 = |eta^2 - sin^2|, a = Re sqrt(eta^2 - sin^2)):
//   R_s = (a^2 + b^2 - 2 a c + c^2) / (a^2 + b^2 + 2 a c + c^2),
//   R_p = R_s (c^2 (a^2 + b^2) - 2 a c s^2 + s^4) / (c^2 (a^2 + b^2) + 2 a c s^2 + s^4).
// A different algebraic route from the complex-g form in fresnel.h.
double reference_conductor(double c, double n, double k) {
  double s2 = 1.0 - c * c;
  double t0 = n * n - k * k - s2;
  double a2b2 = std::sqrt(t0 * t0 + 4.0 * n * n * k * k);
  double a = std::sqrt(std::max(0.0, 0.5 * (a2b2 + t0)));
  double rs = (a2b2 - 2.0 * a * c + c * c) / (a2b2 + 2.0 * a * c + c * c);
  double num = c * c * a2b2 - 2.0 * a * c * s2 + s2 * s2;
  double den = c * c * a2b2 + 2.0 * a * c * s2 + s2 * s2;
  double rp = rs * num / den;
  return 0.5 * (rs + rp);
}

TEST(Fresnel, DielectricNormalIncidenceIsClosedForm) {
  for (double eta : {1.0001, 1.1, 1.33, 1.5, 2.42, 1.0 / 1.5, 0.5, 4.0}) {
    double expected = std::pow((eta - 1.0) / (eta + 1.0), 2.0);
    EXPECT_NEAR(fresnel_dielectric(1.0f, float(eta)), expected, 1e-6 * expected + 1e-12) << "eta " << eta;
  }
}

TEST(Fresnel, DielectricBrewsterAngleKeepsOnlyS) {
  // At tan(theta_B) = eta, r_p = 0 and theta_i + theta_t = 90 deg, so cos_t = sin_i and
  // r_s = (1 - eta^2) / (1 + eta^2): R = r_s^2 / 2.
  for (double eta : {1.33, 1.5, 2.0, 1.0 / 1.5}) {
    double cos_b = 1.0 / std::sqrt(1.0 + eta * eta);
    double rs = (1.0 - eta * eta) / (1.0 + eta * eta);
    double expected = 0.5 * rs * rs;
    EXPECT_NEAR(fresnel_dielectric(float(cos_b), float(eta)), expected, 2e-6) << "eta " << eta;
    // It is the minimum of R in a neighbourhood only for the p part; the unpolarised value
    // matches the s-only closed form, and nearby angles differ from it.
    EXPECT_NEAR(fresnel_dielectric(float(cos_b), float(eta)), reference_dielectric(cos_b, eta), 1e-6);
  }
}

TEST(Fresnel, TotalInternalReflectionBeyondTheCriticalAngle) {
  for (double eta : {1.0 / 1.5, 1.0 / 1.33, 0.9, 0.999}) {
    double cos_c = std::sqrt(1.0 - eta * eta);  // sin(theta_c) = eta
    EXPECT_EQ(fresnel_dielectric(float(cos_c * 0.999), float(eta)), 1.0f) << "eta " << eta;
    EXPECT_EQ(fresnel_dielectric(float(cos_c * 0.5), float(eta)), 1.0f) << "eta " << eta;
    EXPECT_EQ(fresnel_dielectric(0.0f, float(eta)), 1.0f) << "eta " << eta;
    float inside = fresnel_dielectric(float(std::min(1.0, cos_c * 1.01 + 1e-4)), float(eta));
    EXPECT_LT(inside, 1.0f) << "eta " << eta;
    EXPECT_GT(inside, 0.0f) << "eta " << eta;
  }
}

TEST(Fresnel, DielectricMatchesReferenceOverAGrid) {
  double worst = 0.0;
  for (double eta : {0.5, 0.67, 0.9, 0.99, 0.9999, 1.0001, 1.01, 1.2, 1.5, 2.0, 3.0, 10.0}) {
    for (int i = 0; i <= 1000; ++i) {
      double c = i / 1000.0;
      double got = fresnel_dielectric(float(c), float(eta));
      double ref = reference_dielectric(double(float(c)), double(float(eta)));
      // Near the critical angle R climbs steeply to 1; compare in absolute terms there.
      double err = std::fabs(got - ref) / std::max(ref, 1e-3);
      worst = std::max(worst, err);
      EXPECT_LE(err, 2e-4) << "cos " << c << " eta " << eta << ": " << got << " vs " << ref;
    }
  }
  RecordProperty("worst_rel_error", std::to_string(worst));
}

TEST(Fresnel, DielectricExtremesAreFiniteAndExact) {
  // eta exactly 1: no interface, no reflection, at every angle (also 0/0 at grazing).
  for (float c : {0.0f, 1e-30f, 0.3f, 1.0f}) EXPECT_EQ(fresnel_dielectric(c, 1.0f), 0.0f) << c;
  // Grazing: everything reflects; normal incidence is the closed form.
  EXPECT_EQ(fresnel_dielectric(0.0f, 1.5f), 1.0f);
  EXPECT_EQ(fresnel_dielectric(0.0f, 1.0f / 1.5f), 1.0f);
  // eta a hair from 1: tiny but not NaN, and continuous toward 0.
  for (float eta : {1.0f + 1e-7f, 1.0f - 6e-8f, 1.0f + 1e-4f, 1.0f - 1e-4f}) {
    for (float c : {0.0f, 1e-20f, 1e-6f, 0.01f, 0.5f, 1.0f}) {
      float r = fresnel_dielectric(c, eta);
      EXPECT_TRUE(std::isfinite(r) && r >= 0.0f && r <= 1.0f) << "eta " << eta << " cos " << c << ": " << r;
      if (c >= 0.5f) {
        EXPECT_LT(r, 1e-6f) << "eta " << eta << " cos " << c;
      }
    }
  }
  // Huge, infinite or zero eta: finite, and (almost) everything reflects.
  for (float eta : {1e6f, 1e30f, INFINITY, 0.0f}) {
    for (float c : {0.0f, 0.5f, 1.0f}) {
      float r = fresnel_dielectric(c, eta);
      EXPECT_TRUE(std::isfinite(r) && r > 0.99999f && r <= 1.0f) << "eta " << eta << " cos " << c << ": " << r;
    }
  }
  // Out-of-range cosines are clamped, never NaN.
  for (float c : {-0.5f, -0.0f, 1.0000001f, 2.0f}) {
    float r = fresnel_dielectric(c, 1.5f);
    EXPECT_TRUE(std::isfinite(r) && r >= 0.0f && r <= 1.0f) << c;
  }
}

TEST(Fresnel, ConductorGoldAtNormalIncidence) {
  const double n = 0.43, k = 2.45;  // gold near 550 nm
  double expected = ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
  EXPECT_NEAR(fresnel_conductor(1.0f, float(n), float(k)), expected, 1e-6);
  EXPECT_NEAR(expected, 0.78627, 1e-5);  // the arithmetic of the closed form itself
}

TEST(Fresnel, ConductorMatchesReferenceOverAGrid) {
  const double nk[][2] = {{0.43, 2.45}, {0.2, 3.9}, {1.5, 0.01}, {2.9, 3.0}, {0.05, 0.1}, {1.0, 1e-3},
                          {0.0, 1.0},   {3.0, 0.0}, {1.0, 50.0}, {100.0, 200.0}};
  for (const auto& p : nk) {
    for (int i = 0; i <= 500; ++i) {
      double c = i / 500.0;
      double got = fresnel_conductor(float(c), float(p[0]), float(p[1]));
      double ref = p[1] == 0.0 ? reference_dielectric(c, p[0]) : reference_conductor(c, p[0], p[1]);
      EXPECT_NEAR(got, ref, 1e-5 + 1e-5 * ref) << "cos " << c << " n " << p[0] << " k " << p[1];
    }
  }
}

TEST(Fresnel, ConductorWithZeroExtinctionIsTheDielectric) {
  for (float n : {0.5f, 0.9f, 1.0f, 1.33f, 1.5f, 2.4f}) {
    for (int i = 0; i <= 200; ++i) {
      float c = i / 200.0f;
      EXPECT_EQ(fresnel_conductor(c, n, 0.0f), fresnel_dielectric(c, n)) << "n " << n << " cos " << c;
    }
  }
  // And continuously so: a tiny k changes little.
  EXPECT_NEAR(fresnel_conductor(0.7f, 1.5f, 1e-4f), fresnel_dielectric(0.7f, 1.5f), 1e-6);
}

TEST(Fresnel, ConductorExtremesAreFinite) {
  const float ns[] = {0.0f, 1e-6f, 0.43f, 1.0f, 1e3f, 1e6f, 1e20f, 3e38f};
  const float ks[] = {0.0f, 1e-6f, 2.45f, 1e3f, 1e6f, 1e20f, 3e38f};
  const float cs[] = {0.0f, 1e-30f, 1e-6f, 0.5f, 1.0f};
  for (float n : ns) {
    for (float k : ks) {
      for (float c : cs) {
        float r = fresnel_conductor(c, n, k);
        EXPECT_TRUE(std::isfinite(r) && r >= 0.0f && r <= 1.0f) << "n " << n << " k " << k << " cos " << c << ": " << r;
      }
    }
  }
  // Grazing reflects everything; huge extinction reflects (almost) everything.
  EXPECT_NEAR(fresnel_conductor(0.0f, 0.43f, 2.45f), 1.0f, 1e-6f);
  EXPECT_GT(fresnel_conductor(1.0f, 1.0f, 1e6f), 0.999999f);
}

TEST(Fresnel, CurveValues) {
  // facing at 0 deg, perpendicular at 90 deg, the power law in between.
  EXPECT_EQ(fresnel_curve(1.0f, 0.2f, 1.0f, 5.0f), 0.2f);
  EXPECT_EQ(fresnel_curve(0.0f, 0.2f, 1.0f, 5.0f), 1.0f);
  EXPECT_NEAR(fresnel_curve(0.5f, 0.2f, 1.0f, 5.0f), 0.2 + 0.8 * std::pow(0.5, 5.0), 1e-7);
  EXPECT_NEAR(fresnel_curve(0.8f, 0.1f, 0.9f, 2.0f), 0.1 + 0.8 * 0.04, 1e-6);
  // A higher curve is tighter: at a fixed angle, closer to the facing value.
  float prev = 2.0f;
  for (float curve : {0.5f, 1.0f, 2.0f, 5.0f, 10.0f}) {
    float r = fresnel_curve(0.6f, 0.2f, 1.0f, curve);
    EXPECT_LT(r, prev) << curve;
    prev = r;
  }
  // curve 0: perpendicular everywhere (pow(0, 0) = 1 at cos = 1); negative curves clamp to 0.
  EXPECT_EQ(fresnel_curve(1.0f, 0.2f, 1.0f, 0.0f), 1.0f);
  EXPECT_EQ(fresnel_curve(1.0f, 0.2f, 1.0f, -3.0f), 1.0f);
}

TEST(Fresnel, CurveWithEqualFacingAndPerpendicularIsConstant) {
  for (float v : {0.0f, 0.04f, 0.5f, 1.0f}) {
    for (float curve : {0.0f, 1.0f, 5.0f, 100.0f}) {
      for (int i = 0; i <= 100; ++i) EXPECT_EQ(fresnel_curve(i / 100.0f, v, v, curve), v);
    }
  }
}

TEST(Fresnel, EvalDispatchesOnMode) {
  FresnelParams f{AW_FRESNEL_DIELECTRIC, 1.5f, 2.0f, 0.1f, 0.8f, 3.0f};
  for (float c : {0.0f, 0.3f, 1.0f}) {
    f.mode = AW_FRESNEL_DIELECTRIC;
    EXPECT_EQ(fresnel_eval(f, c), fresnel_dielectric(c, 1.5f));
    f.mode = AW_FRESNEL_CONDUCTOR;
    EXPECT_EQ(fresnel_eval(f, c), fresnel_conductor(c, 1.5f, 2.0f));
    f.mode = AW_FRESNEL_CURVE;
    EXPECT_EQ(fresnel_eval(f, c), fresnel_curve(c, 0.1f, 0.8f, 3.0f));
  }
}

// Same inputs through the OpenCL build (kernels/tests/probe_basic_lobes.cl) and the host
// build of the same functions. Measured on PoCL 3.1 / LLVM 15 (x86-64): max relative
// difference 0 for the dielectric and conductor (sqrt and division are correctly rounded on
// both sides) and 3.5e-7 for the curve (pow); the tolerance is the suite's 1e-5 relative.
TEST(Fresnel, HostMatchesDevice) {
  Uniform uni(11);
  std::vector<float> in;
  auto push = [&](float c, float eta, float k, float fa, float pe, float cu) {
    for (float v : {c, eta, k, fa, pe, cu}) in.push_back(v);
  };
  for (float c : {0.0f, 1e-30f, 1e-6f, 0.5f, 1.0f}) {
    for (float eta : {1.0f, 1.0f + 1e-7f, 1.5f, 1.0f / 1.5f, 0.43f}) push(c, eta, 2.45f, 0.2f, 1.0f, 5.0f);
  }
  for (int i = 0; i < 4096; ++i) {
    float c = uni.next();
    float eta = 0.3f + 3.0f * uni.next();
    float k = (i % 3 == 0) ? 0.0f : 5.0f * uni.next();
    push(c, eta, k, uni.next(), uni.next(), 10.0f * uni.next());
  }
  size_t n = in.size() / AW_PROBE_FRESNEL_IN;
  std::vector<float> host(n * AW_PROBE_FRESNEL_OUT);
  for (size_t i = 0; i < n; ++i) probe_fresnel_item(&in[i * AW_PROBE_FRESNEL_IN], &host[i * AW_PROBE_FRESNEL_OUT]);
  std::vector<float> device =
      run_device_probe("tests/probe_basic_lobes.cl", "probe_fresnel", in, AW_PROBE_FRESNEL_OUT, n);
  const char* names[AW_PROBE_FRESNEL_OUT] = {"dielectric", "conductor", "curve",
                                             "eval(dielectric)", "eval(conductor)", "eval(curve)"};
  for (size_t k = 0; k < AW_PROBE_FRESNEL_OUT; ++k) {
    ::testing::AssertionResult r =
        host_matches_device(probe_column(host, AW_PROBE_FRESNEL_OUT, k), probe_column(device, AW_PROBE_FRESNEL_OUT, k),
                            kHostDeviceRelTol, kHostDeviceAbsFloor, names[k]);
    EXPECT_TRUE(r);
    if (verbose()) std::printf("  [host/device] %s\n", r.message());
  }
}

}  // namespace
}  // namespace lobe_test
}  // namespace aw
