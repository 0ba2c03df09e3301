// Scene data shared by host and kernels: materials, lights, render parameters.
// Plain 4-byte fields only; sizes and offsets are asserted on both sides (tests/types).
#ifndef AW_TYPES_SCENE_H
#define AW_TYPES_SCENE_H

#include "types/material.h"

#define AW_LIGHT_POINT 0
#define AW_LIGHT_QUAD 1
#define AW_LIGHT_DISK 2
#define AW_LIGHT_SPHERE 3

#define AW_LIGHT_TWO_SIDED 1u
#define AW_LIGHT_VISIBLE 2u
#define AW_LIGHT_RECTANGLE 4u  // a quad whose edges are orthogonal: sampled by solid angle (lights.h)

// One light. Meaning of p/u/v by type:
//   point:  p = position
//   quad:   p = corner, u = edge_u, v = edge_v, n = unit normal (edge_u × edge_v)
//   disk:   p = center, n = unit normal, u/v = orthonormal tangents, radius
//   sphere: p = center, radius
// radiance: W/m²/sr for area lights; for point lights the radiant intensity (W/sr).
typedef struct {
  uint type;
  uint flags;
  float radius;
  float area;
  float p[3];
  float select_pdf;  // probability that light sampling picks this light
  float u[3];
  float alias_q;     // light selection's alias table (lights.h, light_pick): keep this light with
  float v[3];        // probability alias_q when its bin is drawn, else take light `alias`
  uint alias;
  float n[3];
  float pad1;
  float radiance[3];
  float pad2;
} LightGpu;

// Per-launch parameters, passed by value. Pixel (0,0) is the top-left corner.
typedef struct {
  float cam_origin[3];
  float tan_half_fov;
  float cam_forward[3];
  float aspect;
  float cam_right[3];
  float clamp;  // 0 = off
  float cam_up[3];
  float cutoff;
  float env_radiance[3];
  uint seed;
  uint width;
  uint height;
  uint max_depth;
  uint gi;
  uint num_lights;
  uint num_nodes;
  uint pool_size;
  uint rr_depth;      // first bounce at which Russian roulette may end a path
  // Jobs are (pixel, sample) pairs in sample-major order. A batch is a contiguous run of
  // jobs starting at (batch_pixel, batch_sample); local job i of the batch is
  // pixel (batch_pixel + i) % pixels of sample batch_sample + (batch_pixel + i) / pixels.
  // Kept as two 32-bit numbers so a 4K render at thousands of spp does not overflow.
  uint batch_pixel;
  uint batch_sample;
  uint job_count;  // jobs in this batch
  uint split_spp;  // spp when per-lobe samples split at the first hit (integrator/split.h), else 0
  uint sampler;    // AW_SAMPLER_* (kernels/common/rng.h)
  uint sampler_log2_spp;  // zsobol: ceil(log2(spp)) (common/rng.h, Sampler)
  uint sampler_bits;      // zsobol: 2 ceil(log2(max(width, height))) + sampler_log2_spp
} RenderParams;

#endif
