// The environment map's device buffer (kernels/lights/environment.h has its layout, mapping and
// sampling): texels, per-texel densities and the CDFs of its 2-D piecewise-constant
// distribution, built on the host in double precision.
#pragma once

#include <vector>

namespace aw {

struct PackedEnvironment {
  std::vector<float> buffer;  // the layout of kernels/lights/environment.h
  // The integral of the map's luminance over the sphere, sum of lum * sin(theta) * 2 pi^2 / (w h)
  // (PBR 3rd ed., Sec. 14.2.4's Jacobian): the light-selection power is pi R^2 times it.
  double luminance_integral = 0.0;
};

// rgb: width x height linear RGB, row 0 at the top (+Y); `intensity` multiplies it. `uniform`:
// the distribution ignores the radiance (weights sin theta alone: uniform over the sphere), for
// comparing importance sampling against it (environment.sampling "uniform").
PackedEnvironment pack_environment(const std::vector<float>& rgb, int width, int height, float intensity,
                                   bool uniform = false);

}  // namespace aw
