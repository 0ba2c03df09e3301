#include "host/render/environment_pack.h"

#include <cmath>
#include <stdexcept>

#include "kernels/common/compat.h"
#include "kernels/lights/environment.h"

namespace aw {

PackedEnvironment pack_environment(const std::vector<float>& rgb, int width, int height, float intensity,
                                   bool uniform) {
  if (width <= 0 || height <= 0 || rgb.size() != size_t(width) * size_t(height) * 3)
    throw std::invalid_argument("pack_environment: the map's size does not match its data");
  const uint32_t w = uint32_t(width), h = uint32_t(height);
  const size_t n = size_t(w) * h;
  PackedEnvironment out;
  std::vector<float>& b = out.buffer;
  b.assign(size_t(env_off_marg(w, h)) + h + 1, 0.0f);
  // Sampling weights f(i, j) = luminance * sin(theta at the row's centre): texels near the poles
  // cover less solid angle (PBR 3rd ed., Sec. 14.2.4).
  std::vector<double> f(n);
  const double pi = 3.14159265358979323846;
  double total = 0.0, lum_total = 0.0;
  for (uint32_t j = 0; j < h; ++j) {
    const double sin_t = std::sin(pi * (j + 0.5) / h);
    for (uint32_t i = 0; i < w; ++i) {
      const size_t t = size_t(j) * w + i;
      float3 c = make_float3(rgb[3 * t], rgb[3 * t + 1], rgb[3 * t + 2]) * intensity;
      b[3 * t] = c.x;
      b[3 * t + 1] = c.y;
      b[3 * t + 2] = c.z;
      // Luminance weights are all positive, so every texel with radiance has f > 0 and can be
      // sampled: light sampling alone would still be unbiased.
      const double lum = double(luminance(c));
      f[t] = (uniform ? 1.0 : lum) * sin_t;
      total += f[t];
      lum_total += lum * sin_t;
    }
  }
  out.luminance_integral = lum_total * 2.0 * pi * pi / double(n);
  if (!(lum_total > 0.0) || !std::isfinite(lum_total) || !(total > 0.0)) return out;  // a black map: never selected
  const double mean = total / double(n);
  float* pdf = b.data() + env_off_pdf(w, h);
  float* cond = b.data() + env_off_cond(w, h);
  float* marg = b.data() + env_off_marg(w, h);
  double row_acc = 0.0;
  for (uint32_t j = 0; j < h; ++j) {
    double row = 0.0;
    for (uint32_t i = 0; i < w; ++i) row += f[size_t(j) * w + i];
    float* c = cond + size_t(j) * (w + 1);
    double acc = 0.0;
    c[0] = 0.0f;
    for (uint32_t i = 0; i < w; ++i) {
      const size_t t = size_t(j) * w + i;
      pdf[t] = float(f[t] / mean);  // the density in [0,1)^2: marginal x conditional
      acc += f[t];
      // A row without power keeps a uniform CDF; the marginal never picks it.
      c[i + 1] = row > 0.0 ? float(acc / row) : float(double(i + 1) / w);
    }
    c[w] = 1.0f;
    marg[j] = float(row_acc / total);
    row_acc += row;
  }
  marg[h] = 1.0f;
  return out;
}

}  // namespace aw
