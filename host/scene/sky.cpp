// Preetham, Shirley & Smits 1999, "A Practical Analytic Model for Daylight" ([P99]); see sky.h.
// Everything is evaluated in double and rounded to float on the way out: the Perez factors are
// ratios of exponentials and the xyY -> RGB step subtracts nearly equal terms.
#include "host/scene/sky.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace aw {
namespace {

constexpr double kPi = 3.14159265358979323846;

// cos(theta) of the view direction is clamped to this at the horizon so that B / cos(theta) stays
// finite: with B < 0 (all of [P99]'s B for T >= 1.7) exp(B / 1e-3) is already 0 in double, so the
// clamp changes nothing visible while avoiding 0/0 and inf * 0.
constexpr double kMinCosTheta = 1e-3;

// Chromaticity y is clamped to this in xyY -> XYZ (X = x Y / y), against a division by ~0.
constexpr double kMinChromaY = 1e-6;

// CIE XYZ -> linear Rec.709 RGB (sRGB primaries, D65 white): the exact inverse of the IEC 61966-2-1
// RGB -> XYZ matrix [0.4124 0.3576 0.1805; 0.2126 0.7152 0.0722; 0.0193 0.1192 0.9505], so that the
// Rec.709 luminance 0.2126 R + 0.7152 G + 0.0722 B of the result gives back CIE Y to double precision
// (the usual 4-digit inverse 3.2406, -1.5372, ... would be off by ~1e-4).
glm::dvec3 xyz_to_rec709(const glm::dvec3& xyz) {
  return {3.2406254773 * xyz.x - 1.5372079722 * xyz.y - 0.4986285987 * xyz.z,
          -0.9689307147 * xyz.x + 1.8757560609 * xyz.y + 0.0415175238 * xyz.z,
          0.0557101204 * xyz.x - 0.2040210506 * xyz.y + 1.0569959423 * xyz.z};
}

double rec709_luminance(const glm::dvec3& rgb) { return 0.2126 * rgb.x + 0.7152 * rgb.y + 0.0722 * rgb.z; }

// Out-of-gamut colours (negative channels) and anything non-finite become 0: callers are promised
// finite, non-negative radiance.
glm::dvec3 sanitise(const glm::dvec3& rgb) {
  glm::dvec3 r;
  for (int i = 0; i < 3; ++i) r[i] = std::isfinite(rgb[i]) ? std::max(rgb[i], 0.0) : 0.0;
  return r;
}

// Perez et al. 1993 all-weather distribution as used by [P99] Sec. "Skylight":
//   F(theta, gamma) = (1 + A exp(B / cos theta)) (1 + C exp(D gamma) + E cos^2 gamma),
// theta the zenith angle of the view direction, gamma the angle between view and sun.
double perez(const PerezCoeffs& k, double cos_theta, double gamma, double cos_gamma) {
  const double ct = std::max(cos_theta, kMinCosTheta);
  return (1.0 + k.a * std::exp(k.b / ct)) * (1.0 + k.c * std::exp(k.d * gamma) + k.e * cos_gamma * cos_gamma);
}

// [P99] Appendix A.2: the distribution coefficients are linear in turbidity, A = a1 T + a0 etc.
PerezCoeffs perez_luminance_Y(double t) {
  return {0.1787 * t - 1.4630, -0.3554 * t + 0.4275, -0.0227 * t + 5.3251, 0.1206 * t - 2.5771,
          -0.0670 * t + 0.3703};
}
PerezCoeffs perez_chroma_x(double t) {
  return {-0.0193 * t - 0.2592, -0.0665 * t + 0.0008, -0.0004 * t + 0.2125, -0.0641 * t - 0.8989,
          -0.0033 * t + 0.0452};
}
PerezCoeffs perez_chroma_y(double t) {
  return {-0.0167 * t - 0.2608, -0.0950 * t + 0.0092, -0.0079 * t + 0.2102, -0.0441 * t - 1.6537,
          -0.0109 * t + 0.0529};
}

// [P99] Appendix A.2, zenith chromaticity: c_z = [T^2 T 1] M [theta_s^3 theta_s^2 theta_s 1]^T with
// theta_s in radians and one 3x4 matrix M for x_z and one for y_z.
double zenith_chromaticity(const double m[3][4], double t, double theta_s) {
  const double tv[3] = {t * t, t, 1.0};
  const double sv[4] = {theta_s * theta_s * theta_s, theta_s * theta_s, theta_s, 1.0};
  double c = 0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 4; ++j) c += tv[i] * m[i][j] * sv[j];
  }
  return c;
}

constexpr double kZenithX[3][4] = {{0.00166, -0.00375, 0.00209, 0.0},
                                   {-0.02903, 0.06377, -0.03202, 0.00394},
                                   {0.11693, -0.21196, 0.06052, 0.25886}};
