// Random numbers as a pure function of (sampler, seed, pixel, sample, bounce, dimension).
// Nothing depends on which queue slot or thread runs a path, so the wavefront and the host
// scalar path consume identical numbers and renders are deterministic by construction.
//
// Two samplers (render.sampler):
// - AW_SAMPLER_SOBOL (the default): Owen-scrambled Sobol' points with hash-based scrambling
//   and a per-set shuffle of the sample index (Burley 2020, "Practical Hash-based Owen
//   Scrambling", JCGT 9(4), Sec. 4 and 5). Every (pixel, bounce, dimension) is its own
//   "padded" set: a 1-D request takes Sobol' dimension 0, a 2-D request dimensions 0 and 1
//   (a (0,2)-sequence), each with its own Owen scramble, and the sample index is shuffled by
//   a nested uniform scramble seeded by the set. The shuffle maps the first 2^k indices onto
//   an aligned block of 2^k indices (a nested scramble of the index bits keeps the high bits
//   of indices < 2^k constant), and an aligned block of a (0,2)-sequence is a (0,k,2)-net, so
//   the first 2^k samples of every pixel and set are stratified one per elementary interval
//   (tests/integrator/test_sampler.cpp); the different shuffles decorrelate the sets from each
//   other and the pixels from each other. Any sample count works; powers of two stratify
//   best. Lobe-splitting children use sample indices >= spp (integrator/split.h), the rest of
//   the same sequence, and disjoint index ranges stay disjoint, so parts of a render over
//   sample ranges draw the numbers one render would.
// - AW_SAMPLER_ZSOBOL: the same Owen-scrambled (0,2)-sequence, but one sequence for the whole
//   image per set, its index ordered along a randomised Morton curve over the pixels (Ahmed &
//   Wonka 2020, "Screen-space blue-noise diffusion of Monte Carlo sampling error via
//   hierarchical ordering of pixels", SIGGRAPH Asia, Sec. 4; pbrt-v4's ZSobolSampler is the
//   same idea): neighbouring pixels take neighbouring blocks of one net, so their errors are
//   anti-correlated (blue noise) while each pixel's block stays a net (stratified as with
//   `sobol`). See rng_zsobol_index.
// - AW_SAMPLER_INDEPENDENT: a 4-D hash per (pixel, sample, bounce, dimension) (pcg4d below):
//   white noise, the renderer's sampler before the Sobol' one, kept for comparison.
//
// A sampler is passed as a `Sampler` value (kind, seed, and what zsobol needs of the image:
// its width and index layout), built from the render parameters by rp_sampler()
// (integrator/path_state.h) or by sampler_make() in tests.
#ifndef AW_COMMON_RNG_H
#define AW_COMMON_RNG_H

#include "common/compat.h"
#include "common/features.h"
#include "common/lanes.h"

// Dimensions used at each bounce. Every consumer owns a fixed slot; a 2D sample uses two
// outputs of one hash, so dimension numbers name hashes, not floats.
#define AW_DIM_CAMERA 0        // pixel jitter (2D), bounce 0 only
#define AW_DIM_LOBE 1          // lobe selection (1D)
#define AW_DIM_LIGHT_PICK 2    // which light (1D)
#define AW_DIM_LIGHT 3         // point on the light (2D)
#define AW_DIM_BSDF 4          // direction from the lobe (2D)
#define AW_DIM_RR 5            // Russian roulette (1D)
#define AW_DIM_AO 6            // ambient-occlusion ray directions (2D; sample index s * n + k for n rays)

// render.sampler
#define AW_SAMPLER_SOBOL 0u
#define AW_SAMPLER_INDEPENDENT 1u
#define AW_SAMPLER_ZSOBOL 2u

typedef struct {
  uint kind;      // AW_SAMPLER_*
  uint seed;      // render.seed
  uint width;     // image width (zsobol: pixel index -> x, y)
  uint log2_spp;  // zsobol: ceil(log2(spp)), the bits of a pixel's block of the sequence
  uint bits;      // zsobol: 2 ceil(log2(max(width, height))) + log2_spp, the index's bits
} Sampler;

