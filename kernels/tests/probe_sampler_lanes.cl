// The samplers written on lanes (common/rng.h on common/lanes.h), built with 16 paths per
// work-item, against the host's one-path C++ build of the same functions
// (tests/integrator/test_sampler.cpp, SamplerLanes.*).
// in: n pixels, then n sample indices, then n bounces (uint bits in the float buffer), field-
//     major; n a multiple of 16. params: sampler kind, seed, dimension.
// out: rng_2d's x (n values), its y (n), rng_1d (n), field-major.
#define AW_LANES 16
#include "common/rng.h"

__kernel void probe_sampler_lanes(uint n, __global const float* in, __global float* out,
                                  __global const uint* params) {
  uint g = get_global_id(0);
  if ((g + 1u) * AW_LANES > n) return;
  const __global uint* iu = (const __global uint*)in;
  luint pixel = L_LOAD(iu, g), sample = L_LOAD(iu + n, g), bounce = L_LOAD(iu + 2u * n, g);
  Sampler s = sampler_make(params[0], params[1], 0u, 0u, 0u);
  lfloat2 u = rng_2d(s, pixel, sample, bounce, params[2]);
  lfloat v = rng_1d(s, pixel, sample, bounce, params[2]);
  L_STORE(u.x, out, g);
  L_STORE(u.y, out + n, g);
  L_STORE(v, out + 2u * n, g);
}
