// Scene data shared by host and kernels: materials, lights, render parameters.
// Plain 4-byte fields only; sizes and offsets are asserted on both sides (tests/types).
#ifndef AW_TYPES_SCENE_H
#define AW_TYPES_SCENE_H

#include "types/material.h"
#include "types/texture.h"

#define AW_LIGHT_POINT 0
#define AW_LIGHT_QUAD 1
#define AW_LIGHT_DISK 2
#define AW_LIGHT_SPHERE 3
// Lights at infinity. The host puts them first in the light array (lights[0, num_infinite):
// the environment map, if any, then the suns): a ray that escapes looks only at those
// (classify_hit.h), and no ray ever hits them in lights_intersect.
#define AW_LIGHT_SUN 4  // directional, or a cone of directions when its angle is > 0
#define AW_LIGHT_ENV 5  // the environment map (lights/environment.h); radiance and layout in sc.env
// A triangle of an incandescent object that opted in to light sampling (objects[].light_sampling):
// sampled like an area light, hit as geometry (TriangleInfo.light points back here).
#define AW_LIGHT_TRIANGLE 6

#define AW_LIGHT_TWO_SIDED 1u
#define AW_LIGHT_VISIBLE 2u
#define AW_LIGHT_RECTANGLE 4u  // a quad whose edges are orthogonal: sampled by solid angle (lights.h)

// One light. Meaning of p/u/v by type:
//   point:  p = position
//   quad:   p = corner, u = edge_u, v = edge_v, n = unit normal (edge_u × edge_v)
//   disk:   p = center, n = unit normal, u/v = orthonormal tangents, radius
//   sphere: p = center, radius
//   sun:    n = unit vector towards the sun, radius = cos of the half-angle, area = 1 - that
//           cosine (0: a hard sun, a delta); radiance = the disc's radiance, E / (pi sin^2 of
//           the half-angle), or the irradiance E itself for a hard sun
//   env:    nothing here but the selection fields (the map is sc.env, its size in RenderParams)
//   triangle: p = vertex 0, u = v1 - v0, v = v2 - v0, n = unit normal, area; two-sided
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
  uint tree_bits;    // the light's path from the light tree's root (lights/light_tree.h):
  float radiance[3];
  uint tree_depth;   // bit k = 1: the second child at level k; tree_depth levels
} LightGpu;

// One node of the light tree (lights/light_tree.h), depth-first: an inner node's first child
// is the next node, its second child is `child`; a leaf holds one light, `child` its index.
typedef struct {
  float bmin[3];
  float power;       // selection power of the lights below (luminance, as for the alias table)
  float bmax[3];
  float cos_o;       // cone of the emitters' normals around axis: cos theta_o (-1: all directions)
  float axis[3];
  float cos_e;       // cos theta_e: how far around each normal the emitters emit (0: a hemisphere)
  uint child;
  uint leaf;
  uint pad[2];
} LightTreeNode;

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
  // jobs, placed in the batch ring (host/render/wavefront.cpp) at its indices job_start ..
  // job_start + job_count - 1; ring index j is film pixel (batch_pixel + j) % pixels of sample
  // batch_sample + (batch_pixel + j) / pixels, where pixels = win_w * win_h (the film's
  // window, below). The host chooses batch_pixel (below 2 pixels + the ring's half size) and
  // batch_sample (in uint arithmetic, which wraps) so that j = job_start is the batch's first
  // job; with job_start = 0, batch_pixel < pixels is the batch's first pixel.
  // Kept as two 32-bit numbers so a 4K render at thousands of spp does not overflow.
  uint batch_pixel;
  uint batch_sample;
  uint job_count;  // jobs in this batch
  uint split_spp;  // spp when per-lobe samples split at the first hit (integrator/split.h), else 0
  uint sampler;    // AW_SAMPLER_* (kernels/common/rng.h)
  uint sampler_log2_spp;  // zsobol: ceil(log2(spp)) (common/rng.h, Sampler)
  uint sampler_bits;      // zsobol: 2 ceil(log2(max(width, height))) + sampler_log2_spp
  uint num_infinite;      // lights[0, num_infinite) are at infinity: the environment map, the suns
  uint env_width;         // the environment map (lights/environment.h), 0 x 0 without one
  uint env_height;
  float env_rot_cos;      // environment.rotation about +Y
  float env_rot_sin;
  uint ao_split_spp;      // spp when ao.samples split at the first hit (render.lobe_splitting), else 0
  uint num_tree_nodes;    // the light tree's nodes; 0: lights are chosen by the alias table alone
  float tree_prob;        // with a tree: the probability of choosing among its lights (their power share)
  uint has_mesh_lights;   // sc.tri_light holds each triangle's light (AW_LIGHT_TRIANGLE) or AW_NONE
  // The film's window in the frame (--pixel-bounds / --crop-window, docs/production.md): jobs
  // cover its win_w x win_h pixels, film pixel i being frame pixel (win_x0 + i % win_w,
  // win_y0 + i / win_w). width and height above stay the frame's: the camera and the sampler
  // see frame pixels, so a window renders exactly the frame's pixels.
  uint win_x0;
  uint win_y0;
  uint win_w;
  uint win_h;
  // The film's first sample index (--sample-range START): film pixel p holds the samples
  // [sample_start, sample_start + film_count[p]) (integrator/film.h).
  uint sample_start;
  uint aov_mask;  // the AOVs the film keeps: a bit per AW_AOV_* (integrator/aov.h); 0: none
  uint num_materials;  // the scene's material table (material/architectural.h, MatL on lanes)
} RenderParams;

#endif
