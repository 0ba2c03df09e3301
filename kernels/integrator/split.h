// Per-lobe `samples`: splitting at the first hit (docs/material.md §6). A camera sample whose first
// scattering vertex picks lobe L traces n = max(1, round(samples_L / spp)) rays from that
// vertex, each weighted 1/n; deeper bounces trace one.
//
// The splits run one after another in the same path slot, not side by side: when split s
// ends (the path reaches DONE), accumulate restores the state saved at the first hit and sends
// the slot back to lobe L's queue as split s + 1. This needs no slot allocation, keeps the
// pool's occupancy unchanged, and sums the splits in a fixed order (0, 1, …, n-1), so the
// wavefront and the scalar path, which runs the same functions, agree bit for bit and the
// image stays independent of the pool and batch sizes. What splitting saves is the camera ray,
// its closest hit and the classify stage, paid once for n first-bounce rays.
//
// Randomness: split s draws from the stream of sample index sample + s * spp, which no other
// camera sample of the pixel uses (they are < spp), so the splits are independent and split 0
// is the unsplit path exactly.
//
// The snapshot lives in separate buffers (PathRef.snap_f / snap_u, allocated only when a
// scene splits): a copy of every state field, then the running sum (3 floats), the sum of the
// splits' clamp factors (1 float) and
// (n << 16 | s) (1 uint).
#ifndef AW_INTEGRATOR_SPLIT_H
#define AW_INTEGRATOR_SPLIT_H

#include "common/features.h"
#include "integrator/path_state.h"
#include "material/lobes.h"
#include "types/material.h"
#include "types/scene.h"

#define AW_SPLIT_MAX 1024u  // bound on n (docs/material.md §6 sets none; a pixel's splits stay < 2^16)
#define AW_SNAP_F_COUNT (AW_SF_COUNT + 4)
#define AW_SNAP_U_COUNT (AW_SU_COUNT + 1)
#define AW_SNAP_F(ps, i) ((ps).snap_f[(uint)(i) * (ps).pool + (ps).slot])
#define AW_SNAP_U(ps, i) ((ps).snap_u[(uint)(i) * (ps).pool + (ps).slot])

// n = max(1, round(samples / spp)), rounding halves up, in integers so that host and device
// agree exactly.
AW_FN uint split_count(uint samples, uint spp) {
  if (spp == 0u) return 1u;
  uint n = (2u * min(samples, 1u << 20) + spp) / (2u * spp);
  return n < 1u ? 1u : (n > AW_SPLIT_MAX ? AW_SPLIT_MAX : n);
}

#if AW_LANES == 1  // (the lobes on lanes start no split: integrator/shade_surface.h)
// The split count of lobe `lid` of a material (lobes without `samples` report 0: one ray).
AW_FN uint lobe_split_count(const AW_GLOBAL MaterialGpu* m, uint lid, uint spp) {
  return split_count(lobe_samples(m, lid), spp);
}
#endif

// Starts splitting at the first scattering vertex, before the lobe stage touches the state.
AW_FN void split_begin(PathRef ps, uint n) {
  PS_U(ps, flags) |= AW_PATH_SPLIT;  // saved too: the restored splits never split again
  for (uint f = 0u; f < (uint)AW_SF_COUNT; ++f) AW_SNAP_F(ps, f) = ps.sf[f * ps.pool + ps.slot];
  for (uint f = 0u; f < (uint)AW_SU_COUNT; ++f) AW_SNAP_U(ps, f) = ps.su[f * ps.pool + ps.slot];
  AW_SNAP_F(ps, AW_SF_COUNT + 0) = 0.0f;
  AW_SNAP_F(ps, AW_SF_COUNT + 1) = 0.0f;
  AW_SNAP_F(ps, AW_SF_COUNT + 2) = 0.0f;
  AW_SNAP_F(ps, AW_SF_COUNT + 3) = 0.0f;
  AW_SNAP_U(ps, AW_SU_COUNT) = n << 16;
}

// A split path has ended with sample value `l` (already checked and clamped by path_result,
// by the factor k). Returns 1 when another split follows: the state is back at the first hit,
// ready for the lobe queue PS_U(ps, lobe). Returns 0 when this was the last: *out = the mean
// of the splits, *k_out the mean of their factors (the AOVs' light groups: integrator/aov.h).
AW_FN int split_next(PathRef ps, const RenderParams* rp, float3 l, float k, float3* out, float* k_out) {
  float3 sum = make_float3(AW_SNAP_F(ps, AW_SF_COUNT + 0), AW_SNAP_F(ps, AW_SF_COUNT + 1),
                           AW_SNAP_F(ps, AW_SF_COUNT + 2)) + l;
  float k_sum = AW_SNAP_F(ps, AW_SF_COUNT + 3) + k;
  uint ns = AW_SNAP_U(ps, AW_SU_COUNT);
  uint n = ns >> 16, s = (ns & 0xffffu) + 1u;
  if (s >= n) {
    *out = sum / (float)n;
    *k_out = k_sum / (float)n;
    return 0;
  }
  for (uint f = 0u; f < (uint)AW_SF_COUNT; ++f) ps.sf[f * ps.pool + ps.slot] = AW_SNAP_F(ps, f);
  for (uint f = 0u; f < (uint)AW_SU_COUNT; ++f) ps.su[f * ps.pool + ps.slot] = AW_SNAP_U(ps, f);
  AW_SNAP_F(ps, AW_SF_COUNT + 0) = sum.x;
  AW_SNAP_F(ps, AW_SF_COUNT + 1) = sum.y;
  AW_SNAP_F(ps, AW_SF_COUNT + 2) = sum.z;
  AW_SNAP_F(ps, AW_SF_COUNT + 3) = k_sum;
  AW_SNAP_U(ps, AW_SU_COUNT) = (n << 16) | s;
  PS_U(ps, sample) = PS_U(ps, sample) + s * rp->split_spp;
  return 1;
}

#endif