AW_FN Sampler sampler_make(uint kind, uint seed, uint width, uint log2_spp, uint bits) {
  Sampler s;
  s.kind = kind;
  s.seed = seed;
  s.width = width;
  s.log2_spp = log2_spp;
  s.bits = bits;
  return s;
}

// Smallest r with 2^r >= n (n >= 1).
AW_FN uint ceil_log2_u32(uint n) {
  uint r = 0u;
  while (r < 32u && ((ulong)1 << r) < (ulong)n) ++r;
  return r;
}

// A sampler with zsobol's index layout for a width x height image at spp samples per pixel
// (rng_zsobol_index): a pixel's block of 2^ceil(log2 spp) indices below the Morton code of a
// 2^r x 2^r square holding the image. At most 2 * 16 + 31 = 63 bits (width, height <= 65536,
// spp < 2^31). The host packs RenderParams from it.
AW_FN Sampler sampler_for_image(uint kind, uint seed, uint width, uint height, uint spp) {
  uint l = ceil_log2_u32(spp);
  return sampler_make(kind, seed, width, l, 2u * ceil_log2_u32(width > height ? width : height) + l);
}

// pcg4d: Jarzynski & Olano 2020, "Hash Functions for GPU Rendering", JCGT 9(3), Sec. 3.
// Chosen over a 1D hash chain because it mixes four independent inputs in one pass and
// passed their TestU01 BigCrush battery as a 4D->4D hash.
AW_FN void pcg4d(luint* v) {
  v[0] = v[0] * 1664525u + 1013904223u;
  v[1] = v[1] * 1664525u + 1013904223u;
  v[2] = v[2] * 1664525u + 1013904223u;
  v[3] = v[3] * 1664525u + 1013904223u;
  v[0] += v[1] * v[3];
  v[1] += v[2] * v[0];
  v[2] += v[0] * v[1];
  v[3] += v[1] * v[2];
  v[0] ^= v[0] >> 16u;
  v[1] ^= v[1] >> 16u;
  v[2] ^= v[2] >> 16u;
  v[3] ^= v[3] >> 16u;
  v[0] += v[1] * v[3];
  v[1] += v[2] * v[0];
  v[2] += v[0] * v[1];
  v[3] += v[1] * v[2];
}

// The top 24 bits as a float in [0, 1): exact on both sides (integer ops, one exact scale).
AW_FN lfloat rng_to_unit(luint x) { return L_TO_FLOAT(x >> 8) * (1.0f / 16777216.0f); }

AW_FN lfloat2 rng_independent_2d(uint seed, luint pixel, luint sample, luint bounce, uint dim) {
  luint v[4];
  v[0] = pixel;
  v[1] = sample;
  v[2] = (bounce << 8) | dim;
  v[3] = seed;
  pcg4d(v);
  return make_lfloat2(rng_to_unit(v[0]), rng_to_unit(v[1]));
}

/* ------------------------------ Owen-scrambled Sobol' ------------------------------------ */

AW_FN luint reverse_bits32(luint x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
  x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
  return (x >> 16) | (x << 16);
}

// Sobol' dimension 0 (van der Corput: the index's bits mirrored) and dimension 1 (primitive
// polynomial x + 1, direction numbers v_0 = 1/2, v_k = v_{k-1} xor v_{k-1} / 2: Joe & Kuo
// 2008, "Constructing Sobol sequences with better two-dimensional projections", Sec. 2), as
// 32-bit fractions. Dimension 1's generator matrix is Pascal's triangle mod 2: digit r of
// the point (r = 0 the first, 1/2) is the XOR of the index bits c with binom(c, r) odd, that
// is with r a bit-subset of c (Lucas' theorem). That superset XOR over the 32 bit positions
// takes five shift-and-mask steps instead of a loop over the index bits (sobol_superset_xor,
// digit r at bit r; the fraction is its mirror image).
AW_FN luint sobol_dim0(luint i) { return reverse_bits32(i); }
AW_FN luint sobol_superset_xor(luint z) {
  z ^= (z >> 1) & 0x55555555u;
  z ^= (z >> 2) & 0x33333333u;
  z ^= (z >> 4) & 0x0f0f0f0fu;
  z ^= (z >> 8) & 0x00ff00ffu;
  z ^= (z >> 16) & 0x0000ffffu;
  return z;
}
AW_FN luint sobol_dim1(luint i) { return reverse_bits32(sobol_superset_xor(i)); }

