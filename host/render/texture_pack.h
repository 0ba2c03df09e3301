// Textures for the kernels: every texture's mip pyramid in one byte buffer, and the material
// inputs bound to textures as TexBindingGpu entries (kernels/types/texture.h).
#pragma once

#include <cstdint>
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

// Appends material d's texture bindings (d.textures) to *bindings and records them in *g
// (tex_first, tex_count, cutout_binding, bump_binding, bump_scale, no_bump_lobes). Each bound
// input's constant in *g becomes the largest magnitude the texture can give it, so that the
// features decided from the packed materials include what any texel may switch on.
void pack_material_textures(const Scene& scene, const MaterialDesc& d, MaterialGpu* g,
                            std::vector<TexBindingGpu>* bindings);

}  // namespace aw
