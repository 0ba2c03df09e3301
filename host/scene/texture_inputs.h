// The material inputs that may be bound to a texture ({"texture": NAME} in place of a value;
// docs/scene-format.md#textures), with the words of the kernels' MaterialGpu the value goes
// to and the range it is clamped to (the same ranges the loader clamps constants to,
// host/scene/material_parse.cpp). The loader refuses a texture on any other key; the packer
// (host/render/texture_pack.cpp) turns each binding into a TexBindingGpu.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>

#include "kernels/common/compat.h"
#include "kernels/types/material.h"

namespace aw {

struct TextureInput {
  const char* key;  // as docs/material.md names it
  uint32_t word;    // first 32-bit word in MaterialGpu
  uint32_t count;   // 1: a scalar, 3: a colour
  float lo, hi;
};

namespace texture_inputs_detail {
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr uint32_t word(size_t offset) { return uint32_t(offset / 4); }
constexpr uint32_t refl(int i, size_t field) {
  return word(offsetof(MaterialGpu, refl) + size_t(i) * sizeof(ReflectionGpu) + field);
}
}  // namespace texture_inputs_detail

// Inputs whose packed value is not the key's value alone are absent: fog (a volume, read where
// the path leaves it), the Fresnel controls and per-material depths. incandescent.color is
// packed as colour x scale: its binding's multiplier and offset carry the scale.
inline const TextureInput* texture_inputs(size_t* n) {
  using namespace texture_inputs_detail;
  static const TextureInput kInputs[] = {
      {"diffuse.color", word(offsetof(MaterialGpu, diffuse_color)), 3, 0.0f, 1.0f},
      {"diffuse.weight", word(offsetof(MaterialGpu, diffuse_weight)), 1, 0.0f, 1.0f},
      {"diffuse.roughness", word(offsetof(MaterialGpu, diffuse_roughness)), 1, 0.0f, 1.0f},
      {"translucency.color", word(offsetof(MaterialGpu, transl_color)), 3, 0.0f, 1.0f},
      {"translucency.weight", word(offsetof(MaterialGpu, transl_weight)), 1, 0.0f, 1.0f},
      {"reflection.color", refl(0, offsetof(ReflectionGpu, color)), 3, 0.0f, 1.0f},
      {"reflection.weight", refl(0, offsetof(ReflectionGpu, weight)), 1, 0.0f, 1.0f},
      {"reflection.glossiness", refl(0, offsetof(ReflectionGpu, glossiness)), 1, 0.0f, 1.0f},
      {"reflection2.color", refl(1, offsetof(ReflectionGpu, color)), 3, 0.0f, 1.0f},
      {"reflection2.weight", refl(1, offsetof(ReflectionGpu, weight)), 1, 0.0f, 1.0f},
      {"reflection2.glossiness", refl(1, offsetof(ReflectionGpu, glossiness)), 1, 0.0f, 1.0f},
      {"highlight_vs_reflection", word(offsetof(MaterialGpu, highlight_vs_reflection)), 1, 0.0f, kInf},
      {"anisotropy.amount", word(offsetof(MaterialGpu, aniso_amount)), 1, -1.0f, 1.0f},
      {"anisotropy.rotation", word(offsetof(MaterialGpu, aniso_rotation)), 1, -kInf, kInf},
      {"refraction.color", word(offsetof(MaterialGpu, refr_color)), 3, 0.0f, 1.0f},
      {"refraction.weight", word(offsetof(MaterialGpu, refr_weight)), 1, 0.0f, 1.0f},
      {"refraction.glossiness", word(offsetof(MaterialGpu, refr_glossiness)), 1, 0.0f, 1.0f},
      {"incandescent.color", word(offsetof(MaterialGpu, incandescent)), 3, 0.0f, kInf},
      {"cutout_opacity", word(offsetof(MaterialGpu, cutout_opacity)), 1, 0.0f, 1.0f},
      {"ao.shadow_color", word(offsetof(MaterialGpu, ao_shadow_color)), 3, 0.0f, kInf},
      {"ao.ambient_color", word(offsetof(MaterialGpu, ao_ambient_color)), 3, 0.0f, kInf},
  };
  *n = sizeof(kInputs) / sizeof(kInputs[0]);
  return kInputs;
}

inline const TextureInput* find_texture_input(const std::string& key) {
  size_t n = 0;
  const TextureInput* in = texture_inputs(&n);
  for (size_t i = 0; i < n; ++i)
    if (key == in[i].key) return &in[i];
  return nullptr;
}

}  // namespace aw
