// Shared code written on lanes (common/lanes.h), built with 16 paths per work-item, against
// the host's one-path C++ build of the same functions (tests/integrator/test_sampler.cpp,
// SamplerLanes.*, SamplingLanes.*, RayLanes.* and DiffuseLanes.*; tests/integrator/
// test_light_sampling.cpp, LightLanes.*; tests/integrator/test_shade_lanes.cpp, ShadeLanes.*).
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
#include "lobes/fresnel.h"
#include "lights/lights.h"
#include "integrator/shade_common.h"
#include "integrator/light_select.h"
#include "integrator/shade_surface.h"
#include "integrator/classify_hit.h"

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
  LightL l = light_load(lights, params[0], L_AS_UINT(v[9]));
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

// The path state of probe_shade_lanes and probe_shade_surface_lanes: `in` holds it (AW_SF_COUNT
// float fields of n slots, then AW_SU_COUNT uint fields), copied to `out`, where work-item g's
// 16 slots are shaded: the PathRef of that block, `live` its lanes of the stage.
static PathRef probe_state_lanes(uint n, __global const float* in, __global float* out, uint g, lmask live) {
  const uint nstate = (uint)AW_SF_COUNT + (uint)AW_SU_COUNT;
  for (uint f = 0u; f < nstate; ++f) L_STORE(L_LOAD(in + f * n, g), out + f * n, g);
  PathRef ps;
  ps.sf = out;
  ps.su = (__global uint*)(out + (uint)AW_SF_COUNT * n);
  ps.snap_f = 0;
  ps.snap_u = 0;
  ps.aov = 0;
  ps.pool = n;
  ps.slot = g * AW_LANES;
  PS_SET_LIVE(ps, live);
  return ps;
}

// probe_shade_lanes (integrator/shade_common.h: shade_emit_shadow, shade_continue, on a path
// state of n slots in blocks of 16)
// in: the path state (AW_SF_COUNT float fields of n slots, then AW_SU_COUNT uint fields),
//     then AW_PROBE_SHADE_LANES_IN fields of n values: live (0 or 1), p (3), ng (3), the lobe
//     sample's wi (3), weight (3), pdf, flags (the uint's bits) and eta_scale, the cut-off,
//     the light sample's wi (3) and dist, the light (bits), the contribution (3), and whether
//     to emit the shadow ray (0 or 1).
// rp: the RenderParams.
// out: the path state after the stage (as in), then shade_continue's queue (bits) per slot.
#define AW_PROBE_SHADE_LANES_IN 26
__kernel void probe_shade_lanes(uint n, __global const float* in, __global float* out,
                                __global const RenderParams* rpg) {
  uint g = get_global_id(0);
  if ((g + 1u) * AW_LANES > n) return;
  const uint nstate = (uint)AW_SF_COUNT + (uint)AW_SU_COUNT;
  lfloat v[AW_PROBE_SHADE_LANES_IN];
  for (uint k = 0u; k < AW_PROBE_SHADE_LANES_IN; ++k) v[k] = L_LOAD(in + (nstate + k) * n, g);
  PathRef ps = probe_state_lanes(n, in, out, g, v[0] != 0.0f);
  RenderParams rp = *rpg;
  lfloat3 p = make_lfloat3(v[1], v[2], v[3]), ng = make_lfloat3(v[4], v[5], v[6]);
  LobeSample s;
  s.wi = make_lfloat3(v[7], v[8], v[9]);
  s.weight = make_lfloat3(v[10], v[11], v[12]);
  s.pdf = v[13];
  s.flags = L_AS_UINT(v[14]);
  s.eta_scale = v[15];
  LightSample ls;
  ls.wi = make_lfloat3(v[17], v[18], v[19]);
  ls.dist = v[20];
  ls.le = l3_splat((lfloat)(0.0f));
  ls.pdf = (lfloat)(0.0f);
  ls.is_delta = (lmask)(0);
  lmask emit = v[25] != 0.0f;
  if (L_ANY(emit && ps.live)) {
    PathRef pe = ps;
    PS_KEEP(pe, emit);
    shade_emit_shadow(pe, p, ng, ls, L_AS_UINT(v[21]), make_lfloat3(v[22], v[23], v[24]));
  }
  luint q = shade_continue(ps, &rp, p, ng, s, v[16]);
  L_STORE(L_UINT_AS_FLOAT(q), out + nstate * n, g);
}

