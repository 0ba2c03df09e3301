// Which material and scene features a scene uses (kernels/common/features.h, the one list),
// so the OpenCL program is built with only those code paths.
#pragma once

#include <cstdint>
#include <string>

#include "kernels/common/features.h"

namespace aw {

struct PackedScene;
struct RenderSettings;

struct FeatureSet {
  enum Id {
#define AW_FEATURE_ENUM(name) name = AW_FID_##name,
    AW_FEATURE_LIST(AW_FEATURE_ENUM)
#undef AW_FEATURE_ENUM
        COUNT = AW_FEATURE_COUNT
  };
  bool on[COUNT] = {};

  static FeatureSet all();
  static const char* name(int id);
  static std::string lower_name(int id);  // name(id) in lower case, as describe() lists it
  uint32_t mask() const;  // AW_FEATBIT_* of the features that are on
  // "-DAW_FEATURES=0x...u" for the OpenCL build (kernels/common/features.h).
  std::string defines() const;
  // "reflection refraction light_quad ..." (lower case), or "none".
  std::string describe() const;
  bool lobe(uint32_t lid) const;  // is the shading kernel of lobe `lid` in this build?
};

// The one decision of what a scene uses, from its packed materials and lights and its render
// settings (lobe splitting, the sampler). Conservative: a feature is on when any material or light could
// use it. The kernels still check (classify_hit counts a path that meets a compiled-out
// feature; the renderer then fails). pack_scene calls it and keeps the result in
// PackedScene::features; nothing else decides a feature.
FeatureSet decide_features(const PackedScene& scene, const RenderSettings& settings);

}  // namespace aw
