// What every lobe stage does around its own lobe: next-event estimation (writes the shadow
// ray) and continuing the path (Russian roulette, depth, the extension ray).
#ifndef AW_INTEGRATOR_SHADE_COMMON_H
#define AW_INTEGRATOR_SHADE_COMMON_H

#include "common/features.h"
#include "common/ray.h"
#include "common/rng.h"
#include "common/sampling.h"
#include "integrator/path_state.h"
#include "integrator/queues.h"
#include "lights/lights.h"
#include "lobes/lobe.h"

// Written on lanes (common/lanes.h; path_state.h for the state's reads and writes): at
// AW_LANES = 1 one path, the scalar code; at W > 1 a block of W paths, those of PS_LIVE.

// Writes the shadow ray for a light sample whose unoccluded contribution is `contrib`.
AW_FN void shade_emit_shadow(PathRef ps, lfloat3 p, lfloat3 ng, LightSample ls, luint light, lfloat3 contrib) {
  lfloat3 o = offset_ray_origin(p, ng, PS_LF(ps, sp_err));
  lfloat3 wi = ls.wi;
  lfloat tmax = ls.dist;
  // A light at a finite distance: the ray aims from the offset origin at the sampled point
  // itself and stops just short of it (pbrt-v4 Sec. 6.8.6, SpawnRayTo). Along wi from the
  // offset origin it would cross the light's plane earlier than dist by the offset over the
  // cosine: a light-sampled mesh's own triangles (in the BVH, where sh_light does not skip
  // them) occluded 97% of the samples from a floor 100 units wide (offset 2.7e-4;
  // ManyLights.LightSampledMeshQuadMatchesLambertsFormula). Lights at infinity keep wi.
  lmask finite = ls.dist < AW_INFINITE_DISTANCE;
  if (L_ANY(finite)) {
    lfloat3 d = l3_sub(l3_add(p, l3_scale(ls.wi, ls.dist)), o);
    lfloat len = sqrt(l3_dot(d, d));
    lmask to_point = finite && len > 0.0f && isfinite(len);
    wi = l3_sel(to_point, l3_div(d, len), wi);
    tmax = L_SEL(to_point, len, tmax);
  }
  PS_SET_F(ps, sh_ox, o.x); PS_SET_F(ps, sh_oy, o.y); PS_SET_F(ps, sh_oz, o.z);
  PS_SET_F(ps, sh_dx, wi.x); PS_SET_F(ps, sh_dy, wi.y); PS_SET_F(ps, sh_dz, wi.z);
  // Stop just short of the light: the sampled point lies on the light itself (which the
  // shadow test skips anyway for analytic lights, see sh_light).
  PS_SET_F(ps, sh_tmax, tmax * (1.0f - 1e-4f));
  PS_SET_F(ps, sh_r, contrib.x); PS_SET_F(ps, sh_g, contrib.y); PS_SET_F(ps, sh_b, contrib.z);
  PS_SET_U(ps, sh_light, light);
  PS_SET_U(ps, flags, PS_LU(ps, flags) | AW_PATH_HAS_SHADOW);
}

