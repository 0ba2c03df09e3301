// Access to one path's state, the same on device (SoA buffers) and host (one path).
#ifndef AW_INTEGRATOR_PATH_STATE_H
#define AW_INTEGRATOR_PATH_STATE_H

#include "common/compat.h"
#include "common/features.h"
#include "common/lanes.h"
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
// On lanes (common/lanes.h, AW_LANES = W > 1) it is a handle on W paths: the slots slot ..
// slot + W - 1, and `live`, the lanes that are paths of the stage; see PS_LF below.
typedef struct {
  AW_GLOBAL float* sf;
  AW_GLOBAL uint* su;
  AW_GLOBAL float* snap_f;
  AW_GLOBAL uint* snap_u;
  AW_GLOBAL float* aov;
  uint pool;
  uint slot;
#if AW_LANES > 1
  lmask live;
  int all_live;  // L_ALL(live), kept beside it (PS_SET_LIVE, PS_KEEP): see ps_store_f
#endif
} PathRef;
#define PS_AOV(ps, i) ((ps).aov[(uint)(i) * (ps).pool + (ps).slot])

// One path's field, as an lvalue (code written for one path per call).
#define PS_F(ps, name) ((ps).sf[(uint)AW_SF_##name * (ps).pool + (ps).slot])
#define PS_U(ps, name) ((ps).su[(uint)AW_SU_##name * (ps).pool + (ps).slot])

// Code written on lanes reads a field with PS_LF/PS_LU and writes it with PS_SET_F/PS_SET_U.
// At W = 1 these are PS_F/PS_U. At W > 1 a read is one vector load of the W slots' words
// (fields are field-major, so the block's words are consecutive: what bench_lanes measured
// pays), and a write stores the value into the live lanes only, a read-modify-write of the
// whole vector (the block belongs to one work-item, so no other writes it meanwhile), or a plain
// vector store where all W lanes are live (all_live, kept beside live: PS_SET_LIVE, PS_KEEP):
// Intel's runtime compiled the read-modify-write into a masked store (vmaskmovps), many
// micro-ops on AMD's Zen 3, where it held 72% of regenerate's samples (docs/performance.md,
// "On an AMD EPYC (AVX2)").
// A path that ends or skips the rest of a step leaves `live` (PS_KEEP(ps, m): keep the lanes
// of m); code that does so must then `if (!L_ANY(m)) return`, which at W = 1, where there
// is no `live`, is the scalar code's own early return, so that a write is never reached for
// a path that should not make it.
#if AW_LANES == 1
#define PS_LF(ps, name) PS_F(ps, name)
#define PS_LU(ps, name) PS_U(ps, name)
#define PS_SET_F(ps, name, v) (PS_F(ps, name) = (v))
#define PS_SET_U(ps, name, v) (PS_U(ps, name) = (v))
#define PS_LIVE(ps) 1
#define PS_KEEP(ps, m) ((void)0)
#else
AW_FN void ps_store_f(AW_GLOBAL float* p, lfloat v, lmask m, int all) { L_STORE(all ? v : L_SEL(m, v, L_LOAD(p, 0)), p, 0); }
AW_FN void ps_store_u(AW_GLOBAL uint* p, luint v, lmask m, int all) { L_STORE(all ? v : L_SEL(m, v, L_LOAD(p, 0)), p, 0); }
#define PS_LF(ps, name) L_LOAD((ps).sf + (uint)AW_SF_##name * (ps).pool + (ps).slot, 0)
#define PS_LU(ps, name) L_LOAD((ps).su + (uint)AW_SU_##name * (ps).pool + (ps).slot, 0)
#define PS_SET_F(ps, name, v) ps_store_f((ps).sf + (uint)AW_SF_##name * (ps).pool + (ps).slot, (v), (ps).live, (ps).all_live)
#define PS_SET_U(ps, name, v) ps_store_u((ps).su + (uint)AW_SU_##name * (ps).pool + (ps).slot, (v), (ps).live, (ps).all_live)
#define PS_LIVE(ps) ((ps).live)
#define PS_SET_LIVE(ps, m) ((ps).live = (m), (ps).all_live = L_ALL((ps).live))
#define PS_KEEP(ps, m) PS_SET_LIVE(ps, (ps).live && (m))
#endif

