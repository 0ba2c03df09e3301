// Counter-based random numbers: a pure function of (seed, pixel, sample, bounce, dimension).
// Nothing depends on which queue slot or thread runs a path, so the wavefront and the host
// scalar path consume identical numbers and renders are deterministic by construction.
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

AW_FN float2 rng_2d(uint seed, uint pixel, uint sample, uint bounce, uint dim) {
  uint v[4];
  v[0] = pixel;
  v[1] = sample;
  v[2] = (bounce << 8) | dim;
  v[3] = seed;
  pcg4d(v);
  return make_float2(rng_to_unit(v[0]), rng_to_unit(v[1]));
}

AW_FN float rng_1d(uint seed, uint pixel, uint sample, uint bounce, uint dim) {
  return rng_2d(seed, pixel, sample, bounce, dim).x;
}

#endif
