// Arbitrary output variables (docs/production.md#aovs): what a camera sample reports besides
// its value, summed per pixel in the film's exact sums (integrator/film.h) like the beauty, so
// that parts and resumed renders carry them bit for bit too.
//
// Every sample reports the same AW_AOV_FLOATS numbers (the layout below); the film keeps the
// AOVs the render asked for (RenderParams.aov_mask), in the order of AW_AOV_LIST:
//   first-hit data, the same for a pixel's every sample up to the pixel filter, noise-free
//   enough for a denoiser: albedo (the material's reflectance at the view angle: each lobe's
//   weight times its colour, material_albedo), normal (the shading normal, world space,
//   facing the camera), depth (distance from the camera), position (world space),
//   material_id (the material's index in the scene: the pixel's mean, so fractional at
//   edges); 0 where the camera ray leaves the scene or hits a light;
//   light groups, which sum to the beauty (to float precision; the clamp applies to each as
//   to the beauty): emission (light reaching the camera without scattering: lights, the
//   environment, incandescence at the first hit), ao (ambient occlusion's add term at the
//   first hit), and per lobe chosen at the first hit, everything the path gathered after it:
//   diffuse, translucency, reflection (both reflection lobes), refraction.
#ifndef AW_INTEGRATOR_AOV_H
#define AW_INTEGRATOR_AOV_H

#include "common/compat.h"
#include "common/features.h"
#include "integrator/film.h"
#include "integrator/path_state.h"
#include "material/lobe_list.h"
#include "types/scene.h"

//        id, name,          channels, light group (1: exposed like the beauty)
#define AW_AOV_LIST(X)                \
  X(ALBEDO, albedo, 3, 0)             \
  X(NORMAL, normal, 3, 0)             \
  X(DEPTH, depth, 1, 0)               \
  X(POSITION, position, 3, 0)         \
  X(MATERIAL_ID, material_id, 1, 0)   \
  X(EMISSION, emission, 3, 1)         \
  X(AO, ao, 3, 1)                     \
  X(DIFFUSE, diffuse, 3, 1)           \
  X(TRANSLUCENCY, translucency, 3, 1) \
  X(REFLECTION, reflection, 3, 1)     \
  X(REFRACTION, refraction, 3, 1)

enum {
#define AW_AOV_ID(ID, name, n, group) AW_AOV_##ID,
  AW_AOV_LIST(AW_AOV_ID)
#undef AW_AOV_ID
  AW_AOV_COUNT
};

// The per-sample report: offsets into AW_AOV_FLOATS floats.
#define AW_AOVF_ALBEDO 0
#define AW_AOVF_NORMAL 3
#define AW_AOVF_DEPTH 6
#define AW_AOVF_POSITION 7
#define AW_AOVF_MATERIAL 10
#define AW_AOVF_EMISSION 11
#define AW_AOVF_AO 14
#define AW_AOVF_GROUP 17     // the first-hit lobe's group: its RGB...
#define AW_AOVF_GROUP_ID 20  // ...and which AOV it is (an AW_AOV_* as a float; -1: none)
#define AW_AOV_FLOATS 21

