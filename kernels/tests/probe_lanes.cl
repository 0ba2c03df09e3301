// Shared code written on lanes (common/lanes.h), built with 16 paths per work-item, against
// the host's one-path C++ build of the same functions (tests/integrator/test_sampler.cpp,
// SamplerLanes.*, SamplingLanes.*, RayLanes.* and DiffuseLanes.*; tests/integrator/
// test_light_sampling.cpp, LightLanes.*).
//
// probe_sampler_lanes (common/rng.h)
// in: n pixels, then n sample indices, then n bounces (uint bits in the float buffer), field-
//     major; n a multiple of 16. params: sampler kind, seed, dimension.
// out: rng_2d's x (n values), its y (n), rng_1d (n), field-major.
#define AW_LANES 16
#include "common/rng.h"
#include "common/ray.h"
#include "common/sampling.h"
#include "lobes/diffuse.h"
#include "lights/lights.h"

__kernel void probe_sampler_lanes(uint n, __global const float* in, __global float* out,
                                  __global const uint* params) {
  uint g = get_global_id(0);
  if ((g + 1u) * AW_LANES > n) return;
  const __global uint* iu = (const __global uint*)in;
  luint pixel = L_LOAD(iu, g), sample = L_LOAD(iu + n, g), bounce = L_LOAD(iu + 2u * n, g);
  Sampler s = sampler_make(params[0], params[1], 0u, 0u, 0u);
  lfloat2 u = rng_2d(s, pixel, sample, bounce, params[2]);
  lfloat v = rng_1d(s, pixel, sample, bounce, params[2]);
  L_STORE(u.x, out, g);
  L_STORE(u.y, out + n, g);
  L_STORE(v, out + 2u * n, g);
}

// probe_warps_lanes (common/sampling.h)
// in: 8 fields of n values, field-major: u.x, u.y, n.x, n.y, n.z (a unit normal), pdf_a,
//     pdf_b, cos_max.
// out: AW_PROBE_WARPS_OUT fields of n values, field-major: the disk (2), the cosine-weighted
//      direction (3) and its pdf, the cone direction (3), sin and cos of 2 pi u.x, the frame's
//      t (3) and b (3), the cosine direction taken to world (3) and back to local (3), the
//      power heuristic of (pdf_a, pdf_b) and of (pdf_b, pdf_a).
#define AW_PROBE_WARPS_IN 8
#define AW_PROBE_WARPS_OUT 25
__kernel void probe_warps_lanes(uint n, __global const float* in, __global float* out) {
  uint g = get_global_id(0);
  if ((g + 1u) * AW_LANES > n) return;
  lfloat2 u = make_lfloat2(L_LOAD(in, g), L_LOAD(in + n, g));
  lfloat3 nn = make_lfloat3(L_LOAD(in + 2u * n, g), L_LOAD(in + 3u * n, g), L_LOAD(in + 4u * n, g));
  lfloat pa = L_LOAD(in + 5u * n, g), pb = L_LOAD(in + 6u * n, g), cos_max = L_LOAD(in + 7u * n, g);
  lfloat r[AW_PROBE_WARPS_OUT];
  lfloat2 d = sample_concentric_disk(u);
  r[0] = d.x;
  r[1] = d.y;
  lfloat3 w = sample_cosine_hemisphere(u);
  r[2] = w.x;
  r[3] = w.y;
  r[4] = w.z;
  r[5] = pdf_cosine_hemisphere(w.z);
  lfloat3 cone = sample_uniform_cone(u, cos_max);
  r[6] = cone.x;
  r[7] = cone.y;
  r[8] = cone.z;
  sincos_turn(u.x, &r[9], &r[10]);
  lfloat3 t, b;
  make_frame(nn, &t, &b);
  r[11] = t.x;
  r[12] = t.y;
  r[13] = t.z;
  r[14] = b.x;
  r[15] = b.y;
  r[16] = b.z;
  lfloat3 ww = frame_to_world(w, t, b, nn);
  r[17] = ww.x;
  r[18] = ww.y;
  r[19] = ww.z;
  lfloat3 wl = frame_to_local(ww, t, b, nn);
  r[20] = wl.x;
  r[21] = wl.y;
  r[22] = wl.z;
  r[23] = mis_power(pa, pb);
  r[24] = mis_power(pb, pa);
  for (uint k = 0u; k < AW_PROBE_WARPS_OUT; ++k) L_STORE(r[k], out + k * n, g);
}

// probe_origins_lanes (common/ray.h)
// in: 9 fields of n values: p.xyz, n.xyz, err, x, s. out: offset_ray_origin(p, n, err) (3),
//     aw_float_step(x, s).
__kernel void probe_origins_lanes(uint n, __global const float* in, __global float* out) {
  uint g = get_global_id(0);
  if ((g + 1u) * AW_LANES > n) return;
  lfloat3 p = make_lfloat3(L_LOAD(in, g), L_LOAD(in + n, g), L_LOAD(in + 2u * n, g));
  lfloat3 nn = make_lfloat3(L_LOAD(in + 3u * n, g), L_LOAD(in + 4u * n, g), L_LOAD(in + 5u * n, g));
  lfloat3 o = offset_ray_origin(p, nn, L_LOAD(in + 6u * n, g));
  L_STORE(o.x, out, g);
  L_STORE(o.y, out + n, g);
  L_STORE(o.z, out + 2u * n, g);
  L_STORE(aw_float_step(L_LOAD(in + 7u * n, g), L_LOAD(in + 8u * n, g)), out + 3u * n, g);
}

