// Preetham et al. 1999 daylight sky (host/scene/sky.h): zenith values against the paper's formulas,
// symmetry and shape of the distribution, numerical safety, the lat-long bake and the sun's colour.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "host/scene/sky.h"

namespace {

constexpr double kPi = 3.14159265358979323846;

double deg(double d) { return d * kPi / 180.0; }

// Rec.709 luminance, the weights the renderer uses.
double luminance(const glm::vec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

// Unit direction with zenith angle `theta` from +Y and azimuth `phi` measured from -Z towards +X
// (the lat-long convention of bake_sky_latlong).
glm::vec3 dir_from(double theta, double phi) {
  const double st = std::sin(theta);
  return glm::vec3(glm::dvec3(st * std::sin(phi), std::cos(theta), -st * std::cos(phi)));
}

bool finite_non_negative(const glm::vec3& c) {
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(c[i]) || c[i] < 0.0f) return false;
  }
  return true;
}

// The paper's zenith formulas, written out again independently of sky.cpp (Preetham et al. 1999,
// Appendix A.2): Y_z in kcd/m^2, and the zenith chromaticity polynomials.
double paper_zenith_Y_kcd(double t, double theta_s) {
  const double chi = (4.0 / 9.0 - t / 120.0) * (kPi - 2.0 * theta_s);
  return (4.0453 * t - 4.9710) * std::tan(chi) - 0.2155 * t + 2.4192;
}
double paper_zenith_x(double t, double s) {
  return (0.00166 * s * s * s - 0.00375 * s * s + 0.00209 * s) * t * t +
         (-0.02903 * s * s * s + 0.06377 * s * s - 0.03202 * s + 0.00394) * t +
         (0.11693 * s * s * s - 0.21196 * s * s + 0.06052 * s + 0.25886);
}
double paper_zenith_y(double t, double s) {
  return (0.00275 * s * s * s - 0.00610 * s * s + 0.00317 * s) * t * t +
         (-0.04214 * s * s * s + 0.08970 * s * s - 0.04153 * s + 0.00516) * t +
         (0.15346 * s * s * s - 0.26756 * s * s + 0.06670 * s + 0.26688);
}

// CIE xy chromaticity of a linear Rec.709 colour (IEC 61966-2-1 RGB -> XYZ).
glm::dvec2 chromaticity(const glm::vec3& c) {
  const double x = 0.4124 * c.x + 0.3576 * c.y + 0.1805 * c.z;
  const double y = 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
  const double z = 0.0193 * c.x + 0.1192 * c.y + 0.9505 * c.z;
  return {x / (x + y + z), y / (x + y + z)};
}

// (a) At the zenith F(0, gamma = theta_s) / F(0, theta_s) = 1, so the radiance is the paper's zenith
// value: luminance Y_z * 1000 cd/m^2 and chromaticity (x_z, y_z).
TEST(PreethamSky, ZenithMatchesPaperFormulas) {
  for (double t : {2.0, 3.0, 5.0}) {
    for (double zen_deg : {30.0, 60.0}) {
      const double theta_s = deg(zen_deg);
      const aw::SkyModel s = aw::make_preetham_sky(dir_from(theta_s, deg(40.0)), float(t), glm::vec3(0.2f));
      const glm::vec3 z = aw::sky_radiance(s, glm::vec3(0, 1, 0));
      const double expected = 1000.0 * paper_zenith_Y_kcd(t, theta_s);
      EXPECT_NEAR(luminance(z), expected, 1e-3 * expected) << "T " << t << " theta_s " << zen_deg;
      const glm::dvec2 xy = chromaticity(z);
      EXPECT_NEAR(xy.x, paper_zenith_x(t, theta_s), 1e-4) << "T " << t << " theta_s " << zen_deg;
      EXPECT_NEAR(xy.y, paper_zenith_y(t, theta_s), 1e-4) << "T " << t << " theta_s " << zen_deg;
    }
  }
}