AW_FN uint aov_channels(uint aov) {
#define AW_AOV_CH(ID, name, n, group) \
  if (aov == (uint)AW_AOV_##ID) return n;
  AW_AOV_LIST(AW_AOV_CH)
#undef AW_AOV_CH
  return 0u;
}

AW_FN int aov_is_light_group(uint aov) { return aov >= (uint)AW_AOV_EMISSION; }

// Where an AOV's channels start in the report.
AW_FN uint aov_report_offset(uint aov) {
  if (aov == (uint)AW_AOV_ALBEDO) return AW_AOVF_ALBEDO;
  if (aov == (uint)AW_AOV_NORMAL) return AW_AOVF_NORMAL;
  if (aov == (uint)AW_AOV_DEPTH) return AW_AOVF_DEPTH;
  if (aov == (uint)AW_AOV_POSITION) return AW_AOVF_POSITION;
  if (aov == (uint)AW_AOV_MATERIAL_ID) return AW_AOVF_MATERIAL;
  if (aov == (uint)AW_AOV_EMISSION) return AW_AOVF_EMISSION;
  if (aov == (uint)AW_AOV_AO) return AW_AOVF_AO;
  return AW_AOVF_GROUP;  // the lobe groups share the group slot (AW_AOVF_GROUP_ID says whose)
}

// The light group of a lobe chosen at the first hit.
AW_FN uint aov_group_of_lobe(uint lid) {
  if (lid == (uint)AW_LID_DIFFUSE) return AW_AOV_DIFFUSE;
  if (lid == (uint)AW_LID_TRANSLUCENCY) return AW_AOV_TRANSLUCENCY;
  if (lid == (uint)AW_LID_REFLECTION || lid == (uint)AW_LID_REFLECTION2) return AW_AOV_REFLECTION;
  return AW_AOV_REFRACTION;
}

// The film's channels for the AOVs in `mask`.
AW_FN uint aov_film_channels(uint mask) {
  uint n = 0u;
  for (uint a = 0u; a < (uint)AW_AOV_COUNT; ++a)
    if (mask & (1u << a)) n += aov_channels(a);
  return n;
}

// The first hit's data in the path (PathRef.aov, PS_AOV): the report's first 11 floats, then
// the radiance when the first hit's classify ended (E: what reached the camera unscattered)
// and when the first scattering began (A: E plus ambient occlusion's add term), and the light
// group of the lobe chosen there (-1: none). Constant over a sample's splits (split.h).
#define AW_AOVS_E 11
#define AW_AOVS_A 14
#define AW_AOVS_GROUP 17
#define AW_AOV_STATE 18

AW_FN int aov_on(const RenderParams* rp) { return AW_FEAT_AOV && rp->aov_mask != 0u; }

// A camera ray: nothing known yet (a ray that leaves the scene keeps the zeros).
AW_FN void aov_begin(PathRef ps, const RenderParams* rp) {
  if (!aov_on(rp)) return;
  for (uint i = 0u; i < (uint)AW_AOV_STATE; ++i) PS_AOV(ps, i) = 0.0f;
  PS_AOV(ps, AW_AOVS_GROUP) = -1.0f;
}

// The first surface the camera ray hit.
AW_FN void aov_surface(PathRef ps, const RenderParams* rp, float3 albedo, float3 n, float3 p, float depth, uint material) {
  if (!aov_on(rp) || PS_U(ps, bounce) != 0u) return;
  PS_AOV(ps, AW_AOVF_ALBEDO + 0) = albedo.x;
  PS_AOV(ps, AW_AOVF_ALBEDO + 1) = albedo.y;
  PS_AOV(ps, AW_AOVF_ALBEDO + 2) = albedo.z;
  PS_AOV(ps, AW_AOVF_NORMAL + 0) = n.x;
  PS_AOV(ps, AW_AOVF_NORMAL + 1) = n.y;
  PS_AOV(ps, AW_AOVF_NORMAL + 2) = n.z;
  PS_AOV(ps, AW_AOVF_DEPTH) = depth;
  PS_AOV(ps, AW_AOVF_POSITION + 0) = p.x;
  PS_AOV(ps, AW_AOVF_POSITION + 1) = p.y;
  PS_AOV(ps, AW_AOVF_POSITION + 2) = p.z;
  PS_AOV(ps, AW_AOVF_MATERIAL) = (float)material;
}

AW_FN void aov_store_radiance(PathRef ps, uint at) {
  PS_AOV(ps, at + 0u) = PS_F(ps, rad_r);
  PS_AOV(ps, at + 1u) = PS_F(ps, rad_g);
  PS_AOV(ps, at + 2u) = PS_F(ps, rad_b);
}

// The end of the first hit's classify (`bounce` its vertex): E and A are what the path holds.
AW_FN void aov_first_classified(PathRef ps, const RenderParams* rp, uint bounce) {
  if (!aov_on(rp) || bounce != 0u) return;
  aov_store_radiance(ps, AW_AOVS_E);
  aov_store_radiance(ps, AW_AOVS_A);
}

// The first scattering begins (lobe `lid`; AW_NONE: ambient occlusion ended the path):
// A is what the path holds now.
AW_FN void aov_first_scatter(PathRef ps, const RenderParams* rp, uint lid) {
  if (!aov_on(rp) || PS_U(ps, bounce) != 0u) return;
  aov_store_radiance(ps, AW_AOVS_A);
  if (lid != AW_NONE) PS_AOV(ps, AW_AOVS_GROUP) = (float)aov_group_of_lobe(lid);
}

// A value the film's grid takes: finite and below 2^59 in magnitude, else 0.
AW_FN float aov_safe(float v) { return isfinite(v) && fabs(v) < 5.7646075e17f ? v : 0.0f; }

// The sample's report (AW_AOV_FLOATS): value l (final, the mean of its splits), k the mean
// factor its splits were clamped by (0 for a discarded sample), so that the light groups sum
// to l: emission E k, ao (A - E) k, the first lobe's group l - A k.
AW_FN void aov_report(PathRef ps, float3 l, float k, AW_GLOBAL float* out) {
  for (uint i = 0u; i < (uint)AW_AOVF_EMISSION; ++i) out[i] = aov_safe(PS_AOV(ps, i));
  float group = PS_AOV(ps, AW_AOVS_GROUP);
  float3 e = make_float3(PS_AOV(ps, AW_AOVS_E + 0), PS_AOV(ps, AW_AOVS_E + 1), PS_AOV(ps, AW_AOVS_E + 2)) * k;
  float3 a = make_float3(PS_AOV(ps, AW_AOVS_A + 0), PS_AOV(ps, AW_AOVS_A + 1), PS_AOV(ps, AW_AOVS_A + 2)) * k;
  float3 rest = l - a;
  if (group < 0.0f) {  // no lobe scattered the path: nothing was gathered after A
    e = e + rest;
    rest = make_float3(0.0f, 0.0f, 0.0f);
  }
  float3 ao = a - make_float3(PS_AOV(ps, AW_AOVS_E + 0), PS_AOV(ps, AW_AOVS_E + 1), PS_AOV(ps, AW_AOVS_E + 2)) * k;
  out[AW_AOVF_EMISSION + 0] = aov_safe(e.x);
  out[AW_AOVF_EMISSION + 1] = aov_safe(e.y);
  out[AW_AOVF_EMISSION + 2] = aov_safe(e.z);
  out[AW_AOVF_AO + 0] = aov_safe(ao.x);
  out[AW_AOVF_AO + 1] = aov_safe(ao.y);
  out[AW_AOVF_AO + 2] = aov_safe(ao.z);
  out[AW_AOVF_GROUP + 0] = aov_safe(rest.x);
  out[AW_AOVF_GROUP + 1] = aov_safe(rest.y);
  out[AW_AOVF_GROUP + 2] = aov_safe(rest.z);
  out[AW_AOVF_GROUP_ID] = group;
}

// Adds a sample's report to a pixel's AOV sums (the film's channels of `mask`, in list order).
AW_FN void film_add_aovs(AW_GLOBAL ulong* sums, const AW_GLOBAL float* r, uint mask) {
  uint c = 0u;
  for (uint a = 0u; a < (uint)AW_AOV_COUNT; ++a) {
    if (!(mask & (1u << a))) continue;
    uint n = aov_channels(a), off = aov_report_offset(a);
    int take = a < (uint)AW_AOV_DIFFUSE || r[AW_AOVF_GROUP_ID] == (float)a;
    if (take)
      for (uint j = 0u; j < n; ++j) film_add_signed(sums + (c + j) * 2u, r[off + j]);
    c += n;
  }
}

#ifndef __OPENCL_C_VERSION__
#include <string>
// The AOV names render.aovs and --aovs take: each name of AW_AOV_LIST, and "light_groups" for
// all six light groups. 0 for an unknown name.
inline uint32_t aov_bits_for_name(const std::string& s) {
#define AW_AOV_NAME(ID, name, n, group) \
  if (s == #name) return 1u << AW_AOV_##ID;
  AW_AOV_LIST(AW_AOV_NAME)
#undef AW_AOV_NAME
  if (s == "light_groups") {
    uint32_t b = 0;
    for (uint32_t a = AW_AOV_EMISSION; a < AW_AOV_COUNT; ++a) b |= 1u << a;
    return b;
  }
  return 0u;
}
inline const char* aov_name(uint32_t aov) {
#define AW_AOV_STR(ID, name, n, group) \
  if (aov == AW_AOV_##ID) return #name;
  AW_AOV_LIST(AW_AOV_STR)
#undef AW_AOV_STR
  return "?";
}
inline std::string aov_known_names() {
  std::string s;
  for (uint32_t a = 0; a < AW_AOV_COUNT; ++a) s += std::string(a ? ", " : "") + aov_name(a);
  return s + ", light_groups";
}
#endif

#endif