// Continues the path along a sampled lobe direction (s.weight already includes the lobe's
// energy share over its selection probability), or ends it. Russian roulette is unbiased
// (Arvo & Kirk 1990, "Particle Transport and Image Synthesis", Sec. 3.3): from rr_depth on,
// survival probability min(1, sqrt(m)) with m = max throughput x eta_scale (the square root
// keeps dim paths alive longer than survival m would: measured 1.1-1.5x the efficiency on the
// race's scenes, docs/architecture.md#russian-roulette); below `cutoff` (render.cutoff, or a
// lobe's cut-off threshold) the survival is m / cutoff, so weak paths stop early
// without bias (docs/material.md §5: the realisation of the cut-off thresholds).
// Returns each path's next queue, AW_Q_RAY or AW_Q_DONE.
AW_FN luint shade_continue(PathRef ps, const RenderParams* rp, lfloat3 p, lfloat3 ng, LobeSample s, lfloat cutoff) {
  const luint done = (luint)(AW_Q_DONE);
  luint bounce = PS_LU(ps, bounce);
  // No depth test here: the ray is traced even from the last allowed vertex, because light
  // sampling at this vertex was MIS-weighted against it; classify_hit ends the path at the
  // next surface instead.
  lmask go = s.flags != 0u;
  lfloat3 wi = s.wi;
  // A direction on the wrong side of the geometric surface (possible with interpolated
  // normals) would leak through the mesh: end the path instead.
  lmask transmit = (s.flags & AW_LOBE_TRANSMISSION) != 0u;
  lfloat cg = l3_dot(wi, ng);
  go = go && !L_SEL(transmit, cg >= 0.0f, cg <= 0.0f);

  lfloat3 thr = l3_mul(ps_throughput(ps), s.weight);
  // Roulette judges the throughput without the radiance scaling of refraction (Pharr, Jakob
  // & Humphreys, pbrt-v4, the path integrator's etaScale; Veach 1997, Sec. 5.2, for the
  // 1/eta^2 itself; docs/architecture.md#russian-roulette): entering glass of index 1.5 scales radiance
  // by 1/2.25 and leaving it undoes that, so a path inside would otherwise be killed 56% of
  // the time for a factor that cancels. Thin walls and reflections leave eta_scale at 1.
  // Only refraction changes eta_scale (lobes/refraction.h); without it the factor is 1 and
  // the field is neither read nor written (generate_camera_ray.h).
  lfloat eta_scale = AW_FEAT_REFRACTION ? PS_LF(ps, eta_scale) * s.eta_scale : (lfloat)(1.0f);
  lfloat m = l3_max3(thr) * eta_scale;
  go = go && m > 0.0f && isfinite(m);
  PS_KEEP(ps, go);
  if (!L_ANY(go)) return done;
  if (AW_FEAT_REFRACTION) PS_SET_F(ps, eta_scale, eta_scale);
  lfloat q = (lfloat)(1.0f);
  q = L_SEL(bounce + 1u >= rp->rr_depth, fmin((lfloat)(1.0f), sqrt(m)), q);
  q = L_SEL(m < cutoff, fmin(q, m / cutoff), q);
  lmask roulette = q < 1.0f;
  if (L_ANY(roulette)) {
    lfloat u = rng_1d(rp_sampler(rp), PS_LU(ps, pixel), PS_LU(ps, sample), bounce, AW_DIM_RR);
    go = go && !(roulette && u >= q);
    PS_KEEP(ps, go);
    if (!L_ANY(go)) return done;
    thr = l3_sel(roulette, l3_div(thr, q), thr);
  }
  ps_set_throughput(ps, thr);
  PS_SET_F(ps, bsdf_pdf, s.pdf);  // the lobe's own density: see the MIS note in shade_surface
  // The ray cone widens by the lobe's angular spread, taken as 1/sqrt(pdf): the solid angle a
  // sample of density pdf stands for (the footprint of path differentials by the sampling
  // density: Suykens & Willems 2001, "Path Differentials and Applications", EGWR, Sec. 4);
  // a delta lobe keeps it (a mirror's curvature is ignored). Bounded by pi/2. Only textures
  // read the cone (classify_texture_point).
  lmask specular = (s.flags & AW_LOBE_SPECULAR) != 0u;
  lmask widen = !specular && s.pdf > 0.0f;
  if (AW_FEAT_TEXTURE && L_ANY(widen)) {
    PathRef pw = ps;
    PS_KEEP(pw, widen);
    PS_SET_F(pw, cone_s, PS_LF(pw, cone_s) + fmin(1.0f / sqrt(s.pdf), 1.5707964f));
  }
  luint flags = PS_LU(ps, flags);
  PS_SET_U(ps, flags, L_SEL(specular, flags | AW_PATH_SPECULAR, flags & ~AW_PATH_SPECULAR));
  ps_set_ray(ps, offset_ray_origin(p, l3_sel(transmit, l3_neg(ng), ng), PS_LF(ps, sp_err)), wi);
  PS_SET_U(ps, bounce, bounce + 1u);
  return L_SEL(go, (luint)(AW_Q_RAY), done);
}

#endif