// (b) The distribution depends on the view only through theta and gamma, so mirroring a direction
// about the vertical plane through the sun leaves the radiance unchanged.
TEST(PreethamSky, MirrorSymmetricAboutSunPlane) {
  for (double t : {2.0, 5.0}) {
    const double sun_phi = deg(30.0);
    const aw::SkyModel s = aw::make_preetham_sky(dir_from(deg(50.0), sun_phi), float(t), glm::vec3(0.3f));
    // Normal of the vertical plane through the sun: horizontal, perpendicular to the sun's azimuth.
    const glm::dvec3 n = glm::dvec3(dir_from(0.5 * kPi, sun_phi + 0.5 * kPi));
    int checked = 0;
    for (int i = 0; i < 30; ++i) {
      const double theta = (i + 0.5) / 30.0 * 0.5 * kPi;
      for (int j = 0; j < 60; ++j) {
        const double phi = (j + 0.5) / 60.0 * 2.0 * kPi;
        const glm::dvec3 d = glm::dvec3(dir_from(theta, phi));
        const glm::dvec3 m = d - 2.0 * glm::dot(d, n) * n;
        const glm::vec3 a = aw::sky_radiance(s, glm::vec3(d));
        const glm::vec3 b = aw::sky_radiance(s, glm::vec3(m));
        for (int c = 0; c < 3; ++c) {
          EXPECT_NEAR(a[c], b[c], 1e-4f * std::max(a[c], 1.0f)) << "theta " << theta << " phi " << phi;
        }
        ++checked;
      }
    }
    EXPECT_EQ(checked, 1800);
  }
}

// (c) Circumsolar brightening: at the same elevation the sky towards the sun's azimuth is brighter
// than the opposite azimuth.
TEST(PreethamSky, BrighterTowardsSun) {
  const double sun_phi = deg(-70.0);
  const aw::SkyModel s = aw::make_preetham_sky(dir_from(deg(45.0), sun_phi), 3.0f, glm::vec3(0.2f));
  for (double view_zen_deg : {10.0, 30.0, 45.0, 60.0, 80.0, 88.0}) {
    const double theta = deg(view_zen_deg);
    const double towards = luminance(aw::sky_radiance(s, dir_from(theta, sun_phi)));
    const double away = luminance(aw::sky_radiance(s, dir_from(theta, sun_phi + kPi)));
    EXPECT_GT(towards, away) << "view zenith " << view_zen_deg;
  }
}

// (d) Finite and non-negative everywhere, including the horizon, straight down, the sun itself, and
// suns at and below the horizon.
TEST(PreethamSky, OutputsFiniteAndNonNegative) {
  for (float t : {1.7f, 2.0f, 5.0f, 10.0f}) {
    for (double zen_deg : {0.0, 45.0, 89.0, 90.0, 95.0}) {
      const glm::vec3 sun = dir_from(deg(zen_deg), deg(20.0));
      const aw::SkyModel s = aw::make_preetham_sky(sun, t, glm::vec3(0.25f, 0.2f, 0.15f));
      ASSERT_TRUE(finite_non_negative(s.horizontal_illuminance)) << "T " << t << " zen " << zen_deg;
      ASSERT_TRUE(finite_non_negative(s.ground_radiance)) << "T " << t << " zen " << zen_deg;
      EXPECT_GT(luminance(s.horizontal_illuminance), 0.0) << "T " << t << " zen " << zen_deg;
      std::vector<glm::vec3> dirs = {glm::vec3(0, 1, 0), glm::vec3(0, -1, 0), sun, glm::vec3(1, 0, 0),
                                     glm::vec3(0, 0, -1), glm::vec3(sun.x, 0.0f, sun.z),
                                     glm::vec3(sun.x, 1e-7f, sun.z), glm::vec3(-sun.x, 1e-4f, -sun.z)};
      for (int i = 0; i <= 180; ++i) {
        for (int j = 0; j < 360; ++j) dirs.push_back(dir_from(deg(i), deg(j)));
      }
      int bad = 0;
      for (const glm::vec3& d : dirs) {
        const glm::vec3 l = aw::sky_radiance(s, d);
        if (!finite_non_negative(l)) {
          if (++bad < 5) {
            ADD_FAILURE() << "T " << t << " zen " << zen_deg << " dir " << d.x << " " << d.y << " " << d.z;
          }
        }
      }
      EXPECT_EQ(bad, 0) << "T " << t << " zen " << zen_deg;
      EXPECT_GT(luminance(aw::sky_radiance(s, glm::vec3(0, 1, 0))), 0.0);
      for (float v : aw::bake_sky_latlong(s, 32, 16)) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f);
      EXPECT_TRUE(finite_non_negative(aw::sun_transmittance_rgb(t, float(deg(zen_deg)))));
    }
  }
}

