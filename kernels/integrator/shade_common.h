// What every lobe stage does around its own lobe: next-event estimation (writes the shadow
// ray) and continuing the path (Russian roulette, depth, the extension ray).
#ifndef AW_INTEGRATOR_SHADE_COMMON_H
#define AW_INTEGRATOR_SHADE_COMMON_H

#include "common/ray.h"
#include "common/rng.h"
#include "common/sampling.h"
#include "integrator/path_state.h"
#include "integrator/queues.h"
#include "integrator/scene_ref.h"
#include "integrator/light_select.h"
#include "lobes/lobe.h"

// Writes the shadow ray for a light sample whose unoccluded contribution is `contrib`.
AW_FN void shade_emit_shadow(PathRef ps, float3 p, float3 ng, LightSample ls, uint light, float3 contrib) {
  float3 o = offset_ray_origin(p, ng, PS_F(ps, sp_err));
  float3 wi = ls.wi;
  float tmax = ls.dist;
  // A light at a finite distance: the ray aims from the offset origin at the sampled point
  // itself and stops just short of it (pbrt-v4 Sec. 6.8.6, SpawnRayTo). Along wi from the
  // offset origin it would cross the light's plane earlier than dist by the offset over the
  // cosine: a light-sampled mesh's own triangles (in the BVH, where sh_light does not skip
  // them) occluded 97% of the samples from a floor 100 units wide (offset 2.7e-4;
  // ManyLights.LightSampledMeshQuadMatchesLambertsFormula). Lights at infinity keep wi.
  if (ls.dist < AW_INFINITE_DISTANCE) {
    float3 d = (p + ls.wi * ls.dist) - o;
    float len = sqrt(dot(d, d));
    if (len > 0.0f && isfinite(len)) {
      wi = d / len;
      tmax = len;
    }
  }
  PS_F(ps, sh_ox) = o.x; PS_F(ps, sh_oy) = o.y; PS_F(ps, sh_oz) = o.z;
  PS_F(ps, sh_dx) = wi.x; PS_F(ps, sh_dy) = wi.y; PS_F(ps, sh_dz) = wi.z;
  // Stop just short of the light: the sampled point lies on the light itself (which the
  // shadow test skips anyway for analytic lights, see sh_light).
  PS_F(ps, sh_tmax) = tmax * (1.0f - 1e-4f);
  PS_F(ps, sh_r) = contrib.x; PS_F(ps, sh_g) = contrib.y; PS_F(ps, sh_b) = contrib.z;
  PS_U(ps, sh_light) = light;
  PS_U(ps, flags) |= AW_PATH_HAS_SHADOW;
}

// Continues the path along a sampled lobe direction (s.weight already includes the lobe's
// energy share over its selection probability), or ends it. Russian roulette is unbiased
// (Arvo & Kirk 1990, "Particle Transport and Image Synthesis", Sec. 3.3): from rr_depth on,
// survival probability min(1, sqrt(m)) with m = max throughput x eta_scale (the square root
// keeps dim paths alive longer than survival m would: measured 1.1-1.5x the efficiency on the
// race's scenes, docs/architecture.md#russian-roulette); below `cutoff` (render.cutoff, or a
// lobe's cut-off threshold) the survival is m / cutoff, so weak paths stop early
// without bias (docs/material.md §5: the realisation of the cut-off thresholds).
AW_FN int shade_continue(PathRef ps, const RenderParams* rp, float3 p, float3 ng, LobeSample s, float cutoff) {
  uint bounce = PS_U(ps, bounce);
  // No depth test here: the ray is traced even from the last allowed vertex, because light
  // sampling at this vertex was MIS-weighted against it; classify_hit ends the path at the
  // next surface instead.
  if (s.flags == 0u) return AW_Q_DONE;
  float3 wi = s.wi;
  // A direction on the wrong side of the geometric surface (possible with interpolated
  // normals) would leak through the mesh: end the path instead.
  int transmit = (s.flags & AW_LOBE_TRANSMISSION) != 0u;
  float cg = dot(wi, ng);
  if (transmit ? cg >= 0.0f : cg <= 0.0f) return AW_Q_DONE;

  float3 thr = ps_throughput(ps) * s.weight;
  // Roulette judges the throughput without the radiance scaling of refraction (Pharr, Jakob
  // & Humphreys, pbrt-v4, the path integrator's etaScale; Veach 1997, Sec. 5.2, for the
  // 1/eta^2 itself; docs/architecture.md#russian-roulette): entering glass of index 1.5 scales radiance
  // by 1/2.25 and leaving it undoes that, so a path inside would otherwise be killed 56% of
  // the time for a factor that cancels. Thin walls and reflections leave eta_scale at 1.
  float eta_scale = PS_F(ps, eta_scale) * s.eta_scale;
  float m = max3(thr) * eta_scale;
  if (!(m > 0.0f) || !isfinite(m)) return AW_Q_DONE;
  PS_F(ps, eta_scale) = eta_scale;
  float q = 1.0f;
  if (bounce + 1u >= rp->rr_depth) q = fmin(1.0f, sqrt(m));
  if (m < cutoff) q = fmin(q, m / cutoff);
  if (q < 1.0f) {
    float u = rng_1d(rp_sampler(rp), PS_U(ps, pixel), PS_U(ps, sample), bounce, AW_DIM_RR);
    if (u >= q) return AW_Q_DONE;
    thr = thr / q;
  }
  ps_set_throughput(ps, thr);
  PS_F(ps, bsdf_pdf) = s.pdf;  // the lobe's own density: see the MIS note in shade_surface
  // The ray cone widens by the lobe's angular spread, taken as 1/sqrt(pdf): the solid angle a
  // sample of density pdf stands for (the footprint of path differentials by the sampling
  // density: Suykens & Willems 2001, "Path Differentials and Applications", EGWR, Sec. 4);
  // a delta lobe keeps it (a mirror's curvature is ignored). Bounded by pi/2.
  if (!(s.flags & AW_LOBE_SPECULAR) && s.pdf > 0.0f) PS_F(ps, cone_s) += fmin(1.0f / sqrt(s.pdf), 1.5707964f);
  if (s.flags & AW_LOBE_SPECULAR) PS_U(ps, flags) |= AW_PATH_SPECULAR;
  else PS_U(ps, flags) &= ~AW_PATH_SPECULAR;
  ps_set_ray(ps, offset_ray_origin(p, transmit ? -ng : ng, PS_F(ps, sp_err)), wi);
  PS_U(ps, bounce) = bounce + 1u;
  return AW_Q_RAY;
}

#endif