constexpr double kZenithY[3][4] = {{0.00275, -0.00610, 0.00317, 0.0},
                                   {-0.04214, 0.08970, -0.04153, 0.00516},
                                   {0.15346, -0.26756, 0.06670, 0.26688}};

// [P99] Appendix A.2, zenith luminance in kcd/m^2:
//   Y_z = (4.0453 T - 4.9710) tan(chi) - 0.2155 T + 2.4192,  chi = (4/9 - T/120)(pi - 2 theta_s).
// Clamped to >= 0: the fit goes negative only for T > ~11 with the sun at the horizon.
double zenith_luminance_kcd(double t, double theta_s) {
  const double chi = (4.0 / 9.0 - t / 120.0) * (kPi - 2.0 * theta_s);
  return std::max((4.0453 * t - 4.9710) * std::tan(chi) - 0.2155 * t + 2.4192, 0.0);
}

// Sky radiance (Rec.709 RGB, cd/m^2) for a unit direction in or near the upper hemisphere; the
// horizon clamp of perez() applies to directions with dir.y <= kMinCosTheta.
glm::dvec3 sky_dome_radiance(const SkyModel& s, const glm::dvec3& dir) {
  const double cos_gamma = std::clamp(glm::dot(dir, s.model_to_sun), -1.0, 1.0);
  const double gamma = std::acos(cos_gamma);
  const double cos_theta = dir.y;
  // [P99] Sec. "Skylight": each of Y, x, y is its zenith value times F(theta, gamma) / F(0, theta_s);
  // scale_* hold zenith / F(0, theta_s).
  const double lum = s.scale_Y * perez(s.perez_Y, cos_theta, gamma, cos_gamma);
  const double cx = s.scale_x * perez(s.perez_x, cos_theta, gamma, cos_gamma);
  const double cy = std::max(s.scale_y * perez(s.perez_y, cos_theta, gamma, cos_gamma), kMinChromaY);
  if (!(lum > 0.0)) return glm::dvec3(0.0);
  // xyY -> XYZ (CIE 15): X = x Y / y, Z = (1 - x - y) Y / y.
  const glm::dvec3 xyz(cx * lum / cy, lum, (1.0 - cx - cy) * lum / cy);
  return sanitise(xyz_to_rec709(xyz));
}

// zenith / F(0, theta_s), guarded: for T in [1.7, 10] F(0, theta_s) > 0 (its smallest value, for Y at
// T = 1.7, is ~0.03 from the first factor), but a caller outside that range must not get inf or NaN.
double zenith_scale(double zenith, const PerezCoeffs& k, double theta_s) {
  const double f0 = perez(k, 1.0, theta_s, std::cos(theta_s));
  return (std::isfinite(f0) && f0 > 1e-12) ? zenith / f0 : 0.0;
}

}  // namespace

SkyModel make_preetham_sky(glm::vec3 to_sun, float turbidity, glm::vec3 ground_albedo) {
  SkyModel s;
  glm::dvec3 sun(to_sun);
  const double len = glm::length(sun);
  sun = (std::isfinite(len) && len > 0.0) ? sun / len : glm::dvec3(0, 1, 0);
  s.to_sun = glm::vec3(sun);
  s.turbidity = turbidity;
  s.ground_albedo = glm::clamp(ground_albedo, glm::vec3(0.0f), glm::vec3(1.0f));

  // [P99]'s fits are for a sun above the horizon, and Y_z's tan(chi) changes sign for theta_s > 90 deg:
  // keep the sun's azimuth, clamp its zenith angle to kMaxSunZenith. A sun straight below (no azimuth)
  // is put towards -Z.
  if (sun.y < std::cos(kMaxSunZenith)) {
    glm::dvec3 h(sun.x, 0.0, sun.z);
    const double hl = glm::length(h);
    h = hl > 1e-12 ? h / hl : glm::dvec3(0, 0, -1);
    sun = h * std::sin(kMaxSunZenith) + glm::dvec3(0, 1, 0) * std::cos(kMaxSunZenith);
  }
  s.model_to_sun = sun;
  const double theta_s = std::acos(std::clamp(sun.y, -1.0, 1.0));
  s.model_sun_zenith = theta_s;

  const double t = turbidity;
  s.perez_Y = perez_luminance_Y(t);
  s.perez_x = perez_chroma_x(t);
  s.perez_y = perez_chroma_y(t);
  // [P99] Appendix A.2 gives Y_z in kcd/m^2; the renderer works in cd/m^2.
  s.zenith_Y = 1000.0 * zenith_luminance_kcd(t, theta_s);
  s.zenith_x = zenith_chromaticity(kZenithX, t, theta_s);
  s.zenith_y = zenith_chromaticity(kZenithY, t, theta_s);
  s.scale_Y = zenith_scale(s.zenith_Y, s.perez_Y, theta_s);
  s.scale_x = zenith_scale(s.zenith_x, s.perez_x, theta_s);
  s.scale_y = zenith_scale(s.zenith_y, s.perez_y, theta_s);

  // E_h = integral over the upper hemisphere of L(w) cos(theta) dw, midpoint rule in (theta, phi).
  // The integrand is smooth apart from the kink of exp(D gamma) at the sun, and is weighted by
  // cos(theta) sin(theta), which vanishes where the horizon clamp acts; 128 x 256 cells put the
  // quadrature error well under 0.1% (checked against a finer grid in the tests).
  constexpr int kThetaSteps = 128, kPhiSteps = 256;
  const double dtheta = 0.5 * kPi / kThetaSteps, dphi = 2.0 * kPi / kPhiSteps;
  glm::dvec3 e_h(0.0);
  for (int i = 0; i < kThetaSteps; ++i) {
    const double theta = (i + 0.5) * dtheta;
    const double st = std::sin(theta), ct = std::cos(theta);
    glm::dvec3 ring(0.0);
    for (int j = 0; j < kPhiSteps; ++j) {
      const double phi = (j + 0.5) * dphi;
      ring += sky_dome_radiance(s, glm::dvec3(st * std::sin(phi), ct, -st * std::cos(phi)));
    }
    e_h += ring * (ct * st * dtheta * dphi);
  }
  s.horizontal_illuminance = glm::vec3(sanitise(e_h));
  // Lambertian ground of albedo rho under irradiance E: radiance rho E / pi.
  s.ground_radiance = glm::vec3(sanitise(glm::dvec3(s.ground_albedo) * e_h / kPi));
  return s;
}

