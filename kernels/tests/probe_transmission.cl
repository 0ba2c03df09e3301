// Probe kernels for the host-vs-device tests of the transmission lobes (tests/lobes/
// test_refraction.cpp): each work item reads its fixed inputs, runs the shared header code on
// the device and writes every result, so the test can compare them with the same functions
// compiled as C++. Signature of every probe: (uint n, __global const float* in, __global float* out).
#include "lobes/fog.h"
#include "lobes/refraction.h"
#include "lobes/thin_walled.h"

// The first 8 outputs shared by the lobe probes: eval, pdf, sample wi.xyz, sample weight,
// sample pdf, sample flags (eval and weight: channel x only, what the tests compare).
AW_FN void probe_store_lobe(AW_GLOBAL float* o, float eval, float pdf, LobeSample s) {
  o[0] = eval;
  o[1] = pdf;
  o[2] = s.wi.x;
  o[3] = s.wi.y;
  o[4] = s.wi.z;
  o[5] = s.weight.x;
  o[6] = s.pdf;
  o[7] = (float)s.flags;
}

// in  (12 per item): ax, ay, dist, eta, wo.xyz, wi.xyz, u.xy
// out (10 per item): eval, pdf, sample wi.xyz, sample weight, sample pdf, sample flags,
//                    refraction_cos_t(wo.z, eta), refraction_radiance_scale(eta)
#define AW_PROBE_REFRACTION_IN 12
#define AW_PROBE_REFRACTION_OUT 10
__kernel void probe_refraction(uint n, __global const float* in, __global float* out) {
  uint i = get_global_id(0);
  if (i >= n) return;
  __global const float* a = in + i * AW_PROBE_REFRACTION_IN;
  __global float* o = out + i * AW_PROBE_REFRACTION_OUT;
  RefractionParams p;
  p.mf.ax = a[0];
  p.mf.ay = a[1];
  p.mf.dist = (uint)a[2];
  p.eta = a[3];
  float3 wo = make_float3(a[4], a[5], a[6]);
  float3 wi = make_float3(a[7], a[8], a[9]);
  float2 u = make_float2(a[10], a[11]);
  probe_store_lobe(o, lobe_refraction_eval(p, wo, wi).x, lobe_refraction_pdf(p, wo, wi),
                   lobe_refraction_sample(p, wo, u));
  o[8] = refraction_cos_t(wo.z, p.eta);
  o[9] = refraction_radiance_scale(p.eta);
}

// in  (10 per item): glossiness, wo.xyz, wi.xyz, u.xy, R
// out (10 per item): eval, pdf, sample wi.xyz, sample weight, sample pdf, sample flags, R', T'
#define AW_PROBE_THIN_IN 10
#define AW_PROBE_THIN_OUT 10
__kernel void probe_thin_walled(uint n, __global const float* in, __global float* out) {
  uint i = get_global_id(0);
  if (i >= n) return;
  __global const float* a = in + i * AW_PROBE_THIN_IN;
  __global float* o = out + i * AW_PROBE_THIN_OUT;
  float g = a[0];
  float3 wo = make_float3(a[1], a[2], a[3]);
  float3 wi = make_float3(a[4], a[5], a[6]);
  float2 u = make_float2(a[7], a[8]);
  probe_store_lobe(o, lobe_thin_transmission_eval(g, wo, wi).x, lobe_thin_transmission_pdf(g, wo, wi),
                   lobe_thin_transmission_sample(g, wo, u));
  o[8] = thin_wall_reflectance(a[9]);
  o[9] = thin_wall_transmittance(a[9]);
}

// in  (6 per item): end_color.rgb, distance, use_end_color, d
// out (3 per item): transmittance.rgb
__kernel void probe_fog(uint n, __global const float* in, __global float* out) {
  uint i = get_global_id(0);
  if (i >= n) return;
  __global const float* a = in + i * 6;
  float3 t = fog_transmittance(make_float3(a[0], a[1], a[2]), a[3], a[4] != 0.0f ? 1 : 0, a[5]);
  out[i * 3 + 0] = t.x;
  out[i * 3 + 1] = t.y;
  out[i * 3 + 2] = t.z;
}
