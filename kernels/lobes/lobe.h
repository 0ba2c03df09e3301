// The lobe contract, written once (Mitsuba 3's bsdf.h is the model). Every lobe in
// kernels/lobes/ provides, in the LOCAL shading frame (+z = shading normal, wo and wi unit
// vectors pointing away from the surface):
//
//   float3 lobe_<name>_eval(params, wo, wi)   f(wo, wi) * |cos theta_i|; 0 where the lobe
//                                             has no support (never NaN)
//   float  lobe_<name>_pdf(params, wo, wi)    solid-angle density of lobe_<name>_sample
//                                             choosing wi; 0 for delta lobes
//   LobeSample lobe_<name>_sample(params, wo, u)
//                                             draws wi from the explicit random numbers u
//                                             (never an RNG); weight = eval / pdf, or the
//                                             delta weight; pdf = 0 and weight = 0 on failure
//
// Flags tell MIS and the path logic what kind of scattering happened (pbrt-v4's BxDFFlags).
#ifndef AW_LOBES_LOBE_H
#define AW_LOBES_LOBE_H

#include "common/compat.h"
#include "common/lanes.h"

#define AW_LOBE_REFLECTION 1u
#define AW_LOBE_TRANSMISSION 2u
#define AW_LOBE_DIFFUSE 4u
#define AW_LOBE_GLOSSY 8u
#define AW_LOBE_SPECULAR 16u  // delta: no MIS, no light sampling
#define AW_LOBE_DIFFUSE_REFLECTION (AW_LOBE_DIFFUSE | AW_LOBE_REFLECTION)

// On lanes (common/lanes.h): W paths' samples, each field one vector per coordinate.
typedef struct {
  lfloat3 wi;
  lfloat3 weight;
  lfloat pdf;
  luint flags;  // 0 = no sample
  // eta^2 of the interface crossed (eta = n_t / n_i), the inverse of the 1/eta^2 radiance
  // scaling in `weight`; 1 for everything that does not refract into another medium. Russian
  // roulette multiplies it out of the throughput (pbrt-v4's etaScale; docs/performance.md).
  lfloat eta_scale;
} LobeSample;

AW_FN float cos_theta(float3 w) { return w.z; }

// Half vector of a reflection pair; 0 when it does not exist (both directions must be above
// the surface). Every reflection BRDF's (reflection.h: Beckmann, GGX, Ashikhmin-Shirley).
AW_FN int reflection_half_vector(float3 wo, float3 wi, float3* h) {
  if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return 0;
  float3 v = wo + wi;
  float len = length(v);
  if (!(len > 0.0f)) return 0;
  *h = v / len;
  return 1;
}

// The failed sample of the contract: flags 0, weight 0, pdf 0 (wi is +z, a placeholder that
// callers must not use).
AW_FN LobeSample lobe_no_sample(void) {
  LobeSample s;
  s.wi = make_lfloat3((lfloat)(0.0f), (lfloat)(0.0f), (lfloat)(1.0f));
  s.weight = make_lfloat3((lfloat)(0.0f), (lfloat)(0.0f), (lfloat)(0.0f));
  s.pdf = (lfloat)(0.0f);
  s.flags = (luint)(0u);
  s.eta_scale = (lfloat)(1.0f);
  return s;
}

#endif