// probe_diffuse_lanes (lobes/diffuse.h)
// in: 12 fields of n values: albedo.xyz, roughness, wo.xyz, wi.xyz, u.xy.
// out: AW_PROBE_DIFFUSE_LANES_OUT fields: eval (3), pdf, sample wi (3), weight (3), pdf, flags
//      (the uint's bits), directional albedo at wo.z (3).
#define AW_PROBE_DIFFUSE_LANES_OUT 15
__kernel void probe_diffuse_lanes(uint n, __global const float* in, __global float* out) {
  uint g = get_global_id(0);
  if ((g + 1u) * AW_LANES > n) return;
  lfloat v[12];
  for (uint k = 0u; k < 12u; ++k) v[k] = L_LOAD(in + k * n, g);
  lfloat3 albedo = make_lfloat3(v[0], v[1], v[2]), wo = make_lfloat3(v[4], v[5], v[6]);
  lfloat3 wi = make_lfloat3(v[7], v[8], v[9]);
  lfloat r[AW_PROBE_DIFFUSE_LANES_OUT];
  lfloat3 e = lobe_diffuse_eval(albedo, v[3], wo, wi);
  LobeSample s = lobe_diffuse_sample(albedo, v[3], wo, make_lfloat2(v[10], v[11]));
  lfloat3 a = lobe_diffuse_albedo(albedo, v[3], wo.z);
  r[0] = e.x;
  r[1] = e.y;
  r[2] = e.z;
  r[3] = lobe_diffuse_pdf(v[3], wo, wi);
  r[4] = s.wi.x;
  r[5] = s.wi.y;
  r[6] = s.wi.z;
  r[7] = s.weight.x;
  r[8] = s.weight.y;
  r[9] = s.weight.z;
  r[10] = s.pdf;
  r[11] = L_AS_FLOAT(s.flags);
  r[12] = a.x;
  r[13] = a.y;
  r[14] = a.z;
  for (uint k = 0u; k < AW_PROBE_DIFFUSE_LANES_OUT; ++k) L_STORE(r[k], out + k * n, g);
}

// probe_lights_lanes (lights/lights.h; l_sincos of common/sampling.h)
// in: 12 fields of n values: the shading point p (3), the light sample's u (2), a unit
//     direction (3) and a distance t for light_pdf and light_emitted, the light's index (the
//     uint's bits), the pick's u, an angle x.
// lights: the light table; params: [0] its size.
// out: light_sample's wi (3), dist, le (3), pdf, is_delta (1 or 0); light_pdf; light_emitted
//      (3); light_pick (the uint's bits); sin x, cos x (l_sincos).
#define AW_PROBE_LIGHTS_LANES_IN 12
#define AW_PROBE_LIGHTS_LANES_OUT 16
__kernel void probe_lights_lanes(uint n, __global const float* in, __global float* out,
                                 __global const LightGpu* lights, __global const uint* params) {
  uint g = get_global_id(0);
  if ((g + 1u) * AW_LANES > n) return;
  lfloat v[AW_PROBE_LIGHTS_LANES_IN];
  for (uint k = 0u; k < AW_PROBE_LIGHTS_LANES_IN; ++k) v[k] = L_LOAD(in + k * n, g);
  lfloat3 p = make_lfloat3(v[0], v[1], v[2]), dir = make_lfloat3(v[5], v[6], v[7]);
  LightL l = light_load(lights, L_AS_UINT(v[9]));
  LightSample s = light_sample(l, p, make_lfloat2(v[3], v[4]));
  lfloat3 le = light_emitted(l, dir);
  lfloat r[AW_PROBE_LIGHTS_LANES_OUT];
  r[0] = s.wi.x;
  r[1] = s.wi.y;
  r[2] = s.wi.z;
  r[3] = s.dist;
  r[4] = s.le.x;
  r[5] = s.le.y;
  r[6] = s.le.z;
  r[7] = s.pdf;
  r[8] = L_SEL(s.is_delta != 0, (lfloat)(1.0f), (lfloat)(0.0f));
  r[9] = light_pdf(l, p, dir, v[8]);
  r[10] = le.x;
  r[11] = le.y;
  r[12] = le.z;
  r[13] = L_UINT_AS_FLOAT(light_pick(lights, params[0], v[10]));
  l_sincos(v[11], &r[14], &r[15]);
  for (uint k = 0u; k < AW_PROBE_LIGHTS_LANES_OUT; ++k) L_STORE(r[k], out + k * n, g);
}
