// Texture sampling, the same code on the device and in the host scalar path: images with wrap
// modes, bilinear filtering and mip levels chosen by the path's footprint (trilinear), and the
// procedurals `checker` (box-filtered in closed form) and `noise` (fBm of gradient noise with
// the octaves finer than the footprint faded out). docs/scene-format.md#textures has the
// user's view; kernels/types/texture.h the layout.
//
// Footprint: `fuv`, the width of the path's ray cone where it hit the surface, expressed in the
// surface's UV units (classify_hit.h computes it; docs/architecture.md#texture-footprint).
// A texture whose UV transform scales UVs by s sees s * fuv; an image of w x h texels then
// reads level log2(s * fuv * sqrt(w h)) (Akenine-Möller et al. 2019, "Texture Level of Detail
// Strategies for Real-Time Ray Tracing", Ray Tracing Gems ch. 20, Sec. 20.3.4, eq. 20.2: the
// level from the texel-to-world area ratio and the cone's width).
#ifndef AW_TEXTURE_TEXTURE_H
#define AW_TEXTURE_TEXTURE_H

#include "common/compat.h"
#include "common/rng.h"
#include "types/texture.h"

// IEEE 754 binary16 to float, exactly (every half is a float), in integer arithmetic so that
// host and device decode the same bits the same way.
AW_FN float half_bits_to_float(uint h) {
  uint sign = (h & 0x8000u) << 16;
  uint e = (h >> 10) & 0x1fu;
  uint m = h & 0x3ffu;
  if (e == 0x1fu) return as_float(sign | 0x7f800000u | (m << 13));  // inf, NaN
  if (e == 0u) {
    // Subnormal half: m * 2^-24, exact in float.
    float f = (float)m * 5.9604644775390625e-8f;
    return sign ? -f : f;
  }
  return as_float(sign | ((e + 112u) << 23) | (m << 13));
}

// One texel of level `level` at integer coordinates (already wrapped), expanded to RGBA:
// grey (g,g,g,1), grey+alpha (g,g,g,a), RGB (r,g,b,1).
AW_FN float4 tex_fetch(const AW_GLOBAL TextureGpu* t, const AW_GLOBAL uchar* texels, uint level, uint x, uint y) {
  uint w = max(1u, t->width >> level);
  uint nc = t->channels;
  uint i = (y * w + x) * nc;
  const AW_GLOBAL uchar* base = texels + t->level_offset[level];
  float c[4] = {0.0f, 0.0f, 0.0f, 1.0f};
  for (uint k = 0u; k < nc && k < 4u; ++k) {
    if (t->format == AW_TEXFMT_U8) {
      c[k] = (float)base[i + k] / 255.0f;
    } else if (t->format == AW_TEXFMT_F16) {
      const AW_GLOBAL ushort* p = (const AW_GLOBAL ushort*)base;
      c[k] = half_bits_to_float((uint)p[i + k]);
    } else {
      const AW_GLOBAL float* p = (const AW_GLOBAL float*)base;
      c[k] = p[i + k];
    }
  }
  if (nc == 1u) return make_float4(c[0], c[0], c[0], 1.0f);
  if (nc == 2u) return make_float4(c[0], c[0], c[0], c[1]);
  return make_float4(c[0], c[1], c[2], c[3]);
}

// Texel index i of a row or column of n texels under the wrap mode; -1 for "black" outside.
AW_FN int tex_wrap_index(int i, int n, uint wrap) {
  if (wrap == AW_WRAP_REPEAT) {
    int r = i % n;
    return r < 0 ? r + n : r;
  }
  if (wrap == AW_WRAP_MIRROR) {
    int r = i % (2 * n);
    if (r < 0) r += 2 * n;
    return r < n ? r : 2 * n - 1 - r;
  }
  if (wrap == AW_WRAP_BLACK && (i < 0 || i >= n)) return -1;
  return i < 0 ? 0 : (i >= n ? n - 1 : i);
}

// A texture coordinate brought into a range where the texel index cannot overflow an int,
// without changing what the wrap mode reads: repeat by whole periods, mirror by periods of 2,
// clamp and black to just outside [0, 1]. NaN reads as 0.
AW_FN float tex_reduce_coord(float x, uint wrap) {
  if (!(x == x)) return 0.0f;
  if (wrap == AW_WRAP_REPEAT) return x - floor(x);
  if (wrap == AW_WRAP_MIRROR) return x - 2.0f * floor(0.5f * x);
  return clamp(x, -1.0f, 2.0f);
}