// probe_pick_light_lanes (integrator/light_select.h: shade_pick_light, the alias table)
// in: the path state's uint fields (AW_SU_COUNT fields of n slots: pixel, sample and bounce
//     are read), then the shading point p (3 fields of n values).
// lights: the light table; rp: the RenderParams (num_lights, the sampler).
// out: the light sample's wi (3), dist, le (3), pdf, is_delta (1 or 0), the light picked
//      (bits) and the combined pdf.
#define AW_PROBE_PICK_LANES_OUT 11
__kernel void probe_pick_light_lanes(uint n, __global const float* in, __global float* out,
                                     __global const LightGpu* lights, __global const RenderParams* rpg) {
  uint g = get_global_id(0);
  if ((g + 1u) * AW_LANES > n) return;
  PathRef ps;
  ps.sf = 0;
  ps.su = (__global uint*)in;
  ps.snap_f = 0;
  ps.snap_u = 0;
  ps.aov = 0;
  ps.pool = n;
  ps.slot = g * AW_LANES;
  PS_SET_LIVE(ps, (lmask)(-1));
  const __global float* pin = in + (uint)AW_SU_COUNT * n;
  lfloat3 p = make_lfloat3(L_LOAD(pin, g), L_LOAD(pin + n, g), L_LOAD(pin + 2u * n, g));
  SceneRef sc;
  sc.lights = lights;
  RenderParams rp = *rpg;
  luint light;
  lfloat pdf;
  LightSample s = shade_pick_light(ps, sc, &rp, p, &light, &pdf);
  lfloat r[AW_PROBE_PICK_LANES_OUT] = {s.wi.x, s.wi.y, s.wi.z, s.dist, s.le.x, s.le.y, s.le.z, s.pdf,
                                       L_SEL(s.is_delta != 0, (lfloat)(1.0f), (lfloat)(0.0f)),
                                       L_UINT_AS_FLOAT(light), pdf};
  for (uint k = 0u; k < AW_PROBE_PICK_LANES_OUT; ++k) L_STORE(r[k], out + k * n, g);
}

// probe_shade_surface_lanes (integrator/shade_surface.h: the whole diffuse shading stage, on a
// path state of n slots in blocks of 16)
// in: the path state (as probe_shade_lanes), then one field of n values: live (0 or 1).
// materials, lights: the scene's tables; rp: the RenderParams.
// out: the path state after the stage, then the stage's next queue (bits) per slot.
__kernel void probe_shade_surface_lanes(uint n, __global const float* in, __global float* out,
                                        __global const MaterialGpu* materials, __global const LightGpu* lights,
                                        __global const RenderParams* rpg) {
  uint g = get_global_id(0);
  if ((g + 1u) * AW_LANES > n) return;
  const uint nstate = (uint)AW_SF_COUNT + (uint)AW_SU_COUNT;
  PathRef ps = probe_state_lanes(n, in, out, g, L_LOAD(in + nstate * n, g) != 0.0f);
  SceneRef sc;
  sc.materials = materials;
  sc.lights = lights;
  RenderParams rp = *rpg;
  luint q = shade_surface(ps, sc, &rp, (uint)AW_LID_DIFFUSE);
  L_STORE(L_UINT_AS_FLOAT(q), out + nstate * n, g);
}

// probe_classify_lanes (integrator/classify_hit.h: the whole classification stage, on a path
// state of n slots in blocks of 16)
// in: the path state (as probe_shade_lanes), then one field of n values: live (0 or 1).
// tri_info, verts, materials, lights, tri_light: the scene's tables; rp: the RenderParams.
// out: the path state after the stage, then the stage's next queue (bits) per slot.
__kernel void probe_classify_lanes(uint n, __global const float* in, __global float* out,
                                   __global const TriangleInfo* tri_info, __global const VertexData* verts,
                                   __global const MaterialGpu* materials, __global const LightGpu* lights,
                                   __global const uint* tri_light, __global const RenderParams* rpg) {
  uint g = get_global_id(0);
  if ((g + 1u) * AW_LANES > n) return;
  const uint nstate = (uint)AW_SF_COUNT + (uint)AW_SU_COUNT;
  PathRef ps = probe_state_lanes(n, in, out, g, L_LOAD(in + nstate * n, g) != 0.0f);
  SceneRef sc;
  sc.tri_info = tri_info;
  sc.verts = verts;
  sc.materials = materials;
  sc.lights = lights;
  sc.tri_light = tri_light;
  RenderParams rp = *rpg;
  luint q = classify_hit(ps, sc, &rp);
  L_STORE(L_UINT_AS_FLOAT(q), out + nstate * n, g);
}

// probe_pow_lanes (the artist curve's pow, lobes/fresnel.h: fresnel_curve)
// in: 2 fields of n values: x, y.
// out: pow(x, y) on 16 lanes (n values), then pow(x, y) one float at a time (n values), then
//      fresnel_curve(1 - x, 0, 1, y) on 16 lanes (n values), then its formula one float at a
//      time (n values).
__kernel void probe_pow_lanes(uint n, __global const float* in, __global float* out) {
  uint g = get_global_id(0);
  if ((g + 1u) * AW_LANES > n) return;
  lfloat x = L_LOAD(in, g), y = L_LOAD(in + n, g);
  L_STORE(pow(x, y), out, g);
  L_STORE(fresnel_curve(1.0f - x, (lfloat)(0.0f), (lfloat)(1.0f), y), out + 2u * n, g);
  for (uint k = 0u; k < AW_LANES; ++k) {
    uint i = g * AW_LANES + k;
    float p = pow(in[i], in[n + i]);
    out[n + i] = p;
    float c = clamp(1.0f - in[i], 0.0f, 1.0f);
    float q = pow(1.0f - c, fmax(in[n + i], 0.0f));
    out[3u * n + i] = q < 1.17549435e-38f ? 0.0f : q;  // facing 0, perpendicular 1: the flushed power
  }
}

