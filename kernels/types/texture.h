// Textures as the kernels read them, packed by host/render/texture_pack.cpp from
// host/scene/texture_desc.h and sampled by kernels/texture/texture.h. Plain 4-byte fields only
// (tests/types checks the layout on every device).
#ifndef AW_TYPES_TEXTURE_H
#define AW_TYPES_TEXTURE_H

#define AW_TEX_IMAGE 0u
#define AW_TEX_CHECKER 1u
#define AW_TEX_NOISE 2u

// Texel formats in the byte buffer `texels`: 8-bit unsigned normalised (data images stored
// with 8 bits: bump, rotation, cutout, linear colour), IEEE half (sRGB 8-bit images decoded to
// linear, 16-bit PNGs, half EXRs) and float (float EXRs). `channels` values per texel.
#define AW_TEXFMT_U8 0u
#define AW_TEXFMT_F16 1u
#define AW_TEXFMT_F32 2u

#define AW_WRAP_REPEAT 0u
#define AW_WRAP_CLAMP 1u
#define AW_WRAP_MIRROR 2u
#define AW_WRAP_BLACK 3u

// Mip levels of a 16384 x 16384 image (the largest accepted), with room to spare.
#define AW_TEX_MAX_LEVELS 16

typedef struct {
  uint type;      // AW_TEX_*
  uint format;    // AW_TEXFMT_*
  uint channels;  // 1 (grey), 2 (grey, alpha), 3 (RGB), 4 (RGBA)
  uint wrap;      // AW_WRAP_*
  uint width;     // level 0
  uint height;
  uint levels;    // mip levels: level k is max(1, width >> k) x max(1, height >> k)
  uint octaves;   // noise
  // The texture's UV transform: u' = xf[0] u + xf[1] v + xf[2], v' = xf[3] u + xf[4] v + xf[5].
  float xf[6];
  float uv_scale;  // sqrt |det| of xf's linear part: how much the transform shrinks a footprint
  float pad;
  float color1[4];  // procedurals: RGB, unused
  float color2[4];
  uint level_offset[AW_TEX_MAX_LEVELS];  // byte offset of each level in `texels`
} TextureGpu;

// Where a texture binding's value goes (TexBindingGpu.channel).
#define AW_TEXCH_R 0u
#define AW_TEXCH_G 1u
#define AW_TEXCH_B 2u
#define AW_TEXCH_A 3u
#define AW_TEXCH_LUMINANCE 4u  // Rec. 709 luminance of RGB, into one word
#define AW_TEXCH_RGB 5u        // three words (a colour input); any other channel into `count` words

// A material input read from a texture: value = clamp(offset + multiplier * texel, lo, hi),
// written over the material's constant at word `word` of MaterialGpu (docs/scene-format.md,
// "textures"; kernels/texture/texture.h, material_resolve).
typedef struct {
  uint word;
  uint texture;
  uint channel;  // AW_TEXCH_*
  float multiplier;
  float offset;
  float lo;
  float hi;
  uint count;  // words written: 1 (a scalar input) or 3 (a colour input)
  uint uv_set; // 0 or 1: the UV set the lookup reads (VertexData.uv or uv2)
  uint pad[3];
} TexBindingGpu;

#endif
