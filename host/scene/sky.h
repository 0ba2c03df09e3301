// Analytic daylight sky of Preetham, Shirley & Smits 1999, "A Practical Analytic Model for
// Daylight", SIGGRAPH 99 (cited below as [P99]): the Perez et al. 1993 sky distribution with
// coefficients and zenith values fitted against turbidity, plus the spectral transmittance of the
// direct sun. Host-only, standard library and GLM; the renderer bakes the sky to a lat-long map
// (bake_sky_latlong) and uses sun_transmittance_rgb for the colour of its sun light.
//
// Conventions: world space, +Y up; radiance in linear Rec.709 RGB whose Rec.709 luminance
// (0.2126 R + 0.7152 G + 0.0722 B) is in cd/m^2.
#pragma once

#include <vector>

#include <glm/glm.hpp>

namespace aw {

// The five coefficients A..E of the Perez distribution for one of Y, x, y ([P99] Appendix A.2).
struct PerezCoeffs {
  double a = 0, b = 0, c = 0, d = 0, e = 0;
};

struct SkyModel {             // built once per scene
  glm::vec3 to_sun{0, 1, 0};  // unit vector towards the sun, world space, +Y is up (as given, normalised)
  float turbidity = 3;        // Preetham's T, valid [1.7, 10] (the paper's fitted range; callers validate)
  glm::vec3 ground_albedo{0}; // reflectance of the ground below the horizon, clamped to [0,1]

  // Precomputed by make_preetham_sky. [P99] fits the model for suns above the horizon only, so the
  // model uses `model_to_sun`: `to_sun` with its zenith angle clamped to at most kMaxSunZenith (same
  // azimuth). A sun at or below the horizon therefore gives the dusk sky of a sun 0.1 deg up: finite,
  // but not a twilight model.
  glm::dvec3 model_to_sun{0, 1, 0};
  double model_sun_zenith = 0;  // theta_s of the model, radians, in [0, kMaxSunZenith]
  PerezCoeffs perez_Y, perez_x, perez_y;
  // Zenith values: Y in cd/m^2 ([P99]'s kcd/m^2 times 1000), chromaticity x, y.
  double zenith_Y = 0, zenith_x = 0, zenith_y = 0;
  // zenith value / F(0, theta_s) for Y, x, y: radiance = this * F(theta, gamma) ([P99] Sec. "Skylight").
  double scale_Y = 0, scale_x = 0, scale_y = 0;
  // E_h: illuminance on a horizontal plane from the sky dome alone (no sun disc), per RGB channel, in
  // lux (Rec.709 luminance of it is the photometric E_h). Numerical integral, see make_preetham_sky.
  glm::vec3 horizontal_illuminance{0};
  // ground_albedo * horizontal_illuminance / pi: a Lambertian ground lit by the sky dome.
  glm::vec3 ground_radiance{0};
};

// Largest sun zenith angle the sky model is evaluated at: 89.9 degrees (see SkyModel).
constexpr double kMaxSunZenith = 89.9 * 3.14159265358979323846 / 180.0;

// Builds the model for a sun along `to_sun` (need not be normalised; a zero vector means +Y).
SkyModel make_preetham_sky(glm::vec3 to_sun, float turbidity, glm::vec3 ground_albedo);

// Sky radiance seen looking along unit direction `dir` (towards the sky), linear Rec.709 RGB, whose
// luminance is in cd/m^2. Below the horizon (dir.y < 0) it is the ground, s.ground_radiance, the
// same value bake_sky_latlong writes there. Always finite and >= 0.
glm::vec3 sky_radiance(const SkyModel& s, glm::vec3 dir);

// Colour of the direct sun after the atmosphere, for a sun `sun_zenith_radians` from the zenith
// (clamped to [0, pi/2]): [P99]'s spectral transmittance (Rayleigh and Angstrom aerosol only, see
// sky.cpp) applied to an equal-energy spectrum, integrated against the CIE 1931 2-degree observer,
// in linear Rec.709 RGB (negative channels clamped to 0), divided channel by channel by the same
// spectrum's colour without the atmosphere (so that the light's own colour is the sun above the
// atmosphere, white by default; an equal-energy spectrum alone is warm against Rec.709's D65
// white, about 1.20, 0.95, 0.91), and scaled to luminance 1.
glm::vec3 sun_transmittance_rgb(float turbidity, float sun_zenith_radians);

// Lat-long bake of sky_radiance: width x height RGB floats, row-major, row 0 at the top (+Y, zenith).
// Pixel centres: theta = (row + 0.5) / height * pi from +Y, phi = ((col + 0.5) / width - 0.5) * 2 pi,
// direction = (sin theta sin phi, cos theta, -sin theta cos phi): the centre column looks along -Z
// and u increases towards +X. Pixels with dir.y < 0 hold s.ground_radiance. An empty vector if
// width or height is not positive.
std::vector<float> bake_sky_latlong(const SkyModel& s, int width, int height);

}  // namespace aw
