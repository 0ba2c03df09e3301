// Host-vs-device probes for the basic lobes (tests/lobes): Fresnel (all three modes), the
// diffuse EON lobe and translucency. Each probe reads a fixed number of floats per item and
// writes a fixed number back. The per-item functions are shared: the C++ test includes this
// file and runs the very same functions on the host (the __kernel wrappers below are OpenCL
// only), so the comparison is between two compilers of one source.
#include "common/compat.h"
#include "lobes/diffuse.h"
#include "lobes/fresnel.h"
#include "lobes/translucency.h"

// Layouts (floats per item):
//   fresnel      in  6: cos_i, eta, k, facing, perpendicular, curve
//                out 6: dielectric, conductor, curve, eval(DIELECTRIC), eval(CONDUCTOR), eval(CURVE)
//   diffuse      in 12: albedo.xyz, roughness, wo.xyz, wi.xyz, u.xy
//                out 15: eval.xyz, pdf, sample.wi.xyz, sample.weight.xyz, sample.pdf,
//                        sample.flags, albedo(wo.z).xyz
//   translucency in 11: color.xyz, wo.xyz, wi.xyz, u.xy
//                out 12: eval.xyz, pdf, sample.wi.xyz, sample.weight.xyz, sample.pdf, sample.flags
#define AW_PROBE_FRESNEL_IN 6
#define AW_PROBE_FRESNEL_OUT 6
#define AW_PROBE_DIFFUSE_IN 12
#define AW_PROBE_DIFFUSE_OUT 15
#define AW_PROBE_TRANSLUCENCY_IN 11
#define AW_PROBE_TRANSLUCENCY_OUT 12

AW_FN void probe_fresnel_item(const AW_GLOBAL float* in, AW_GLOBAL float* out) {
  FresnelParams f;
  f.eta = in[1];
  f.k = in[2];
  f.facing = in[3];
  f.perpendicular = in[4];
  f.curve = in[5];
  out[0] = fresnel_dielectric(in[0], in[1]);
  out[1] = fresnel_conductor(in[0], in[1], in[2]);
  out[2] = fresnel_curve(in[0], in[3], in[4], in[5]);
  f.mode = AW_FRESNEL_DIELECTRIC;
  out[3] = fresnel_eval(f, in[0]);
  f.mode = AW_FRESNEL_CONDUCTOR;
  out[4] = fresnel_eval(f, in[0]);
  f.mode = AW_FRESNEL_CURVE;
  out[5] = fresnel_eval(f, in[0]);
}

AW_FN void probe_store_sample(LobeSample s, AW_GLOBAL float* out) {
  store_f3(out, s.wi);
  store_f3(out + 3, s.weight);
  out[6] = s.pdf;
  out[7] = (float)s.flags;
}

AW_FN void probe_diffuse_item(const AW_GLOBAL float* in, AW_GLOBAL float* out) {
  float3 albedo = load_f3(in);
  float roughness = in[3];
  float3 wo = load_f3(in + 4);
  float3 wi = load_f3(in + 7);
  float2 u = make_float2(in[10], in[11]);
  store_f3(out, lobe_diffuse_eval(albedo, roughness, wo, wi));
  out[3] = lobe_diffuse_pdf(roughness, wo, wi);
  probe_store_sample(lobe_diffuse_sample(albedo, roughness, wo, u), out + 4);
  store_f3(out + 12, lobe_diffuse_albedo(albedo, roughness, wo.z));
}

AW_FN void probe_translucency_item(const AW_GLOBAL float* in, AW_GLOBAL float* out) {
  float3 color = load_f3(in);
  float3 wo = load_f3(in + 3);
  float3 wi = load_f3(in + 6);
  float2 u = make_float2(in[9], in[10]);
  store_f3(out, lobe_translucency_eval(color, wo, wi));
  out[3] = lobe_translucency_pdf(wo, wi);
  probe_store_sample(lobe_translucency_sample(color, wo, u), out + 4);
}

#ifdef __OPENCL_C_VERSION__
__kernel void probe_fresnel(uint n, __global const float* in, __global float* out) {
  uint i = get_global_id(0);
  if (i >= n) return;
  probe_fresnel_item(in + i * AW_PROBE_FRESNEL_IN, out + i * AW_PROBE_FRESNEL_OUT);
}

__kernel void probe_diffuse(uint n, __global const float* in, __global float* out) {
  uint i = get_global_id(0);
  if (i >= n) return;
  probe_diffuse_item(in + i * AW_PROBE_DIFFUSE_IN, out + i * AW_PROBE_DIFFUSE_OUT);
}

__kernel void probe_translucency(uint n, __global const float* in, __global float* out) {
  uint i = get_global_id(0);
  if (i >= n) return;
  probe_translucency_item(in + i * AW_PROBE_TRANSLUCENCY_IN, out + i * AW_PROBE_TRANSLUCENCY_OUT);
}
#endif
