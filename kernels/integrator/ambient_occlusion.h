// From: AO / To: the lobe queue classify_hit chose (PS_U lobe), or DONE when it chose none.
// The material's ambient occlusion (docs/material.md §4), traced between the hit's
// classification and its lobe stage, only for materials with ao.enable and only in builds
// whose scene has such a material (feature AO).
//
// AO rays are cosine-weighted in a cone of half-angle spread * pi / 2 around the shading
// normal (its opposite with invert_normal): Malley's method (PBR 3rd ed., Sec. 13.6.3) on a
// disk of radius sin(half-angle), which is the cosine-weighted density restricted to the
// cone. A ray that meets a surface at distance d < max_distance keeps the visibility
// (d / max_distance)^falloff: 0 at the surface, 1 at max_distance, linear for falloff 1, so
// falloff < 1 biases towards un-occluded and > 1 towards occluded as the material's
// documentation says (max_distance 0: unlimited reach, every hit occludes fully). v is the
// mean visibility of the rays and AO = lerp(shadow_color, ambient_color, v).
//   add:      throughput x diffuse weight x diffuse colour x AO (x 1/k with
//             exposure_compensation) is added, as indirect diffuse light would be;
//   multiply: the throughput is multiplied by AO, so everything the path gathers from here on
//             (direct and indirect light) is; with apply_to_incandescence the incandescence of
//             this hit too (classify_hit leaves it to this stage).
// Multiplying by the estimate of AO from this vertex's rays is unbiased for AO x (the rest):
// the AO rays' random numbers (AW_DIM_AO) are independent of every other decision.
// At the first hit, ao.samples splits like a lobe's samples (§6): n = max(1, round(samples /
// spp)) rays, weighted 1/n, taking sample indices s n + k of the AO set so the n spp
// directions of a pixel form one stratified set; deeper hits trace one ray.
#ifndef AW_INTEGRATOR_AMBIENT_OCCLUSION_H
#define AW_INTEGRATOR_AMBIENT_OCCLUSION_H

#include "common/ray.h"
#include "common/rng.h"
#include "common/sampling.h"
#include "integrator/aov.h"
#include "integrator/intersect_shadow.h"
#include "integrator/light_select.h"
#include "integrator/path_state.h"
#include "integrator/queues.h"
#include "integrator/split.h"
#include "integrator/shading_material.h"

// Visibility in [0, 1] along one AO ray.
AW_FN float ao_ray_visibility(SceneRef sc, const AW_GLOBAL MaterialGpu* m, float3 o, float3 w) {
  float reach = m->ao_max_distance > 0.0f ? m->ao_max_distance : FLT_MAX;
  TriangleHit h = scene_intersect(sc, o, w, 0.0f, reach);
  if (h.prim < 0) return 1.0f;
  float t = h.t;
  if (!(m->ao_max_distance > 0.0f)) return 0.0f;
  return pow(clamp(t / m->ao_max_distance, 0.0f, 1.0f), m->ao_falloff);
}

AW_FN int ambient_occlusion(PathRef ps, SceneRef sc, const RenderParams* rp) {
  const AW_GLOBAL MaterialGpu* m = shading_material(ps, sc, rp);
  uint lid = PS_U(ps, lobe);
  int next = lid == AW_NONE ? AW_Q_DONE : AW_Q_LOBE + (int)lid;
  if (!(AW_FEAT_AO && m->ao_samples > 0u)) return next;
  float3 p = ps_sp_position(ps);
  float3 axis = ps_sp_normal(ps), ng = ps_sp_geo_normal(ps);
  if (m->ao_flags & AW_AO_INVERT) {
    axis = -axis;
    ng = -ng;
  }
  float3 t, b;
  make_frame(axis, &t, &b);
  float s_max, c_max;
  sincos_turn(0.25f * clamp(m->ao_spread, 0.0f, 1.0f), &s_max, &c_max);  // angle spread * pi / 2
  float3 o = offset_ray_origin(p, ng, PS_F(ps, sp_err));
  uint bounce = PS_U(ps, bounce), sample = PS_U(ps, sample), pixel = PS_U(ps, pixel);
  uint n = bounce == 0u ? split_count(m->ao_samples, rp->ao_split_spp) : 1u;
  float vis = 0.0f;
  for (uint k = 0u; k < n; ++k) {
    float2 u = rng_2d(rp_sampler(rp), pixel, sample * n + k, bounce, AW_DIM_AO);
    float2 d = sample_concentric_disk(u) * s_max;
    float3 w = normalize(frame_to_world(make_float3(d.x, d.y, safe_sqrt(1.0f - d.x * d.x - d.y * d.y)), t, b, axis));
    // A direction below the geometric surface (the shading normal tilts the cone) would start
    // inside the object: the surface itself occludes it.
    if (dot(w, ng) > 0.0f) vis += ao_ray_visibility(sc, m, o, w);
  }
  vis /= (float)n;
  float3 ao = load_f3(m->ao_shadow_color) + (load_f3(m->ao_ambient_color) - load_f3(m->ao_shadow_color)) * vis;
  float3 thr = ps_throughput(ps);
  if (m->ao_flags & AW_AO_MULTIPLY) {
    // (A light-sampled triangle's emission was added, MIS-weighted, by classify_hit.)
    int is_light = triangle_light(sc, rp, PS_U(ps, hit_prim)) != AW_NONE;
    if (AW_FEAT_INCANDESCENCE && (m->ao_flags & AW_AO_INCANDESCENCE) && !is_light)
      ps_add_radiance(ps, thr * load_f3(m->incandescent) * ao * PS_F(ps, emit_scale));
    ps_set_throughput(ps, thr * ao);
  } else if (!(m->flags & AW_MAT_METAL)) {  // metal has no diffuse (docs/material.md §1)
    ps_add_radiance(ps, thr * load_f3(m->diffuse_color) * ao * (m->diffuse_weight * m->ao_add_scale));
  }
  aov_first_scatter(ps, rp, AW_NONE);  // the ao light group: what this stage added at the first hit
  return next;
}

#endif