// Bilinear filtering of one level. Texel (i, j) covers [i, i+1]/w x [j, j+1]/h with row 0 at
// the top (v = 1), so the centres are at (i + 0.5)/w, 1 - (j + 0.5)/h.
AW_FN float4 tex_bilinear(const AW_GLOBAL TextureGpu* t, const AW_GLOBAL uchar* texels, uint level, float u, float v) {
  int w = (int)max(1u, t->width >> level), h = (int)max(1u, t->height >> level);
  float x = tex_reduce_coord(u, t->wrap) * (float)w - 0.5f;
  float y = (1.0f - tex_reduce_coord(v, t->wrap)) * (float)h - 0.5f;
  float fx0 = floor(x), fy0 = floor(y);
  float ax = x - fx0, ay = y - fy0;
  int x0 = (int)fx0, y0 = (int)fy0;
  int xs[2] = {tex_wrap_index(x0, w, t->wrap), tex_wrap_index(x0 + 1, w, t->wrap)};
  int ys[2] = {tex_wrap_index(y0, h, t->wrap), tex_wrap_index(y0 + 1, h, t->wrap)};
  float4 acc = make_float4(0.0f, 0.0f, 0.0f, 0.0f);
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 2; ++i) {
      float wt = (i ? ax : 1.0f - ax) * (j ? ay : 1.0f - ay);
      if (xs[i] < 0 || ys[j] < 0 || wt == 0.0f) continue;
      acc = acc + tex_fetch(t, texels, level, (uint)xs[i], (uint)ys[j]) * wt;
    }
  }
  return acc;
}

// The mip level for footprint f (in the texture's own, transformed, UV units): log2 of the
// footprint in texels, clamped to the pyramid.
AW_FN float tex_image_level(const AW_GLOBAL TextureGpu* t, float f) {
  float texels_across = f * sqrt((float)t->width * (float)t->height);
  if (!(texels_across > 1.0f)) return 0.0f;
  return fmin(log2(texels_across), (float)(t->levels - 1u));
}

// Mean over [x - f/2, x + f/2] of the square wave that is +1 on even cells [2k, 2k+1) and -1
// on odd ones: the difference of its integral, the triangle wave S(x) = 1 - |x mod 2 - 1|,
// over the box's width (the box-filtered checker of Apodaca & Gritz 2000, "Advanced
// RenderMan", Sec. 11.4.2, in its closed form).
AW_FN float checker_wave_mean(float x, float f) {
  if (!(f > 1e-6f)) return x - 2.0f * floor(0.5f * x) < 1.0f ? 1.0f : -1.0f;
  float a = x - 0.5f * f, b = x + 0.5f * f;
  float ma = a - 2.0f * floor(0.5f * a), mb = b - 2.0f * floor(0.5f * b);
  float sa = 1.0f - fabs(ma - 1.0f), sb = 1.0f - fabs(mb - 1.0f);
  // Whole periods inside the box contribute nothing to the integral (the wave's mean is 0).
  return clamp((sb - sa) / f, -1.0f, 1.0f);
}

// Perlin's gradient noise in 2-D (Perlin 2002, "Improving Noise", SIGGRAPH: the quintic fade
// 6t^5 - 15t^4 + 10t^3 and gradients chosen by hashing the lattice point), with eight
// gradient directions and the lattice hashed by pcg_hash1 (common/rng.h) instead of a
// permutation table, so no table has to be shared between host and device. About [-0.71, 0.71].
AW_FN float noise_grad(uint ix, uint iy, float dx, float dy) {
  uint hsh = pcg_hash1(ix * 0x8da6b343u ^ pcg_hash1(iy)) & 7u;
  const float d = 0.70710678f;
  float gx = hsh < 2u ? (hsh == 0u ? 1.0f : -1.0f) : (hsh < 4u ? 0.0f : ((hsh & 1u) ? -d : d));
  float gy = hsh < 2u ? 0.0f : (hsh < 4u ? (hsh == 2u ? 1.0f : -1.0f) : ((hsh & 2u) ? -d : d));
  return gx * dx + gy * dy;
}
AW_FN float noise_fade(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }
AW_FN float gradient_noise(float x, float y) {
  // Beyond 2^24 a float has no fraction left to interpolate; clamping keeps the int cast defined.
  x = clamp(x, -16777216.0f, 16777216.0f);
  y = clamp(y, -16777216.0f, 16777216.0f);
  float fx = floor(x), fy = floor(y);
  float dx = x - fx, dy = y - fy;
  uint ix = (uint)(int)fx, iy = (uint)(int)fy;
  float n00 = noise_grad(ix, iy, dx, dy), n10 = noise_grad(ix + 1u, iy, dx - 1.0f, dy);
  float n01 = noise_grad(ix, iy + 1u, dx, dy - 1.0f), n11 = noise_grad(ix + 1u, iy + 1u, dx - 1.0f, dy - 1.0f);
  float sx = noise_fade(dx), sy = noise_fade(dy);
  return mix(mix(n00, n10, sx), mix(n01, n11, sx), sy);
}