// Laine & Karras' permutation as improved by Burley 2020 (Sec. 3): every output bit is the
// input bit XOR a function of the lower bits only (additions and multiplications by even
// constants carry upwards), which is what a nested uniform (Owen) scramble does when applied
// to the bit-reversed number.
AW_FN luint laine_karras_permutation(luint x, luint seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}

// Owen scrambling in base 2 of a 32-bit fraction (first digit = the top bit); applied to a
// sample index it is the shuffle (Burley 2020, Sec. 4).
AW_FN luint nested_uniform_scramble(luint x, luint seed) {
  return reverse_bits32(laine_karras_permutation(reverse_bits32(x), seed));
}

// The seeds of one padded set: the index shuffle and one scramble per coordinate.
AW_FN void sobol_set_seeds(uint seed, luint pixel, luint bounce, uint dim, luint* s) {
  s[0] = pixel;
  s[1] = (bounce << 8) | dim;
  s[2] = seed;
  s[3] = 0x50b01u;  // a tag: these hashes never equal the independent sampler's
  pcg4d(s);
}

// The point of sample `sample` in one padded set. Written out: the shuffle is
// nested_uniform_scramble(sample), and scrambling a Sobol' coordinate mirrors it, permutes and
// mirrors back; since dimension 0 is the mirrored index and dimension 1 the mirrored superset
// XOR, the mirrors in between cancel (the same numbers as scrambling sobol_dim0/1(index)).
AW_FN lfloat2 rng_sobol_2d(uint seed, luint pixel, luint sample, luint bounce, uint dim) {
  luint s[4];
  sobol_set_seeds(seed, pixel, bounce, dim, s);
  luint i = nested_uniform_scramble(sample, s[0]);
  luint x = reverse_bits32(laine_karras_permutation(i, s[1]));
  luint y = reverse_bits32(laine_karras_permutation(sobol_superset_xor(i), s[2]));
  return make_lfloat2(rng_to_unit(x), rng_to_unit(y));
}

AW_FN lfloat rng_sobol_1d(uint seed, luint pixel, luint sample, luint bounce, uint dim) {
  luint s[4];
  sobol_set_seeds(seed, pixel, bounce, dim, s);
  luint i = nested_uniform_scramble(sample, s[0]);
  return rng_to_unit(reverse_bits32(laine_karras_permutation(i, s[1])));
}

/* ------------------------------ Z-ordered (blue-noise) Sobol' ---------------------------- */

// Not written on lanes yet beyond pcg_hash (its index is 64-bit and its digit permutation a
// table lookup): one path per call only. A lane program (AW_LANES > 1) has Sobol' and the independent
// sampler; nothing builds one for a zsobol render (common/lanes.h).
// pcg: Jarzynski & Olano 2020 (JCGT 9(3), Sec. 3): their recommended 1-D 32-bit hash.
// Written once, instantiated on lanes (pcg_hash) and for one value (pcg_hash1: code that is
// one path per call, e.g. texture noise, in a program of any width; the same function at W = 1).
#define AW_PCG_HASH(T, name)                                       \
  AW_FN T name(T v) {                                              \
    T state = v * 747796405u + 2891336453u;                        \
    T word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u; \
    return (word >> 22u) ^ word;                                   \
  }
AW_PCG_HASH(luint, pcg_hash)
AW_PCG_HASH(uint, pcg_hash1)
#undef AW_PCG_HASH

