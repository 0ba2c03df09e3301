// Fog: absorption inside a refractive object (docs/material.md §3.7 "Fog"), applied by the
// integrator to every segment a ray travels inside the object, shadow rays included.
//
// Both modes are Beer–Lambert attenuation T(d) = exp(-sigma d) of a homogeneous absorbing
// medium (Beer's law; pbrt-v4, Sec. 11.2 "Transmittance"), with sigma set from the artist's
// parameters:
//
// - use_end_color: sigma_c = -ln(end_color_c) / distance per channel, so
//       T_c(d) = end_color_c ^ (d / distance)
//   exactly end_color at d = distance, 1 at d = 0; a channel of 0 is opaque (0 for any d > 0),
//   a channel of 1 is clear.
//
// - fade to black ("rays fade to black and stop at `distance`"): read as the limit of the
//   end-colour mode for an end colour of (almost) black. T(d) = AW_FOG_BLACK_LEVEL^(d/distance),
//   i.e. optical depth ln(1000) ~ 6.91 at `distance`, where the segment's transmittance is
//   1e-3 (black on any display) and the ray stops: T = 0 for d >= distance.
//   Why exponential and not a linear ramp max(0, 1 - d/distance): the integrator applies the
//   fog per segment (a ray bouncing inside the object has several), and only an exponential
//   is memoryless, T(a + b) = T(a) T(b), so the product over the segments depends only on the
//   total path length inside, as Beer–Lambert requires. A per-segment linear ramp would make
//   the result depend on how a path is cut into segments (two segments of 0.5 D would give
//   0.25 rather than black). The cut to 0 at d >= distance is the spec's "stop": it changes
//   T by at most 1e-3 and lets the path end.
//
// distance <= 0 (or NaN) disables the fog: T = 1 (docs/material.md §1: "0 disables"). End colours
// are clamped to [0, 1]: an absorbing medium cannot amplify.
#ifndef AW_LOBES_FOG_H
#define AW_LOBES_FOG_H

#include "common/compat.h"

// Transmittance at `distance` in fade-to-black mode, and its optical depth -ln(level).
#define AW_FOG_BLACK_LEVEL 1e-3f
#define AW_FOG_BLACK_OPTICAL_DEPTH 6.907755279f  // ln(1000)

// Transmittance of one channel with end colour c (clamped to [0, 1]) over t = d / distance.
AW_FN float fog_channel_transmittance(float c, float t) {
  c = clamp(c, 0.0f, 1.0f);
  if (!(t > 0.0f)) return 1.0f;  // d = 0: nothing absorbed, even for c = 0 (0^0 avoided)
  if (c <= 0.0f) return 0.0f;
  if (c >= 1.0f) return 1.0f;
  return pow(c, t);  // t may be +inf (tiny distance): pow(c < 1, inf) = 0
}

// Transmittance of a segment of length d inside the object (per channel, in [0, 1]).
AW_FN float3 fog_transmittance(float3 end_color, float distance_param, int use_end_color, float d) {
  float3 one = make_float3(1.0f, 1.0f, 1.0f);
  if (!(distance_param > 0.0f) || !(d > 0.0f)) return one;
  float t = d / distance_param;  // >= 0; +inf when distance_param is denormal-small
  if (use_end_color) {
    return make_float3(fog_channel_transmittance(end_color.x, t), fog_channel_transmittance(end_color.y, t),
                       fog_channel_transmittance(end_color.z, t));
  }
  if (t >= 1.0f) return make_float3(0.0f, 0.0f, 0.0f);  // "stop at distance"
  float tr = exp(-AW_FOG_BLACK_OPTICAL_DEPTH * t);
  return make_float3(tr, tr, tr);
}

#endif