glm::vec3 sky_radiance(const SkyModel& s, glm::vec3 dir) {
  glm::dvec3 d(dir);
  const double len = glm::length(d);
  if (!(std::isfinite(len) && len > 0.0)) return glm::vec3(0.0f);
  d /= len;
  if (d.y < 0.0) return s.ground_radiance;
  return glm::vec3(sky_dome_radiance(s, d));
}

namespace {

// CIE 1931 2-degree standard observer colour matching functions x-bar, y-bar, z-bar, 380..780 nm in
// 10 nm steps (CIE 15:2004 Table T.4, every second 5 nm entry).
constexpr int kCmfCount = 41;
constexpr double kCmfFirstNm = 380.0, kCmfStepNm = 10.0;
constexpr double kCmf[kCmfCount][3] = {
    {0.001368, 0.000039, 0.006450},  // 380
    {0.004243, 0.000120, 0.020050},  // 390
    {0.014310, 0.000396, 0.067850},  // 400
    {0.043510, 0.001210, 0.207400},  // 410
    {0.134380, 0.004000, 0.645600},  // 420
    {0.283900, 0.011600, 1.385600},  // 430
    {0.348280, 0.023000, 1.747060},  // 440
    {0.336200, 0.038000, 1.772110},  // 450
    {0.290800, 0.060000, 1.669200},  // 460
    {0.195360, 0.090980, 1.287640},  // 470
    {0.095640, 0.139020, 0.812950},  // 480
    {0.032010, 0.208020, 0.465180},  // 490
    {0.004900, 0.323000, 0.272000},  // 500
    {0.009300, 0.503000, 0.158200},  // 510
    {0.063270, 0.710000, 0.078250},  // 520
    {0.165500, 0.862000, 0.042160},  // 530
    {0.290400, 0.954000, 0.020300},  // 540
    {0.433450, 0.994950, 0.008750},  // 550
    {0.594500, 0.995000, 0.003900},  // 560
    {0.762100, 0.952000, 0.002100},  // 570
    {0.916300, 0.870000, 0.001650},  // 580
    {1.026300, 0.757000, 0.001100},  // 590
    {1.062200, 0.631000, 0.000800},  // 600
    {1.002600, 0.503000, 0.000340},  // 610
    {0.854450, 0.381000, 0.000190},  // 620
    {0.642400, 0.265000, 0.000050},  // 630
    {0.447900, 0.175000, 0.000020},  // 640
    {0.283500, 0.107000, 0.000000},  // 650
    {0.164900, 0.061000, 0.000000},  // 660
    {0.087400, 0.032000, 0.000000},  // 670
    {0.046770, 0.017000, 0.000000},  // 680
    {0.022700, 0.008210, 0.000000},  // 690
    {0.011359, 0.004102, 0.000000},  // 700
    {0.005790, 0.002091, 0.000000},  // 710
    {0.002899, 0.001047, 0.000000},  // 720
    {0.001440, 0.000520, 0.000000},  // 730
    {0.000690, 0.000249, 0.000000},  // 740
    {0.000332, 0.000120, 0.000000},  // 750
    {0.000166, 0.000060, 0.000000},  // 760
    {0.000083, 0.000030, 0.000000},  // 770
    {0.000042, 0.000015, 0.000000},  // 780
};

}  // namespace

