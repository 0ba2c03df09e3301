// Which material and light features a scene uses (kernels/common/features.h), so the OpenCL
// program is built with only those code paths.
#pragma once

#include <string>
#include <vector>

#include "host/render/scene_pack.h"

namespace aw {

struct FeatureSet {
  enum Id {
#define AW_FEATURE_ENUM(name) name,
    AW_FEATURE_LIST(AW_FEATURE_ENUM)
#undef AW_FEATURE_ENUM
        COUNT
  };
  bool on[COUNT] = {};

  static FeatureSet all();
  static const char* name(int id);
  // "-DAW_SPECIALISED -DAW_FEAT_TRANSLUCENCY=0 ..." for the OpenCL build.
  std::string defines() const;
  // "reflection refraction light_quad ..." (lower case), or "none".
  std::string describe() const;
  bool lobe(uint32_t lid) const;  // is the shading kernel of lobe `lid` in this build?
};

// Conservative: a feature is on when any material or light could use it. The kernels still
// check (classify_hit counts a path that meets a compiled-out lobe; the renderer then fails).
FeatureSet derive_features(const PackedScene& scene);

}  // namespace aw
