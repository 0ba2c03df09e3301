// Diffuse reflection. The foundation renders Lambert (Oren–Nayar roughness 0, which the
// material issue requires to equal Lambert exactly); the energy-preserving Oren–Nayar lobe
// extends this file.
#ifndef AW_LOBES_DIFFUSE_H
#define AW_LOBES_DIFFUSE_H

#include "common/sampling.h"
#include "lobes/lobe.h"

// f = albedo / pi on the upper hemisphere (both directions above the surface).
AW_FN float3 lobe_diffuse_eval(float3 albedo, float3 wo, float3 wi) {
  if (wo.z <= 0.0f || wi.z <= 0.0f) return make_float3(0.0f, 0.0f, 0.0f);
  return albedo * (wi.z * (1.0f / M_PI_F));
}

AW_FN float lobe_diffuse_pdf(float3 wo, float3 wi) {
  if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
  return pdf_cosine_hemisphere(wi.z);
}

// Cosine-weighted sampling makes the weight exactly the albedo (f cos / pdf).
AW_FN LobeSample lobe_diffuse_sample(float3 albedo, float3 wo, float2 u) {
  LobeSample s;
  s.wi = sample_cosine_hemisphere(u);
  s.pdf = lobe_diffuse_pdf(wo, s.wi);
  if (!(s.pdf > 0.0f)) {
    s.weight = make_float3(0.0f, 0.0f, 0.0f);
    s.flags = 0u;
    s.pdf = 0.0f;
    return s;
  }
  s.weight = albedo;
  s.flags = AW_LOBE_DIFFUSE_REFLECTION;
  return s;
}

#endif