// fBm: octave k has frequency 2^k and amplitude 2^-k. An octave whose cells the footprint f
// covers is replaced by its mean, 0 ("clamping": Norton, Rockwood & Skolmoski 1982,
// "Clamping: a method of antialiasing textured surfaces by bandwidth limiting in object
// space"), fading out between f 2^k = 1/4 and 1/2. Returns 0..1 (0.5 = the mean).
AW_FN float noise_fbm(float x, float y, uint octaves, float f) {
  float sum = 0.0f, norm = 0.0f, amp = 1.0f, freq = 1.0f;
  for (uint k = 0u; k < octaves && k < 16u; ++k) {
    float wgt = clamp(2.0f - 4.0f * f * freq, 0.0f, 1.0f);
    if (wgt > 0.0f) sum += wgt * amp * gradient_noise(x * freq + 17.0f * (float)k, y * freq + 31.0f * (float)k);
    norm += amp;
    amp *= 0.5f;
    freq *= 2.0f;
  }
  return norm > 0.0f ? clamp(0.5f + 0.70710678f * sum / norm, 0.0f, 1.0f) : 0.5f;
}

// The texture's value (linear RGBA) at surface UV (u, v) for a footprint fuv (0 = a point).
AW_FN float4 texture_eval(const AW_GLOBAL TextureGpu* t, const AW_GLOBAL uchar* texels, float u, float v, float fuv) {
  float tu = t->xf[0] * u + t->xf[1] * v + t->xf[2];
  float tv = t->xf[3] * u + t->xf[4] * v + t->xf[5];
  float f = fuv * t->uv_scale;
  if (t->type == AW_TEX_CHECKER) {
    float p = checker_wave_mean(tu, f) * checker_wave_mean(tv, f);
    float a = 0.5f + 0.5f * p;  // the share of color1
    return make_float4(a * t->color1[0] + (1.0f - a) * t->color2[0], a * t->color1[1] + (1.0f - a) * t->color2[1],
                       a * t->color1[2] + (1.0f - a) * t->color2[2], 1.0f);
  }
  if (t->type == AW_TEX_NOISE) {
    float a = noise_fbm(tu, tv, t->octaves, f);  // the share of color2
    return make_float4((1.0f - a) * t->color1[0] + a * t->color2[0], (1.0f - a) * t->color1[1] + a * t->color2[1],
                       (1.0f - a) * t->color1[2] + a * t->color2[2], 1.0f);
  }
  float level = tex_image_level(t, f);
  uint l0 = (uint)level;
  float a = level - (float)l0;
  float4 c = tex_bilinear(t, texels, l0, tu, tv);
  if (a > 0.0f && l0 + 1u < t->levels) c = c * (1.0f - a) + tex_bilinear(t, texels, l0 + 1u, tu, tv) * a;
  return c;
}

// The smallest useful finite-difference step in surface UV for texture t (bump mapping): one
// texel of level 0 for images, a 1/1024 of a cell for procedurals.
AW_FN float texture_step(const AW_GLOBAL TextureGpu* t) {
  float s = t->uv_scale > 0.0f ? t->uv_scale : 1.0f;
  if (t->type == AW_TEX_IMAGE) return 1.0f / (s * (float)max(t->width, t->height));
  return 1.0f / (1024.0f * s);
}

// A binding's scalar (channel R/G/B/A or luminance) from an RGBA value, before offset/multiplier.
AW_FN float texture_channel(float4 c, uint channel) {
  if (channel == AW_TEXCH_R) return c.x;
  if (channel == AW_TEXCH_G) return c.y;
  if (channel == AW_TEXCH_B) return c.z;
  if (channel == AW_TEXCH_A) return c.w;
  return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z;
}

#endif
