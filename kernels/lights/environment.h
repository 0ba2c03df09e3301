// The environment map (environment.type "map", and the baked "sky"): a lat-long radiance image
// seen at infinity, importance-sampled for next-event estimation and MIS-weighted against BSDF
// sampling when a ray escapes (classify_hit.h).
//
// Mapping (docs/scene-format.md, "environment"): +Y is up. A unit direction d in the map's own
// frame has polar angle theta = acos(d.y) from +Y and azimuth phi = atan2(d.x, -d.z); the
// image coordinate is u = 0.5 + phi / (2 pi) (left to right), v = theta / pi (top row = +Y).
// So the centre column looks along -Z and u grows towards +X. `rotation` turns the map about
// +Y by that angle (counter-clockwise seen from above): world d -> map frame R_y(-rotation) d.
//
// Distribution: the 2-D piecewise-constant density of Pharr, Jakob & Humphreys, "Physically
// Based Rendering" 3rd ed., Sec. 13.6.7 (marginal over rows, conditional over columns, each
// sampled by inverting its CDF; inversion keeps the Sobol' points' stratification, which an
// alias table would scramble), over the weights f(i, j) = luminance(texel) * sin(theta_j) so
// that texels are chosen in proportion to the power they carry (Sec. 14.2.4: the lat-long
// map's Jacobian, d omega = 2 pi^2 sin(theta) du dv). Radiance is looked up per texel (nearest,
// no filtering) so the sampled density follows the radiance exactly: a map whose upper half is
// 1 and lower half 0 is sampled with no variance on an upward plane.
//
// Buffer (sc.env, floats, built by host/render/environment_pack.cpp), for a w x h map:
//   [0, 3wh)                  texel radiance RGB (intensity applied), row-major, top row first
//   [3wh, 4wh)                pdf_uv of each texel: f(i, j) / mean(f) (the density in [0,1)^2)
//   [4wh, 4wh + h (w + 1))    per row, the conditional CDF over its w columns (0 ... 1)
//   [.., + h + 1)             the marginal CDF over rows (0 ... 1)
#ifndef AW_LIGHTS_ENVIRONMENT_H
#define AW_LIGHTS_ENVIRONMENT_H

#include "common/compat.h"
#include "common/sampling.h"
#include "types/scene.h"

AW_FN uint env_off_pdf(uint w, uint h) { return 3u * w * h; }
AW_FN uint env_off_cond(uint w, uint h) { return 4u * w * h; }
AW_FN uint env_off_marg(uint w, uint h) { return 4u * w * h + h * (w + 1u); }

// World direction -> the map's frame (rotation about +Y by -rotation).
AW_FN float3 env_to_map(const RenderParams* rp, float3 d) {
  float c = rp->env_rot_cos, s = rp->env_rot_sin;
  return make_float3(c * d.x - s * d.z, d.y, s * d.x + c * d.z);
}
AW_FN float3 env_from_map(const RenderParams* rp, float3 d) {
  float c = rp->env_rot_cos, s = rp->env_rot_sin;
  return make_float3(c * d.x + s * d.z, d.y, -s * d.x + c * d.z);
}

// The texel a map-frame direction falls in (clamped: u = 1 or v = 1 exactly belong to the last).
AW_FN uint env_texel(const RenderParams* rp, float3 dm) {
  uint w = rp->env_width, h = rp->env_height;
  float v = acos(clamp(dm.y, -1.0f, 1.0f)) * (1.0f / M_PI_F);
  float u = 0.5f + atan2(dm.x, -dm.z) * (0.5f / M_PI_F);
  uint i = min((uint)fmax(u * (float)w, 0.0f), w - 1u);
  uint j = min((uint)fmax(v * (float)h, 0.0f), h - 1u);
  return j * w + i;
}

AW_FN float3 env_texel_radiance(const AW_GLOBAL float* env, uint t) { return load_f3(env + 3u * t); }

// Radiance arriving along -d (d: world direction of the escaping ray).
AW_FN float3 env_radiance(const AW_GLOBAL float* env, const RenderParams* rp, float3 d) {
  return env_texel_radiance(env, env_texel(rp, env_to_map(rp, d)));
}

// Solid-angle density of env_sample drawing world direction d: pdf_uv / (2 pi^2 sin theta)
// (PBR 3rd ed., Sec. 14.2.4). Zero at the poles, where the map has no area.
AW_FN float env_pdf(const AW_GLOBAL float* env, const RenderParams* rp, float3 d) {
  float3 dm = env_to_map(rp, d);
  // sin(theta) from the horizontal components: sqrt(1 - y^2) loses digits near the poles
  // (measured: 1e-3 relative disagreement with the sampler's density there).
  float sin_t = sqrt(dm.x * dm.x + dm.z * dm.z);
  if (!(sin_t > 0.0f)) return 0.0f;
  float pdf_uv = env[env_off_pdf(rp->env_width, rp->env_height) + env_texel(rp, dm)];
  return pdf_uv / (2.0f * M_PI_F * M_PI_F * sin_t);
}

// Inverts a piecewise-constant CDF of n cells (cdf[0] = 0, cdf[n] = 1): the cell k with
// cdf[k] <= u < cdf[k+1] (binary search; empty cells have zero width and are never returned
// for u < 1) and u's position inside it, in [0, 1).
AW_FN uint env_invert_cdf(const AW_GLOBAL float* cdf, uint n, float u, float* du) {
  uint lo = 0u, hi = n;  // invariant: cdf[lo] <= u < cdf[hi] (cdf[n] = 1 > u)
  while (hi - lo > 1u) {
    uint mid = (lo + hi) >> 1;
    if (cdf[mid] <= u) lo = mid;
    else hi = mid;
  }
  float width = cdf[lo + 1u] - cdf[lo];
  *du = width > 0.0f ? clamp((u - cdf[lo]) / width, 0.0f, 0.99999994f) : 0.5f;
  return lo;
}

#if AW_LANES == 1
// Draws a world direction; returns 0 (and pdf 0) for a map with no power. One path per call:
// not in a program built on lanes (AW_LANES > 1, common/lanes.h), which is built only for
// scenes without an environment map (integrator/light_select.h). *texel is the texel
// sampled, whose radiance the caller takes (the same texel env_radiance would look up).
AW_FN float3 env_sample(const AW_GLOBAL float* env, const RenderParams* rp, float2 u, float* pdf, uint* texel) {
  uint w = rp->env_width, h = rp->env_height;
  float dv, du;
  uint j = env_invert_cdf(env + env_off_marg(w, h), h, u.y, &dv);
  uint i = env_invert_cdf(env + env_off_cond(w, h) + j * (w + 1u), w, u.x, &du);
  *texel = j * w + i;
  float pdf_uv = env[env_off_pdf(w, h) + *texel];
  float theta_v = ((float)j + dv) / (float)h;  // theta / pi
  float phi_u = ((float)i + du) / (float)w;     // phi / (2 pi) + 1/2
  float st, ct, sp, cp;
  // theta = pi theta_v in [0, pi]: sincos_turn(x) gives the angle 2 pi x.
  sincos_turn(0.5f * theta_v, &st, &ct);
  sincos_turn(phi_u - 0.5f, &sp, &cp);
  st = fmax(st, 0.0f);
  *pdf = st > 0.0f && pdf_uv > 0.0f ? pdf_uv / (2.0f * M_PI_F * M_PI_F * st) : 0.0f;
  return env_from_map(rp, make_float3(st * sp, ct, -st * cp));
}

#endif  // AW_LANES == 1

#endif
