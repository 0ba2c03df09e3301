#include "host/render/features.h"

#include <cctype>
#include <cstdio>

#include "host/render/scene_pack.h"
#include "kernels/integrator/split.h"
#include "kernels/material/architectural.h"
#include "kernels/material/lobe_list.h"

static_assert(AW_FEATURE_COUNT <= 32, "feature bits are a 32-bit mask (kernels/common/features.h, AW_FEATURES)");

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

uint32_t FeatureSet::mask() const {
  uint32_t m = 0;
  for (int i = 0; i < COUNT; ++i)
    if (on[i]) m |= 1u << i;
  return m;
}

std::string FeatureSet::defines() const {
  char buf[32];
  std::snprintf(buf, sizeof buf, "-DAW_FEATURES=0x%08xu", mask());
  return buf;
}

std::string FeatureSet::lower_name(int id) {
  std::string n = name(id);
  for (char& c : n) c = char(std::tolower(static_cast<unsigned char>(c)));
  return n;
}

std::string FeatureSet::describe() const {
  std::string s;
  for (int i = 0; i < COUNT; ++i)
    if (on[i]) s += (s.empty() ? "" : " ") + lower_name(i);
  return s.empty() ? "none" : s;
}

bool FeatureSet::lobe(uint32_t lid) const { return (lobe_feature_bit(lid) & ~mask()) == 0u; }

FeatureSet decide_features(const PackedScene& scene, const RenderSettings& settings) {
  FeatureSet f;
  // Material features: the kernels' own definition of what a material uses.
  uint32_t used = 0;
  for (const MaterialGpu& m : scene.materials) used |= material_features(&m);
  for (int i = 0; i < AW_FEAT_MATERIAL_COUNT; ++i) f.on[i] = (used >> i) & 1u;
  for (const LightGpu& l : scene.lights) {
    if (l.type == AW_LIGHT_POINT) f.on[FeatureSet::LIGHT_POINT] = true;
    if (l.type == AW_LIGHT_QUAD) f.on[FeatureSet::LIGHT_QUAD] = true;
    if (l.type == AW_LIGHT_DISK) f.on[FeatureSet::LIGHT_DISK] = true;
    if (l.type == AW_LIGHT_SPHERE) f.on[FeatureSet::LIGHT_SPHERE] = true;
    if (l.type == AW_LIGHT_SUN) f.on[FeatureSet::LIGHT_SUN] = true;
    if (l.type == AW_LIGHT_ENV) f.on[FeatureSet::ENV_MAP] = true;
    if (l.type == AW_LIGHT_TRIANGLE) f.on[FeatureSet::LIGHT_MESH] = true;
  }
  if (!scene.light_tree.empty()) f.on[FeatureSet::LIGHT_TREE] = true;
  if (!scene.soup.spheres.empty()) f.on[FeatureSet::SPHERE] = true;
  if (!scene.soup.instances.empty()) f.on[FeatureSet::INSTANCE] = true;
  // The sampler (Sobol' is in every build).
  if (settings.sampler == RenderSettings::Sampler::Independent) f.on[FeatureSet::SAMPLER_INDEPENDENT] = true;
  if (settings.sampler == RenderSettings::Sampler::ZSobol) f.on[FeatureSet::SAMPLER_ZSOBOL] = true;
  if (settings.aovs != 0) f.on[FeatureSet::AOV] = true;
  // Per-lobe samples split the first hit's rays (docs/material.md §6) only when some lobe that
  // a material can choose at all gets n = round(samples / spp) >= 2; otherwise splitting
  // changes nothing and the kernels are built without it (kernels/integrator/split.h).
  if (settings.lobe_splitting) {
    const uint32_t spp = uint32_t(settings.spp);
    for (const MaterialGpu& m : scene.materials)
      for (uint32_t lid = 0; lid < AW_LID_COUNT; ++lid)
        if (lobe_present(&m, lid) && lobe_split_count(&m, lid, spp) > 1u) f.on[FeatureSet::SPLIT] = true;
  }
  return f;
}

}  // namespace aw
