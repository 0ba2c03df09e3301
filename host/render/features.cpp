#include "host/render/features.h"

#include <cctype>

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
  auto positive = [](const float* c) { return c[0] > 0.0f || c[1] > 0.0f || c[2] > 0.0f; };
  for (const MaterialGpu& m : scene.materials) {
    bool refl = false;
    for (const ReflectionGpu& r : m.refl) refl |= r.weight > 0.0f && positive(r.color);
    bool transmit = m.refr_weight > 0.0f;
    bool transl = transmit && (m.flags & AW_MAT_TRANSLUCENCY) && m.transl_weight > 0.0f;
    bool refr = transmit && !(transl && m.transl_weight >= 1.0f);
    f.on[FeatureSet::REFLECTION] |= refl;
    f.on[FeatureSet::TRANSLUCENCY] |= transl;
    f.on[FeatureSet::REFRACTION] |= refr;
    f.on[FeatureSet::ROUGH_DIFFUSE] |= m.diffuse_roughness > 0.0f;
    f.on[FeatureSet::ANISOTROPY] |= refl && m.aniso_amount != 0.0f;
    f.on[FeatureSet::FOG] |= refr && m.fog_distance > 0.0f;
    f.on[FeatureSet::CUTOUT] |= m.cutout_opacity < 0.5f;
    f.on[FeatureSet::INCANDESCENCE] |= positive(m.incandescent);
  }
  for (const LightGpu& l : scene.lights) {
    if (l.type == AW_LIGHT_POINT) f.on[FeatureSet::LIGHT_POINT] = true;
    if (l.type == AW_LIGHT_QUAD) f.on[FeatureSet::LIGHT_QUAD] = true;
    if (l.type == AW_LIGHT_DISK) f.on[FeatureSet::LIGHT_DISK] = true;
    if (l.type == AW_LIGHT_SPHERE) f.on[FeatureSet::LIGHT_SPHERE] = true;
  }
  return f;
}

}  // namespace aw
