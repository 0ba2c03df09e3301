// Access to one path's state, the same on device (SoA buffers) and host (one path).
#ifndef AW_INTEGRATOR_PATH_STATE_H
#define AW_INTEGRATOR_PATH_STATE_H

#include "common/compat.h"
#include "common/rng.h"
#include "types/scene.h"

enum {
#define AW_STATE_F(name) AW_SF_##name,
#define AW_STATE_U(name)
#include "integrator/state_template.h"
#undef AW_STATE_F
#undef AW_STATE_U
  AW_SF_COUNT
};
enum {
#define AW_STATE_F(name)
#define AW_STATE_U(name) AW_SU_##name,
#include "integrator/state_template.h"
#undef AW_STATE_F
#undef AW_STATE_U
  AW_SU_COUNT
};

// Path flags.
#define AW_PATH_SPECULAR 1u    // last scattering was a delta lobe: no MIS on a light hit
#define AW_PATH_HAS_SHADOW 2u  // the lobe stage wrote a shadow ray this bounce
#define AW_PATH_EMITTERS_ONLY 4u  // the ray only looks for lights: a surface hit ends the path
#define AW_PATH_FRONT 8u          // the current hit is on the outside (front face) of its surface
#define AW_PATH_MISSING_FEATURE 16u  // hit a material feature this kernel build lacks (a bug)
#define AW_PATH_SPLIT 32u            // the first-hit lobe is being split (integrator/split.h)

// AW_NONE (no index): common/compat.h

// The render's sampler (render.sampler and what it needs of the image), for rng_1d/rng_2d.
AW_FN Sampler rp_sampler(const RenderParams* rp) {
  return sampler_make(rp->sampler, rp->seed, rp->width, rp->sampler_log2_spp, rp->sampler_bits);
}

// A handle on one path: the buffers, the pool size (the stride between fields) and the slot.
// snap_f / snap_u: the first-hit snapshot of lobe splitting (integrator/split.h); only the
// stages that split or end paths get them, the others leave them null. aov: the first hit's
// AOV data (integrator/aov.h, AW_AOVS_*), only when the render asks for AOVs (rp->aov_mask).
typedef struct {
  AW_GLOBAL float* sf;
  AW_GLOBAL uint* su;
  AW_GLOBAL float* snap_f;
  AW_GLOBAL uint* snap_u;
  AW_GLOBAL float* aov;
  uint pool;
  uint slot;
} PathRef;
#define PS_AOV(ps, i) ((ps).aov[(uint)(i) * (ps).pool + (ps).slot])

#define PS_F(ps, name) ((ps).sf[(uint)AW_SF_##name * (ps).pool + (ps).slot])
#define PS_U(ps, name) ((ps).su[(uint)AW_SU_##name * (ps).pool + (ps).slot])

AW_FN float3 ps_ray_origin(PathRef ps) { return make_float3(PS_F(ps, ray_ox), PS_F(ps, ray_oy), PS_F(ps, ray_oz)); }
AW_FN float3 ps_ray_dir(PathRef ps) { return make_float3(PS_F(ps, ray_dx), PS_F(ps, ray_dy), PS_F(ps, ray_dz)); }
AW_FN void ps_set_ray(PathRef ps, float3 o, float3 d) {
  PS_F(ps, ray_ox) = o.x; PS_F(ps, ray_oy) = o.y; PS_F(ps, ray_oz) = o.z;
  PS_F(ps, ray_dx) = d.x; PS_F(ps, ray_dy) = d.y; PS_F(ps, ray_dz) = d.z;
}
AW_FN float3 ps_throughput(PathRef ps) { return make_float3(PS_F(ps, thr_r), PS_F(ps, thr_g), PS_F(ps, thr_b)); }
AW_FN void ps_set_throughput(PathRef ps, float3 t) { PS_F(ps, thr_r) = t.x; PS_F(ps, thr_g) = t.y; PS_F(ps, thr_b) = t.z; }
AW_FN float3 ps_radiance(PathRef ps) { return make_float3(PS_F(ps, rad_r), PS_F(ps, rad_g), PS_F(ps, rad_b)); }
AW_FN void ps_add_radiance(PathRef ps, float3 l) { PS_F(ps, rad_r) += l.x; PS_F(ps, rad_g) += l.y; PS_F(ps, rad_b) += l.z; }
AW_FN float3 ps_sp_position(PathRef ps) { return make_float3(PS_F(ps, sp_px), PS_F(ps, sp_py), PS_F(ps, sp_pz)); }
AW_FN float3 ps_sp_normal(PathRef ps) { return make_float3(PS_F(ps, sp_nx), PS_F(ps, sp_ny), PS_F(ps, sp_nz)); }
AW_FN float3 ps_sp_tangent(PathRef ps) { return make_float3(PS_F(ps, sp_tx), PS_F(ps, sp_ty), PS_F(ps, sp_tz)); }
AW_FN float3 ps_lobe_weight(PathRef ps) { return make_float3(PS_F(ps, lobe_wr), PS_F(ps, lobe_wg), PS_F(ps, lobe_wb)); }
AW_FN float3 ps_sp_unbumped_normal(PathRef ps) { return make_float3(PS_F(ps, sp_bx), PS_F(ps, sp_by), PS_F(ps, sp_bz)); }
AW_FN float3 ps_sp_geo_normal(PathRef ps) { return make_float3(PS_F(ps, sp_gx), PS_F(ps, sp_gy), PS_F(ps, sp_gz)); }

// Writes the closest hit of the extension ray (both intersectors end here).
AW_FN void ps_set_hit(PathRef ps, float t, float u, float v, uint prim, uint inst, uint light) {
  PS_F(ps, hit_t) = t;
  PS_F(ps, hit_u) = u;
  PS_F(ps, hit_v) = v;
  PS_U(ps, hit_prim) = prim;
  PS_U(ps, hit_inst) = inst;
  PS_U(ps, hit_light) = light;
}

#endif
