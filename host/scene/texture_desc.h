// The "textures" section (docs/scene-format.md#textures) and a material input bound to a
// texture, as the loader hands them to the renderer (host/render/texture_pack.h packs them
// for the kernels; kernels/texture/texture.h samples them on both sides).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace aw {

struct TextureDesc {
  enum class Type { Image, Checker, Noise };
  enum class ColorSpace { Srgb, Linear };
  enum class Wrap { Repeat, Clamp, Mirror, Black };
  Type type = Type::Image;
  std::string name;  // the key in "textures" (or "FILE.gltf#texture 3" for glTF's)
  // Image: where the texels came from (a file as resolved against the scene file, or a
  // description such as "FILE.glb, image 2" for embedded images), for messages and stats.
  std::string source;
  ColorSpace colorspace = ColorSpace::Linear;  // of the file's values; texels below are linear
  Wrap wrap = Wrap::Repeat;
  // UV transform applied before the lookup: uv' = R(rotation) * (uv * scale) + offset
  // (KHR_texture_transform's order: scale, then rotate, then translate).
  glm::vec2 scale{1.0f};
  glm::vec2 offset{0.0f};
  float rotation = 0.0f;  // degrees, counter-clockwise in UV space
  // Image: linear RGBA texels, row 0 at V = 1 (the top row of the file), width * height * 4.
  int width = 0, height = 0;
  int channels = 0;  // channels the file had (1..4); texels always hold 4 (grey repeated, alpha 1)
  bool eight_bit = false;  // the file stored 8 bits per channel (packed as 8-bit when linear)
  std::vector<float> texels;
  // Procedurals (checker, noise): the two colours (RGB), noise octaves.
  glm::vec3 color1{0.0f}, color2{1.0f};
  int octaves = 4;
};

// The decoded image of `from` (size, channels, precision, texels) into *to, which keeps its own
// name, colour space, wrap and transform: two uses of one file with other settings.
inline void copy_decoded_image(const TextureDesc& from, TextureDesc* to) {
  to->width = from.width;
  to->height = from.height;
  to->channels = from.channels;
  to->eight_bit = from.eight_bit;
  to->texels = from.texels;
}

// A material input read from a texture: {"texture": NAME, "channel": "r", "multiplier": 2}.
// channel: -1 = RGB for colours, the luminance (Rec. 709 weights) for scalars; 0..3 = R, G, B, A
// (a colour input then takes that channel as grey).
// The input's value is offset + multiplier * texel (glTF's roughness maps become glossiness
// as 1 - roughness: offset 1, multiplier -roughnessFactor).
struct TextureRef {
  uint32_t texture = 0;  // index into Scene::textures
  int channel = -1;
  float multiplier = 1.0f;
  float offset = 0.0f;
  int uv_set = 0;  // 0 or 1: which of the mesh's UV sets the lookup reads (a mesh without set 1 reads set 0)
};

// A material's texture-bound inputs, keyed by the input's key as docs/material.md names it
// ("diffuse.color", "reflection.glossiness", "bump.input", "cutout_opacity", ...).
using TextureBindings = std::map<std::string, TextureRef>;

// Image decoding (host/scene/texture_image.cpp). PNG and JPEG through stb_image, EXR through
// OpenEXR, recognised by their content, not their name. t->colorspace says how to read the
// values (sRGB decoded to linear); fills width, height, channels, eight_bit and texels. On
// failure returns false with a message that does not repeat the source.
bool decode_texture_image(const unsigned char* bytes, size_t size, TextureDesc* t, std::string* error);
bool load_texture_file(const std::string& path, TextureDesc* t, std::string* error);

}  // namespace aw