glm::vec3 sun_transmittance_rgb(float turbidity, float sun_zenith_radians) {
  // Kasten & Young's air mass (below) is fitted up to the horizon and goes negative past ~94 deg, so
  // the zenith angle is clamped to [0, 90 deg]; m(90 deg) ~ 36.5.
  double theta = std::isfinite(sun_zenith_radians) ? sun_zenith_radians : 0.0;
  theta = std::clamp(theta, 0.0, 0.5 * kPi);
  const double theta_deg = theta * 180.0 / kPi;
  // [P99] Appendix A (sunlight), relative optical mass (Kasten & Young 1989):
  //   m = 1 / (cos theta_s + 0.15 (93.885 - theta_s[deg])^-1.253).
  const double m = 1.0 / (std::cos(theta) + 0.15 * std::pow(93.885 - theta_deg, -1.253));
  // [P99] Appendix A (sunlight), Angstrom turbidity of the aerosols, linear in T (the paper prints
  // beta = 0.04608365822050 T - 0.04586025928522); alpha = 1.3 (ratio of small to large particles).
  // beta is clamped to >= 0 for T < ~1, outside the model's range.
  const double alpha = 1.3;
  const double beta = std::max(0.04608365822050 * turbidity - 0.04586025928522, 0.0);

  // Approximation: [P99]'s sun spectrum also carries ozone, mixed-gas and water-vapour absorption
  // (tabulated k_o, k_g, k_wa); they are left out here, so only the two scattering terms below shape
  // the colour. Ozone's Chappuis band (around 600 nm) would make the low sun slightly less red.
  glm::dvec3 xyz(0.0), xyz0(0.0);
  for (int i = 0; i < kCmfCount; ++i) {
    const double lambda_um = (kCmfFirstNm + kCmfStepNm * i) * 1e-3;  // [P99]'s fits take micrometres
    // [P99] Appendix A (sunlight), Rayleigh scattering: tau_R = exp(-0.008735 lambda^-4.08 m).
    const double tau_r = std::exp(-0.008735 * std::pow(lambda_um, -4.08) * m);
    // [P99] Appendix A (sunlight), aerosol scattering (Angstrom): tau_a = exp(-beta lambda^-alpha m).
    const double tau_a = std::exp(-beta * std::pow(lambda_um, -alpha) * m);
    // Equal-energy spectrum outside the atmosphere (1 at every wavelength), so the spectrum at the
    // ground is the transmittance itself; the 10 nm step cancels in the normalisation below.
    const double e = tau_r * tau_a;
    xyz += e * glm::dvec3(kCmf[i][0], kCmf[i][1], kCmf[i][2]);
    xyz0 += glm::dvec3(kCmf[i][0], kCmf[i][1], kCmf[i][2]);
  }
  // Relative to the sun above the atmosphere, which the light's own colour describes (white by
  // default): an equal-energy spectrum is itself warmer than Rec.709's D65 white (about
  // 1.20, 0.95, 0.91), and without this division a sun at the zenith would come out orange.
  const glm::dvec3 rgb0 = sanitise(xyz_to_rec709(xyz0));
  const glm::dvec3 rgb = sanitise(xyz_to_rec709(xyz)) / rgb0;
  const double lum = rec709_luminance(rgb);
  // Unreachable for clamped inputs (the red end survives: tau at 780 nm is still ~3e-10 for T = 10
  // with the sun on the horizon, far inside double's range), kept so that the result is always finite.
  if (!(lum > 1e-300)) return glm::vec3(1.0f);
  return glm::vec3(rgb / lum);
}

std::vector<float> bake_sky_latlong(const SkyModel& s, int width, int height) {
  if (width <= 0 || height <= 0) return {};
  std::vector<float> out(static_cast<size_t>(width) * static_cast<size_t>(height) * 3);
  for (int row = 0; row < height; ++row) {
    const double theta = (row + 0.5) / height * kPi;
    const double st = std::sin(theta), ct = std::cos(theta);
    for (int col = 0; col < width; ++col) {
      const double phi = ((col + 0.5) / width - 0.5) * 2.0 * kPi;
      const glm::vec3 dir(glm::dvec3(st * std::sin(phi), ct, -st * std::cos(phi)));
      // Same float direction a caller of sky_radiance would pass, so the map and the function agree.
      const glm::vec3 l = sky_radiance(s, dir);
      float* p = &out[(static_cast<size_t>(row) * width + col) * 3];
      p[0] = l.x;
      p[1] = l.y;
      p[2] = l.z;
    }
  }
  return out;
}

}  // namespace aw
