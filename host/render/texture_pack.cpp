#include "host/render/texture_pack.h"

#include <Imath/half.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>

#include "host/scene/texture_inputs.h"
#include "kernels/material/lobe_list.h"

namespace aw {

namespace {

// One mip level, RGBA floats: level 0 is read where the loader left it (TextureDesc::texels,
// 4 GiB at 16384 x 16384 texels: copying it doubled the peak memory and the time of packing a
// texture that large), the coarser ones are owned here.
struct Level {
  int w = 0, h = 0;
  const float* rgba = nullptr;
  std::vector<float> own;
};

// The next level: each texel the mean of the 2x2 block above it (a box filter; an odd last
// row or column of the finer level is averaged into its neighbour's block, so no texel is
// dropped and the mean is kept). Every texel's sum is taken in the finer level's row order
// (row by row, left to right, from 0) and divided by its count.
Level downsample(const Level& a) {
  Level b;
  b.w = std::max(1, a.w / 2);
  b.h = std::max(1, a.h / 2);
  b.own.assign(size_t(b.w) * size_t(b.h) * 4, 0.0f);
  if (a.w % 2 == 0 && a.h % 2 == 0) {
    // Every block is 2 x 2 (the common case, and all of a power-of-two pyramid but its 1-texel
    // rows or columns): the same sums in the same order, without the per-texel weights.
    for (int by = 0; by < b.h; ++by) {
      const float* r0 = a.rgba + size_t(2 * by) * size_t(a.w) * 4;
      const float* r1 = r0 + size_t(a.w) * 4;
      float* o = b.own.data() + size_t(by) * size_t(b.w) * 4;
      for (int bx = 0; bx < b.w; ++bx)
        for (int c = 0; c < 4; ++c) {
          const size_t i = size_t(2 * bx) * 4 + size_t(c);
          o[size_t(bx) * 4 + size_t(c)] = (((0.0f + r0[i]) + r0[i + 4]) + r1[i]) + r1[i + 4];
          o[size_t(bx) * 4 + size_t(c)] /= 4.0f;
        }
    }
    b.rgba = b.own.data();
    return b;
  }
  std::vector<float> weight(size_t(b.w) * size_t(b.h), 0.0f);
  for (int y = 0; y < a.h; ++y) {
    const int by = std::min(y / 2, b.h - 1);
    for (int x = 0; x < a.w; ++x) {
      const int bx = std::min(x / 2, b.w - 1);
      const size_t bi = size_t(by) * size_t(b.w) + size_t(bx);
      for (int c = 0; c < 4; ++c) b.own[bi * 4 + size_t(c)] += a.rgba[(size_t(y) * size_t(a.w) + size_t(x)) * 4 + size_t(c)];
      weight[bi] += 1.0f;
    }
  }
  for (size_t i = 0; i < weight.size(); ++i)
    for (int c = 0; c < 4; ++c) b.own[i * 4 + size_t(c)] /= weight[i];
  b.rgba = b.own.data();
  return b;
}

void put_level(const Level& l, uint32_t format, int channels, std::vector<uint8_t>* out) {
  // The channels the texture keeps: grey is stored once (R), grey+alpha as (R, A).
  const int src[4][4] = {{0}, {0, 3}, {0, 1, 2}, {0, 1, 2, 3}};
  const size_t n = size_t(l.w) * size_t(l.h) * size_t(channels);
  const size_t bytes = format == AW_TEXFMT_U8 ? 1 : format == AW_TEXFMT_F16 ? 2 : 4;
  const size_t start = out->size();
  out->resize(start + ((n * bytes + 3) & ~size_t(3)), 0);  // each level 4-byte aligned
  uint8_t* dst = out->data() + start;
  for (size_t i = 0; i < size_t(l.w) * size_t(l.h); ++i) {
    for (int c = 0; c < channels; ++c) {
      const float v = l.rgba[i * 4 + size_t(src[channels - 1][c])];
      const size_t k = i * size_t(channels) + size_t(c);
      if (format == AW_TEXFMT_U8) {
        // lround of a value in [0, 255], as floor(x + 0.5) taken in double (exact there; in
        // float, 0.49999997f + 0.5f would round up to 1): the same bytes, without a call per texel.
        dst[k] = uint8_t(double(std::clamp(v, 0.0f, 1.0f) * 255.0f) + 0.5);
      } else if (format == AW_TEXFMT_F16) {
        const uint16_t h = Imath::half(v).bits();
        std::memcpy(dst + 2 * k, &h, 2);
      } else {
        std::memcpy(dst + 4 * k, &v, 4);
      }
    }
  }
}

}  // namespace

PackedTextures pack_textures(const Scene& scene) {
  PackedTextures p;
  for (const TextureDesc& t : scene.textures) {
    TextureGpu g;
    std::memset(&g, 0, sizeof(g));
    g.wrap = t.wrap == TextureDesc::Wrap::Clamp    ? AW_WRAP_CLAMP
             : t.wrap == TextureDesc::Wrap::Mirror ? AW_WRAP_MIRROR
             : t.wrap == TextureDesc::Wrap::Black  ? AW_WRAP_BLACK
                                                   : AW_WRAP_REPEAT;
    // uv' = R(rotation) (uv * scale) + offset.
    const double r = double(t.rotation) * M_PI / 180.0, c = std::cos(r), s = std::sin(r);
    g.xf[0] = float(c * t.scale.x);
    g.xf[1] = float(-s * t.scale.y);
    g.xf[2] = t.offset.x;
    g.xf[3] = float(s * t.scale.x);
    g.xf[4] = float(c * t.scale.y);
    g.xf[5] = t.offset.y;
    g.uv_scale = float(std::sqrt(std::fabs(double(t.scale.x) * double(t.scale.y))));
    for (int k = 0; k < 3; ++k) {
      g.color1[k] = t.color1[k];
      g.color2[k] = t.color2[k];
    }
    g.octaves = uint32_t(std::max(1, t.octaves));
    if (t.type == TextureDesc::Type::Checker) {
      g.type = AW_TEX_CHECKER;
    } else if (t.type == TextureDesc::Type::Noise) {
      g.type = AW_TEX_NOISE;
    } else {
      g.type = AW_TEX_IMAGE;
      g.channels = uint32_t(std::clamp(t.channels, 1, 4));
      // 8-bit linear data keeps its 8 bits; 8-bit sRGB decoded to linear needs more near black
      // (its first step is 3e-4) and a half's 11 significant bits hold it; 16-bit and EXR
      // images keep floats (a half would lose a 16-bit height map's low bits).
      g.format = t.eight_bit ? (t.colorspace == TextureDesc::ColorSpace::Linear ? AW_TEXFMT_U8 : AW_TEXFMT_F16)
                             : AW_TEXFMT_F32;
      g.width = uint32_t(t.width);
      g.height = uint32_t(t.height);
      // The whole pyramid's bytes at once: growing the buffer level by level copied level 0 again.
      size_t pyramid = 0;
      const size_t texel_bytes = size_t(g.channels) * (g.format == AW_TEXFMT_U8 ? 1 : g.format == AW_TEXFMT_F16 ? 2 : 4);
      for (int w = t.width, h = t.height;; w = std::max(1, w / 2), h = std::max(1, h / 2)) {
        pyramid += (size_t(w) * size_t(h) * texel_bytes + 3) & ~size_t(3);
        if (w == 1 && h == 1) break;
      }
      p.texels.reserve(p.texels.size() + pyramid);
      Level l;
      l.w = t.width;
      l.h = t.height;
      l.rgba = t.texels.data();
      for (uint32_t k = 0; k < AW_TEX_MAX_LEVELS; ++k) {
        if (p.texels.size() > 0xffffffffull)
          throw SceneError(scene.path + ": textures: the textures' texels take more than the 4 GiB the kernels address");
        g.level_offset[k] = uint32_t(p.texels.size());
        put_level(l, g.format, int(g.channels), &p.texels);
        g.levels = k + 1;
        if (l.w == 1 && l.h == 1) break;
        l = downsample(l);
      }
      if (p.texels.size() > 0xffffffffull)
        throw SceneError(scene.path + ": textures: the textures' texels take more than the 4 GiB the kernels address");
    }
    p.textures.push_back(g);
  }
  return p;
}

void TextureRanges::get(uint32_t texture, uint32_t channel, float* lo, float* hi) {
  auto found = cache_.find(texture);
  if (found == cache_.end()) {
    const TextureDesc& t = scene_.textures[texture];
    Range r;
    for (int k = 0; k < 5; ++k) {
      r.lo[k] = std::numeric_limits<float>::max();
      r.hi[k] = -std::numeric_limits<float>::max();
    }
    auto visit = [&](const float* c) {
      const float v[5] = {c[0], c[1], c[2], c[3], 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2]};
      for (int k = 0; k < 5; ++k) {
        r.lo[k] = std::min(r.lo[k], v[k]);
        r.hi[k] = std::max(r.hi[k], v[k]);
      }
    };
    if (t.type == TextureDesc::Type::Image) {
      for (size_t i = 0; i + 3 < t.texels.size(); i += 4) visit(&t.texels[i]);
    } else {
      const float c1[4] = {t.color1.x, t.color1.y, t.color1.z, 1.0f}, c2[4] = {t.color2.x, t.color2.y, t.color2.z, 1.0f};
      visit(c1);
      visit(c2);
    }
    for (int k = 0; k < 5; ++k)
      if (r.lo[k] > r.hi[k]) r.lo[k] = r.hi[k] = 0.0f;
    found = cache_.emplace(texture, r).first;
  }
  const uint32_t k = channel < 4 ? channel : 4;
  *lo = found->second.lo[k];
  *hi = found->second.hi[k];
}