AW_FN lfloat3 ps_ray_origin(PathRef ps) { return make_lfloat3(PS_LF(ps, ray_ox), PS_LF(ps, ray_oy), PS_LF(ps, ray_oz)); }
AW_FN lfloat3 ps_ray_dir(PathRef ps) { return make_lfloat3(PS_LF(ps, ray_dx), PS_LF(ps, ray_dy), PS_LF(ps, ray_dz)); }
AW_FN void ps_set_ray(PathRef ps, lfloat3 o, lfloat3 d) {
  PS_SET_F(ps, ray_ox, o.x); PS_SET_F(ps, ray_oy, o.y); PS_SET_F(ps, ray_oz, o.z);
  PS_SET_F(ps, ray_dx, d.x); PS_SET_F(ps, ray_dy, d.y); PS_SET_F(ps, ray_dz, d.z);
}
AW_FN lfloat3 ps_throughput(PathRef ps) { return make_lfloat3(PS_LF(ps, thr_r), PS_LF(ps, thr_g), PS_LF(ps, thr_b)); }
AW_FN void ps_set_throughput(PathRef ps, lfloat3 t) {
  PS_SET_F(ps, thr_r, t.x); PS_SET_F(ps, thr_g, t.y); PS_SET_F(ps, thr_b, t.z);
}
AW_FN lfloat3 ps_radiance(PathRef ps) { return make_lfloat3(PS_LF(ps, rad_r), PS_LF(ps, rad_g), PS_LF(ps, rad_b)); }
AW_FN void ps_add_radiance(PathRef ps, lfloat3 l) {
  PS_SET_F(ps, rad_r, PS_LF(ps, rad_r) + l.x); PS_SET_F(ps, rad_g, PS_LF(ps, rad_g) + l.y); PS_SET_F(ps, rad_b, PS_LF(ps, rad_b) + l.z);
}
AW_FN lfloat3 ps_sp_position(PathRef ps) { return make_lfloat3(PS_LF(ps, sp_px), PS_LF(ps, sp_py), PS_LF(ps, sp_pz)); }
AW_FN lfloat3 ps_sp_normal(PathRef ps) { return make_lfloat3(PS_LF(ps, sp_nx), PS_LF(ps, sp_ny), PS_LF(ps, sp_nz)); }
AW_FN lfloat3 ps_sp_tangent(PathRef ps) { return make_lfloat3(PS_LF(ps, sp_tx), PS_LF(ps, sp_ty), PS_LF(ps, sp_tz)); }
AW_FN lfloat3 ps_lobe_weight(PathRef ps) { return make_lfloat3(PS_LF(ps, lobe_wr), PS_LF(ps, lobe_wg), PS_LF(ps, lobe_wb)); }
AW_FN lfloat3 ps_sp_unbumped_normal(PathRef ps) { return make_lfloat3(PS_LF(ps, sp_bx), PS_LF(ps, sp_by), PS_LF(ps, sp_bz)); }
AW_FN lfloat3 ps_sp_geo_normal(PathRef ps) { return make_lfloat3(PS_LF(ps, sp_gx), PS_LF(ps, sp_gy), PS_LF(ps, sp_gz)); }

// Writes the closest hit of the extension ray (both intersectors end here). The instance only
// where the build has instances: nothing else reads it (integrator/classify_hit.h), and the
// lane kernels that write hits are built for scenes without them.
AW_FN void ps_set_hit(PathRef ps, lfloat t, lfloat u, lfloat v, luint prim, luint inst, luint light) {
  PS_SET_F(ps, hit_t, t);
  PS_SET_F(ps, hit_u, u);
  PS_SET_F(ps, hit_v, v);
  PS_SET_U(ps, hit_prim, prim);
  if (AW_FEAT_INSTANCE) PS_SET_U(ps, hit_inst, inst);
  PS_SET_U(ps, hit_light, light);
}

#endif