#if AW_LANES == 1

// Digit d (0..3) through the p-th (0..23) of the 24 permutations of {0, 1, 2, 3}, in
// lexicographic order: permutation p is byte p of the table, entry d at bits 2d..2d+1.
AW_FN uint base4_permute(uint p, uint d) {
  const uint table[6] = {0x78d8b4e4u, 0xb1e16c9cu, 0x2d8d39c9u, 0x36c672d2u, 0x63931e4eu, 0x1b4b2787u};
  return (table[p >> 2] >> (8u * (p & 3u) + 2u * d)) & 3u;
}

// x in the even bits, y in the odd bits (16 bits each: width, height <= 65536).
AW_FN uint morton2(uint x, uint y) {
  ulong v = (ulong)x | ((ulong)y << 32);
  v = (v | (v << 8)) & 0x00ff00ff00ff00ffUL;
  v = (v | (v << 4)) & 0x0f0f0f0f0f0f0f0fUL;
  v = (v | (v << 2)) & 0x3333333333333333UL;
  v = (v | (v << 1)) & 0x5555555555555555UL;
  return (uint)v | ((uint)(v >> 32) << 1);
}

// The index into the set's sequence of sample `sample` of pixel (x, y) (Ahmed & Wonka 2020,
// Sec. 4). The Morton code of the pixel followed by the sample's log2_spp bits, read as
// base-4 digits from the top (aligned at the bottom; an odd count leaves bit 0 a base-2
// digit), has every digit replaced by its image under a random permutation of {0..3} chosen
// by a hash of the digits above it and of the set. That is an Owen scramble in base 4 of the
// quadtree of pixels: the four quadrants of every node go, in a random order, to the four
// quarters of the node's range of indices. So:
// - a pixel's samples are one aligned block of 2^log2_spp indices (its digits are above the
//   sample digits, which are only permuted among themselves), and an aligned block of a
//   (0,2)-sequence is a (0, log2_spp, 2)-net: each pixel stratified as with `sobol`;
// - the pixels of every aligned 2^j x 2^j square share one aligned block of 4^j blocks: a
//   net over the square, so neighbours' errors cancel in a low-pass view (blue noise);
// - the order differs per set (the hash takes it), which decorrelates the sets.
// The hash that picks a digit's permutation: of the digits above it and of the set.
AW_FN uint zsobol_digit_hash(ulong higher, uint set_seed) {
  return pcg_hash((uint)higher ^ pcg_hash((uint)(higher >> 32) ^ set_seed));
}

AW_FN ulong rng_zsobol_index(Sampler s, uint pixel, uint sample, uint set_seed) {
  uint x = pixel % s.width, y = pixel / s.width;
  ulong m = ((ulong)morton2(x, y) << s.log2_spp) | (ulong)sample;
  ulong out = 0;
  int odd = (int)(s.bits & 1u);
  for (int shift = (int)s.bits - 2; shift >= odd; shift -= 2) {
    uint h = zsobol_digit_hash(m >> (shift + 2), set_seed);
    uint d = (uint)(m >> shift) & 3u;
    out |= (ulong)base4_permute(h % 24u, d) << shift;
  }
  if (odd) out |= (m & 1UL) ^ (ulong)(zsobol_digit_hash(m >> 1, set_seed) >> 31);
  return out;
}

// The set's seeds: [0] orders the index, [1] and [2] scramble the two coordinates. Unlike
// sobol_set_seeds, the pixel is not among them: one scrambled sequence serves the image.
AW_FN void zsobol_set_seeds(uint seed, uint bounce, uint dim, uint* s) {
  s[0] = 0x25081u;  // a tag: these hashes never equal the other samplers'
  s[1] = (bounce << 8) | dim;
  s[2] = seed;
  s[3] = 0x2b1u;
  pcg4d(s);
}