void pack_material_textures(const Scene& scene, const MaterialDesc& d, TextureRanges& ranges, MaterialGpu* g,
                            std::vector<TexBindingGpu>* bindings) {
  g->tex_first = uint32_t(bindings->size());
  g->tex_count = 0;
  g->cutout_binding = AW_NONE;
  g->bump_binding = AW_NONE;
  g->bump_scale = d.bump.scale;
  g->no_bump_lobes = (d.diffuse.disable_bump ? (1u << AW_LID_DIFFUSE) | (1u << AW_LID_TRANSLUCENCY) : 0u) |
                     (d.reflection.disable_bump ? 1u << AW_LID_REFLECTION : 0u) |
                     (d.reflection2.disable_bump ? 1u << AW_LID_REFLECTION2 : 0u) |
                     (d.refraction.disable_bump ? 1u << AW_LID_REFRACTION : 0u);
  for (const auto& [key, ref] : d.textures) {
    TexBindingGpu b;
    std::memset(&b, 0, sizeof(b));
    b.texture = ref.texture;
    b.multiplier = ref.multiplier;
    b.offset = ref.offset;
    b.uv_set = uint32_t(ref.uv_set);
    if (key == "bump.input") {
      b.channel = ref.channel < 0 ? AW_TEXCH_LUMINANCE : uint32_t(ref.channel);
      b.count = 1;
      b.lo = -std::numeric_limits<float>::max();
      b.hi = std::numeric_limits<float>::max();
      g->bump_binding = uint32_t(bindings->size());
      bindings->push_back(b);
      continue;
    }
    const TextureInput* in = find_texture_input(key);
    if (!in) continue;  // the loader refused it already
    b.word = in->word;
    b.count = in->count;
    b.lo = in->lo;
    b.hi = in->hi;
    b.channel = ref.channel >= 0 ? uint32_t(ref.channel) : (in->count == 3 ? AW_TEXCH_RGB : AW_TEXCH_LUMINANCE);
    if (key == "incandescent.color") {  // packed as colour x scale
      b.multiplier *= d.incandescent.scale;
      b.offset *= d.incandescent.scale;
    }
    if (key == "cutout_opacity") g->cutout_binding = uint32_t(bindings->size());
    // The constant: the value of largest magnitude the texture can give (see the header).
    float* w = reinterpret_cast<float*>(g);
    for (uint32_t k = 0; k < in->count; ++k) {
      const uint32_t ch = b.channel == AW_TEXCH_RGB ? k : b.channel;
      float lo = 0.0f, hi = 0.0f;
      ranges.get(ref.texture, ch, &lo, &hi);
      const float a = std::clamp(b.offset + b.multiplier * lo, b.lo, b.hi);
      const float z = std::clamp(b.offset + b.multiplier * hi, b.lo, b.hi);
      w[in->word + k] = std::fabs(z) >= std::fabs(a) ? z : a;
    }
    bindings->push_back(b);
    ++g->tex_count;
  }
  // The cutout binding must be among the material's word bindings (it is: one entry per key),
  // and the bump binding after them, outside [tex_first, tex_first + tex_count): move it last.
  if (g->bump_binding != AW_NONE && g->bump_binding != g->tex_first + g->tex_count) {
    const TexBindingGpu bump = (*bindings)[g->bump_binding];
    bindings->erase(bindings->begin() + g->bump_binding);
    if (g->cutout_binding != AW_NONE && g->cutout_binding > g->bump_binding) --g->cutout_binding;
    bindings->push_back(bump);
    g->bump_binding = uint32_t(bindings->size() - 1);
  }
}

}  // namespace aw