// (e) Lat-long layout: size, the zenith row, the constant ground below the horizon, where +X lies.
TEST(PreethamSky, BakeLatLong) {
  const int w = 64, h = 32;
  const glm::vec3 albedo(0.3f, 0.2f, 0.1f);
  // Sun 60 deg from the zenith towards +X: phi = 90 deg, i.e. column 3/4 of the width.
  const aw::SkyModel s = aw::make_preetham_sky(dir_from(deg(60.0), 0.5 * kPi), 3.0f, albedo);
  const std::vector<float> img = aw::bake_sky_latlong(s, w, h);
  ASSERT_EQ(img.size(), size_t(w) * h * 3);
  auto px = [&](int row, int col) {
    const float* p = &img[(size_t(row) * w + col) * 3];
    return glm::vec3(p[0], p[1], p[2]);
  };
  // Row 0 holds the centres nearest the zenith (all columns equally near).
  const double theta0 = 0.5 / h * kPi;
  for (int col : {0, w / 2, w - 1}) {
    const double phi = ((col + 0.5) / w - 0.5) * 2.0 * kPi;
    const glm::vec3 expected = aw::sky_radiance(s, dir_from(theta0, phi));
    const glm::vec3 got = px(0, col);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], expected[c], 1e-5f * expected[c]) << "col " << col;
  }
  // Below the horizon: the constant ground, albedo * E_h / pi.
  const glm::vec3 ground = albedo * s.horizontal_illuminance / float(kPi);
  EXPECT_GT(luminance(ground), 0.0);
  for (int row = h / 2; row < h; ++row) {
    for (int col = 0; col < w; ++col) {
      const glm::vec3 g = px(row, col);
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(g[c], ground[c], 1e-5f * ground[c]) << row << " " << col;
    }
  }
  // The brightest sky pixel is next to the sun: in the column at phi = 90 deg (+X).
  int best_row = 0, best_col = 0;
  double best = -1.0;
  for (int row = 0; row < h / 2; ++row) {
    for (int col = 0; col < w; ++col) {
      const double l = luminance(px(row, col));
      if (l > best) best = l, best_row = row, best_col = col;
    }
  }
  EXPECT_TRUE(best_col == 3 * w / 4 || best_col == 3 * w / 4 - 1) << best_col;
  EXPECT_NEAR((best_row + 0.5) / h * 180.0, 60.0, 180.0 / h);
  // Degenerate sizes give nothing rather than garbage.
  EXPECT_TRUE(aw::bake_sky_latlong(s, 0, 8).empty());
  EXPECT_TRUE(aw::bake_sky_latlong(s, 8, -1).empty());
}

// E_h from make_preetham_sky agrees with an independent, finer integral of sky_radiance * cos over the
// upper hemisphere (uniform in cos(theta), so the cosine weight is exact).
TEST(PreethamSky, HorizontalIlluminanceMatchesIndependentIntegral) {
  for (double zen_deg : {0.0, 30.0, 75.0}) {
    const aw::SkyModel s = aw::make_preetham_sky(dir_from(deg(zen_deg), deg(10.0)), 3.0f, glm::vec3(1.0f));
    const int nu = 400, nphi = 800;
    glm::dvec3 e(0.0);
    for (int i = 0; i < nu; ++i) {
      const double mu = (i + 0.5) / nu;  // cos(theta)
      const double theta = std::acos(mu);
      for (int j = 0; j < nphi; ++j) {
        e += glm::dvec3(aw::sky_radiance(s, dir_from(theta, (j + 0.5) / nphi * 2.0 * kPi))) * mu;
      }
    }
    e *= (1.0 / nu) * (2.0 * kPi / nphi);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(s.horizontal_illuminance[c], e[c], 2e-3 * e[c]) << "zen " << zen_deg;
    }
    // With albedo 1 the ground radiance is E_h / pi.
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(s.ground_radiance[c], s.horizontal_illuminance[c] / kPi, 1e-5 * s.ground_radiance[c]);
    }
  }
}

