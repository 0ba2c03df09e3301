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
// - AW_SAMPLER_INDEPENDENT: a 4-D hash per (pixel, sample, bounce, dimension) (pcg4d below):
//   white noise, the renderer's sampler before the Sobol' one, kept for comparison.
#ifndef AW_COMMON_RNG_H
#define AW_COMMON_RNG_H

#include "common/compat.h"

// Dimensions used at each bounce. Every consumer owns a fixed slot; a 2D sample uses two
// outputs of one hash, so dimension numbers name hashes, not floats.
#define AW_DIM_CAMERA 0        // pixel jitter (2D), bounce 0 only
#define AW_DIM_LOBE 1          // lobe selection (1D)
#define AW_DIM_LIGHT_PICK 2    // which light (1D)
#define AW_DIM_LIGHT 3         // point on the light (2D)
#define AW_DIM_BSDF 4          // direction from the lobe (2D)
#define AW_DIM_RR 5            // Russian roulette (1D)

// render.sampler
#define AW_SAMPLER_SOBOL 0u
#define AW_SAMPLER_INDEPENDENT 1u

// pcg4d: Jarzynski & Olano 2020, "Hash Functions for GPU Rendering", JCGT 9(3), Sec. 3.
// Chosen over a 1D hash chain because it mixes four independent inputs in one pass and
// passed their TestU01 BigCrush battery as a 4D->4D hash.
AW_FN void pcg4d(uint* v) {
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
AW_FN float rng_to_unit(uint x) { return (float)(x >> 8) * (1.0f / 16777216.0f); }

AW_FN float2 rng_independent_2d(uint seed, uint pixel, uint sample, uint bounce, uint dim) {
  uint v[4];
  v[0] = pixel;
  v[1] = sample;
  v[2] = (bounce << 8) | dim;
  v[3] = seed;
  pcg4d(v);
  return make_float2(rng_to_unit(v[0]), rng_to_unit(v[1]));
}

/* ------------------------------ Owen-scrambled Sobol' ------------------------------------ */

AW_FN uint reverse_bits32(uint x) {
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
AW_FN uint sobol_dim0(uint i) { return reverse_bits32(i); }
AW_FN uint sobol_superset_xor(uint z) {
  z ^= (z >> 1) & 0x55555555u;
  z ^= (z >> 2) & 0x33333333u;
  z ^= (z >> 4) & 0x0f0f0f0fu;
  z ^= (z >> 8) & 0x00ff00ffu;
  z ^= (z >> 16) & 0x0000ffffu;
  return z;
}
AW_FN uint sobol_dim1(uint i) { return reverse_bits32(sobol_superset_xor(i)); }

// Laine & Karras' permutation as improved by Burley 2020 (Sec. 3): every output bit is the
// input bit XOR a function of the lower bits only (additions and multiplications by even
// constants carry upwards), which is what a nested uniform (Owen) scramble does when applied
// to the bit-reversed number.
AW_FN uint laine_karras_permutation(uint x, uint seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}

// Owen scrambling in base 2 of a 32-bit fraction (first digit = the top bit); applied to a
// sample index it is the shuffle (Burley 2020, Sec. 4).
AW_FN uint nested_uniform_scramble(uint x, uint seed) {
  return reverse_bits32(laine_karras_permutation(reverse_bits32(x), seed));
}

// The seeds of one padded set: the index shuffle and one scramble per coordinate.
AW_FN void sobol_set_seeds(uint seed, uint pixel, uint bounce, uint dim, uint* s) {
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
AW_FN float2 rng_sobol_2d(uint seed, uint pixel, uint sample, uint bounce, uint dim) {
  uint s[4];
  sobol_set_seeds(seed, pixel, bounce, dim, s);
  uint i = nested_uniform_scramble(sample, s[0]);
  uint x = reverse_bits32(laine_karras_permutation(i, s[1]));
  uint y = reverse_bits32(laine_karras_permutation(sobol_superset_xor(i), s[2]));
  return make_float2(rng_to_unit(x), rng_to_unit(y));
}

AW_FN float rng_sobol_1d(uint seed, uint pixel, uint sample, uint bounce, uint dim) {
  uint s[4];
  sobol_set_seeds(seed, pixel, bounce, dim, s);
  uint i = nested_uniform_scramble(sample, s[0]);
  return rng_to_unit(reverse_bits32(laine_karras_permutation(i, s[1])));
}

/* ------------------------------------ the interface -------------------------------------- */

AW_FN float2 rng_2d(uint sampler, uint seed, uint pixel, uint sample, uint bounce, uint dim) {
  if (sampler == AW_SAMPLER_INDEPENDENT) return rng_independent_2d(seed, pixel, sample, bounce, dim);
  return rng_sobol_2d(seed, pixel, sample, bounce, dim);
}

AW_FN float rng_1d(uint sampler, uint seed, uint pixel, uint sample, uint bounce, uint dim) {
  if (sampler == AW_SAMPLER_INDEPENDENT) return rng_independent_2d(seed, pixel, sample, bounce, dim).x;
  return rng_sobol_1d(seed, pixel, sample, bounce, dim);
}

#endif
