// Probe for host-vs-device agreement of the reflection lobe and the microfacet distributions
// (tests/lobes/test_microfacet.cpp). One work item per input record; the record layout and the
// per-item function are shared: the C++ test includes this file too (the __kernel is compiled
// only by OpenCL), so host and device run exactly the same code on the same inputs.
//
// Input record (AW_PROBE_REFL_IN floats):
//   0 brdf, 1 glossiness, 2 anisotropy amount, 3..5 tint,
//   6 fresnel mode, 7 eta, 8 k, 9 facing, 10 perpendicular, 11 curve,
//   12..14 wo, 15..17 wi, 18..19 u
// Output record (AW_PROBE_REFL_OUT floats):
//   0..2 eval(wo, wi), 3 pdf(wo, wi),
//   4..6 sample.wi, 7..9 sample.weight, 10 sample.pdf, 11 sample.flags,
//   12..14 albedo_estimate(wo.z),
//   15 mf_D(h), 16 mf_G2(wo, wi, h), 17 mf_pdf_visible(wo, h), 18 mf_lambda(wo),
//   19..21 mf_sample_visible(wo, u),
//   22 mf.ax, 23 mf.ay, 24 as_nu, 25 as_nv
// with h = normalize(wo + wi) (or +z when that is degenerate).
#include "lobes/reflection.h"

#define AW_PROBE_REFL_IN 20
#define AW_PROBE_REFL_OUT 26

AW_FN void probe_reflection_item(const AW_GLOBAL float* in, AW_GLOBAL float* out) {
  FresnelParams f;
  f.mode = (uint)in[6];
  f.eta = in[7];
  f.k = in[8];
  f.facing = in[9];
  f.perpendicular = in[10];
  f.curve = in[11];
  ReflectionParams p = reflection_params_make(load_f3(in + 3), (uint)in[0], in[1], in[2], f);
  float3 wo = load_f3(in + 12);
  float3 wi = load_f3(in + 15);
  float2 u = make_float2(in[18], in[19]);

  store_f3(out + 0, lobe_reflection_eval(p, wo, wi));
  out[3] = lobe_reflection_pdf(p, wo, wi);
  LobeSample s = lobe_reflection_sample(p, wo, u);
  store_f3(out + 4, s.wi);
  store_f3(out + 7, s.weight);
  out[10] = s.pdf;
  out[11] = (float)s.flags;
  store_f3(out + 12, lobe_reflection_albedo_estimate(p, wo.z));

  float3 h = wo + wi;
  float len = length(h);
  h = len > 0.0f ? h / len : make_float3(0.0f, 0.0f, 1.0f);
  out[15] = mf_D(p.mf, h);
  out[16] = mf_G2(p.mf, wo, wi, h);
  out[17] = mf_pdf_visible(p.mf, wo, h);
  out[18] = mf_lambda(p.mf, wo);
  store_f3(out + 19, mf_sample_visible(p.mf, wo, u));
  out[22] = p.mf.ax;
  out[23] = p.mf.ay;
  out[24] = p.as_nu;
  out[25] = p.as_nv;
}

#ifdef __OPENCL_C_VERSION__
__kernel void probe_reflection(uint n, __global const float* in, __global float* out) {
  uint i = get_global_id(0);
  if (i >= n) return;
  probe_reflection_item(in + (size_t)i * AW_PROBE_REFL_IN, out + (size_t)i * AW_PROBE_REFL_OUT);
}
#endif