// A sun below the horizon is evaluated as a sun just above it: still a (dim, finite) dusk sky.
TEST(PreethamSky, SunBelowHorizonClampsToHorizon) {
  const glm::vec3 albedo(0.2f);
  const aw::SkyModel below = aw::make_preetham_sky(dir_from(deg(100.0), deg(15.0)), 3.0f, albedo);
  const aw::SkyModel at = aw::make_preetham_sky(dir_from(aw::kMaxSunZenith, deg(15.0)), 3.0f, albedo);
  EXPECT_NEAR(below.model_sun_zenith, aw::kMaxSunZenith, 1e-9);
  for (const glm::vec3& d :
       {glm::vec3(0, 1, 0), dir_from(deg(70.0), deg(15.0)), dir_from(deg(80.0), deg(200.0))}) {
    const glm::vec3 a = aw::sky_radiance(below, d), b = aw::sky_radiance(at, d);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1e-4f * std::max(b[c], 1.0f));
    EXPECT_GT(luminance(a), 0.0);
  }
}

// (f) The direct sun: unit luminance, reddened, more so for a lower sun and a hazier atmosphere.
TEST(PreethamSky, SunTransmittanceReddens) {
  for (float t : {1.7f, 2.0f, 3.0f, 5.0f, 10.0f}) {
    double prev_ratio = 1e30;
    for (int zen = 0; zen <= 85; zen += 5) {
      const glm::vec3 c = aw::sun_transmittance_rgb(t, float(deg(zen)));
      ASSERT_TRUE(finite_non_negative(c));
      EXPECT_NEAR(luminance(c), 1.0, 1e-5) << "T " << t << " zen " << zen;
      EXPECT_GE(c.x, c.y) << "T " << t << " zen " << zen;
      EXPECT_GE(c.y, c.z) << "T " << t << " zen " << zen;
      const double ratio = c.z / c.x;
      // Strictly redder while blue is left; once the blue channel has left the Rec.709 gamut (clamped
      // to 0) it stays there.
      if (prev_ratio > 0.0) {
        EXPECT_LT(ratio, prev_ratio) << "T " << t << " zen " << zen;
      } else {
        EXPECT_EQ(ratio, 0.0) << "T " << t << " zen " << zen;
      }
      prev_ratio = ratio;
    }
  }
  for (int zen : {0, 30, 60, 85}) {
    double prev_ratio = 1e30;
    for (float t : {1.7f, 2.0f, 3.0f, 5.0f, 7.0f, 10.0f}) {
      const glm::vec3 c = aw::sun_transmittance_rgb(t, float(deg(zen)));
      const double ratio = c.z / c.x;
      if (prev_ratio > 0.0) {
        EXPECT_LT(ratio, prev_ratio) << "T " << t << " zen " << zen;
      } else {
        EXPECT_EQ(ratio, 0.0) << "T " << t << " zen " << zen;
      }
      prev_ratio = ratio;
    }
  }
  // Out-of-range zenith angles are clamped, not propagated.
  for (float zen : {-0.5f, 1.6f, 2.0f, 3.2f, NAN}) {
    const glm::vec3 c = aw::sun_transmittance_rgb(3.0f, zen);
    EXPECT_TRUE(finite_non_negative(c));
    EXPECT_NEAR(luminance(c), 1.0, 1e-5);
  }
}

}  // namespace
