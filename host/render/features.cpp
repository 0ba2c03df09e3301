#include "host/render/features.h"

#include <cctype>

#include "kernels/material/architectural.h"

namespace aw {

FeatureSet FeatureSet::all() {
  FeatureSet f;
  for (bool& b : f.on) b = true;
  return f;
}

const char* FeatureSet::name(int id) {
  static const char* names[] = {
#define AW_FEATURE_NAME(n) #n,
      AW_FEATURE_LIST(AW_FEATURE_NAME)
#undef AW_FEATURE_NAME
  };
  return names[id];
}

std::string FeatureSet::defines() const {
  std::string s = "-DAW_SPECIALISED";
  for (int i = 0; i < COUNT; ++i) s += std::string(" -DAW_FEAT_") + name(i) + "=" + (on[i] ? "1" : "0");
  return s;
}

std::string FeatureSet::describe() const {
  std::string s;
  for (int i = 0; i < COUNT; ++i) {
    if (!on[i]) continue;
    std::string n = name(i);
    for (char& c : n) c = char(std::tolower(static_cast<unsigned char>(c)));
    s += (s.empty() ? "" : " ") + n;
  }
  return s.empty() ? "none" : s;
}

bool FeatureSet::lobe(uint32_t lid) const {
  switch (lid) {
    case AW_LID_TRANSLUCENCY: return on[TRANSLUCENCY];
    case AW_LID_REFLECTION:
    case AW_LID_REFLECTION2: return on[REFLECTION];
    case AW_LID_REFRACTION: return on[REFRACTION];
    default: return true;  // diffuse is always built
  }
}

FeatureSet derive_features(const PackedScene& scene) {
  FeatureSet f;
  // The kernels' own definition of what a material uses (AW_FEATBIT_* in list order).
  static_assert(AW_FEATBIT_TRANSLUCENCY == 1u << FeatureSet::TRANSLUCENCY &&
                    AW_FEATBIT_REFLECTION == 1u << FeatureSet::REFLECTION &&
                    AW_FEATBIT_REFRACTION == 1u << FeatureSet::REFRACTION &&
                    AW_FEATBIT_ROUGH_DIFFUSE == 1u << FeatureSet::ROUGH_DIFFUSE &&
                    AW_FEATBIT_ANISOTROPY == 1u << FeatureSet::ANISOTROPY && AW_FEATBIT_FOG == 1u << FeatureSet::FOG &&
                    AW_FEATBIT_CUTOUT == 1u << FeatureSet::CUTOUT &&
                    AW_FEATBIT_INCANDESCENCE == 1u << FeatureSet::INCANDESCENCE &&
                    AW_FEATBIT_BRDF_BECKMANN == 1u << FeatureSet::BRDF_BECKMANN &&
                    AW_FEATBIT_BRDF_AS == 1u << FeatureSet::BRDF_AS &&
                    AW_FEATBIT_FRESNEL_CONDUCTOR == 1u << FeatureSet::FRESNEL_CONDUCTOR &&
                    AW_FEATBIT_FRESNEL_CURVE == 1u << FeatureSet::FRESNEL_CURVE &&
                    AW_FEATBIT_THIN_WALLED == 1u << FeatureSet::THIN_WALLED &&
                    AW_FEAT_MATERIAL_COUNT == FeatureSet::THIN_WALLED + 1,
                "feature bits follow AW_FEATURE_LIST, material features first");
  uint32_t used = 0;
  for (const MaterialGpu& m : scene.materials) used |= material_features(&m);
  for (int i = 0; i < AW_FEAT_MATERIAL_COUNT; ++i) f.on[i] = (used >> i) & 1u;
  for (const LightGpu& l : scene.lights) {
    if (l.type == AW_LIGHT_POINT) f.on[FeatureSet::LIGHT_POINT] = true;
    if (l.type == AW_LIGHT_QUAD) f.on[FeatureSet::LIGHT_QUAD] = true;
    if (l.type == AW_LIGHT_DISK) f.on[FeatureSet::LIGHT_DISK] = true;
    if (l.type == AW_LIGHT_SPHERE) f.on[FeatureSet::LIGHT_SPHERE] = true;
  }
  // pack_scene decides whether any lobe splits (render.lobe_splitting and samples vs spp).
  f.on[FeatureSet::SPLIT] = scene.params.split_spp != 0u;
  return f;
}

}  // namespace aw
