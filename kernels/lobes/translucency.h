// Translucency: diffuse transmission (docs/material.md §3.2), the "double-sided diffuse
// lighting" of leaves and paper. A Lambertian lobe on the far side of the surface:
//   f(wo, wi) = color / pi   where wo and wi lie on opposite sides, 0 elsewhere,
// sampled with the cosine-weighted hemisphere (Malley's method, common/sampling.h) mirrored
// to the side opposite wo, pdf = |cos theta_i| / pi, so the sample weight is exactly `color`
// and the directional albedo is `color` (lossless for white).
//
// The integrator's frame has wo.z > 0, so wi.z < 0 there; the lobe is written for either
// side of wo (only "opposite sides" matters), which keeps it reciprocal:
// f(wo, wi) = f(wi, wo). wo.z == 0 or wi.z == 0 (grazing exactly) has no support.
#ifndef AW_LOBES_TRANSLUCENCY_H
#define AW_LOBES_TRANSLUCENCY_H

#include "common/sampling.h"
#include "lobes/lobe.h"

#ifndef AW_LOBE_DIFFUSE_TRANSMISSION
#define AW_LOBE_DIFFUSE_TRANSMISSION (AW_LOBE_DIFFUSE | AW_LOBE_TRANSMISSION)
#endif

// Sign tests rather than wo.z * wi.z < 0: the product of two tiny cosines underflows to 0.
AW_FN int translucency_opposite_sides(float3 wo, float3 wi) {
  return (wo.z > 0.0f && wi.z < 0.0f) || (wo.z < 0.0f && wi.z > 0.0f);
}

// f * |cos theta_i|.
AW_FN float3 lobe_translucency_eval(float3 color, float3 wo, float3 wi) {
  if (!translucency_opposite_sides(wo, wi)) return make_float3(0.0f, 0.0f, 0.0f);
  return color * (fabs(wi.z) * (1.0f / M_PI_F));
}

AW_FN float lobe_translucency_pdf(float3 wo, float3 wi) {
  if (!translucency_opposite_sides(wo, wi)) return 0.0f;
  return pdf_cosine_hemisphere(fabs(wi.z));
}

AW_FN LobeSample lobe_translucency_sample(float3 color, float3 wo, float2 u) {
  LobeSample s = lobe_no_sample();
  s.wi = sample_cosine_hemisphere(u);
  if (wo.z > 0.0f) s.wi.z = -s.wi.z;  // the far side of wo
  s.pdf = lobe_translucency_pdf(wo, s.wi);
  if (!(s.pdf > 0.0f)) {
    s.weight = make_float3(0.0f, 0.0f, 0.0f);
    s.flags = 0u;
    s.pdf = 0.0f;
    return s;
  }
  s.weight = color;  // f |cos| / pdf = (color / pi) |cos| / (|cos| / pi)
  s.flags = AW_LOBE_DIFFUSE_TRANSMISSION;
  return s;
}

// Directional albedo (for lobe selection weights): `color` wherever wo has support.
AW_FN float3 lobe_translucency_albedo(float3 color, float cos_o) {
  return cos_o != 0.0f ? color : make_float3(0.0f, 0.0f, 0.0f);
}

#endif