// The point: Sobol' dimensions 0 and 1 of the index's low 32 bits, Owen-scrambled as in
// rng_sobol_2d. Indices of more than 32 bits (images over 65536 pixels at 65536 spp) fold
// their high bits into the scrambles, so those points stay distinct. Sample indices past a
// pixel's block (lobe-splitting children, >= spp) take the `sobol` sampler's numbers, which
// are stratified per pixel the same way (their blocks are aligned too).
// The point's index (low 32 bits) and its two coordinates' scramble seeds (k[1], k[2]).
AW_FN uint zsobol_point_setup(Sampler s, uint pixel, uint sample, uint bounce, uint dim, uint* k) {
  zsobol_set_seeds(s.seed, bounce, dim, k);
  ulong i = rng_zsobol_index(s, pixel, sample, k[0]);
  uint hi = (uint)(i >> 32);
  k[1] ^= pcg_hash(hi);
  k[2] ^= pcg_hash(hi ^ 0x9e3779b9u);
  return (uint)i;
}

AW_FN float2 rng_zsobol_2d(Sampler s, uint pixel, uint sample, uint bounce, uint dim) {
  if ((sample >> s.log2_spp) != 0u) return rng_sobol_2d(s.seed, pixel, sample, bounce, dim);
  uint k[4];
  uint lo = zsobol_point_setup(s, pixel, sample, bounce, dim, k);
  uint xs = reverse_bits32(laine_karras_permutation(lo, k[1]));
  uint ys = reverse_bits32(laine_karras_permutation(sobol_superset_xor(lo), k[2]));
  return make_float2(rng_to_unit(xs), rng_to_unit(ys));
}

// The first coordinate alone (rng_zsobol_2d(...).x, without computing the second).
AW_FN float rng_zsobol_1d(Sampler s, uint pixel, uint sample, uint bounce, uint dim) {
  if ((sample >> s.log2_spp) != 0u) return rng_sobol_1d(s.seed, pixel, sample, bounce, dim);
  uint k[4];
  uint lo = zsobol_point_setup(s, pixel, sample, bounce, dim, k);
  return rng_to_unit(reverse_bits32(laine_karras_permutation(lo, k[1])));
}

#endif  // AW_LANES == 1

/* ------------------------------------ the interface -------------------------------------- */

// A build has only the samplers its scene uses (common/features.h: Sobol' always; the host
// refuses a render whose sampler the build lacks, host/render/wavefront.cpp). Written on lanes
// (common/lanes.h): one path per call at AW_LANES = 1, W paths (each its own pixel, sample and
// bounce) at AW_LANES = W; the sampler, seed and dimension are the same for all of them.
AW_FN lfloat2 rng_2d(Sampler s, luint pixel, luint sample, luint bounce, uint dim) {
  if (AW_FEAT_SAMPLER_INDEPENDENT && s.kind == AW_SAMPLER_INDEPENDENT)
    return rng_independent_2d(s.seed, pixel, sample, bounce, dim);
#if AW_LANES == 1
  if (AW_FEAT_SAMPLER_ZSOBOL && s.kind == AW_SAMPLER_ZSOBOL) return rng_zsobol_2d(s, pixel, sample, bounce, dim);
#endif
  return rng_sobol_2d(s.seed, pixel, sample, bounce, dim);
}

// The first coordinate of the 2-D set (the same number rng_2d(...).x gives).
AW_FN lfloat rng_1d(Sampler s, luint pixel, luint sample, luint bounce, uint dim) {
  if (AW_FEAT_SAMPLER_INDEPENDENT && s.kind == AW_SAMPLER_INDEPENDENT)
    return rng_independent_2d(s.seed, pixel, sample, bounce, dim).x;
#if AW_LANES == 1
  if (AW_FEAT_SAMPLER_ZSOBOL && s.kind == AW_SAMPLER_ZSOBOL) return rng_zsobol_1d(s, pixel, sample, bounce, dim);
#endif
  return rng_sobol_1d(s.seed, pixel, sample, bounce, dim);
}

#endif
