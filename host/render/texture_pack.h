// Textures for the kernels: every texture's mip pyramid in one byte buffer, and the material
// inputs bound to textures as TexBindingGpu entries (kernels/types/texture.h).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "host/scene/scene.h"
#include "kernels/common/compat.h"
#include "kernels/types/scene.h"

namespace aw {

struct PackedTextures {
  std::vector<TextureGpu> textures;
  std::vector<uint8_t> texels;  // every level of every texture, 4-byte aligned
};

// Builds the mip pyramids (2x2 box filter, level k of size max(1, w >> k) x max(1, h >> k))
// and packs them in the smallest format that keeps the file's precision: 8-bit linear data as
// 8 bits, 8-bit sRGB (decoded to linear) and 16-bit images as halves, EXRs as floats. Throws
// SceneError when the texels exceed the 4 GiB the 32-bit offsets address.
PackedTextures pack_textures(const Scene& scene);

// Each texture's range of values per channel (R, G, B, A and luminance), for the constants of
// pack_material_textures: computed in one pass over a texture's texels the first time a
// material binds it, and kept for the scene's other materials (a 16384 x 16384 image holds
// 4 GiB of texels).
class TextureRanges {
 public:
  explicit TextureRanges(const Scene& scene) : scene_(scene) {}
  void get(uint32_t texture, uint32_t channel, float* lo, float* hi);

 private:
  struct Range {
    float lo[5], hi[5];
  };
  const Scene& scene_;
  std::map<uint32_t, Range> cache_;
};

// Appends material d's texture bindings (d.textures) to *bindings and records them in *g
// (tex_first, tex_count, cutout_binding, bump_binding, bump_scale, no_bump_lobes). Each bound
// input's constant in *g becomes the largest magnitude the texture can give it (its range from
// `ranges`), so that the features decided from the packed materials include what any texel may
// switch on.
void pack_material_textures(const Scene& scene, const MaterialDesc& d, TextureRanges& ranges, MaterialGpu* g,
                            std::vector<TexBindingGpu>* bindings);

}  // namespace aw
