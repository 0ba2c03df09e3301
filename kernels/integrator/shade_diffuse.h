// From: DIFFUSE / To: RAY or DONE (and SHADOW when a light sample can contribute).
// Next-event estimation with MIS against cosine sampling, then a cosine-sampled bounce.
#ifndef AW_INTEGRATOR_SHADE_DIFFUSE_H
#define AW_INTEGRATOR_SHADE_DIFFUSE_H

#include "integrator/shade_common.h"
#include "lobes/diffuse.h"

AW_FN int shade_diffuse(PathRef ps, SceneRef sc, const RenderParams* rp) {
  float3 p = ps_sp_position(ps);
  float3 n = ps_sp_normal(ps);
  float3 ng = ps_sp_geo_normal(ps);
  float3 t, b;
  make_frame(n, &t, &b);
  float3 wo = frame_to_local(-ps_ray_dir(ps), t, b, n);
  const AW_GLOBAL MaterialGpu* m = &sc.materials[PS_U(ps, material)];
  float3 albedo = load_f3(m->diffuse_color);
  float lobe_pdf = PS_F(ps, lobe_pdf);
  PS_U(ps, flags) &= ~AW_PATH_HAS_SHADOW;

  if (rp->num_lights > 0u) {
    uint light;
    float pdf_light;
    LightSample ls = shade_pick_light(ps, sc, rp, p, &light, &pdf_light);
    // Both normals must see the light: the shading normal for the BSDF, the geometric one
    // so that light never arrives through the back of the surface.
    if (pdf_light > 0.0f && dot(ls.wi, ng) > 0.0f) {
      float3 wi = frame_to_local(ls.wi, t, b, n);
      float3 f = lobe_diffuse_eval(albedo, wo, wi);
      // The path scatters through ONE lobe, chosen with probability lobe_pdf, so this is a
      // one-sample estimate of that lobe's share (divide by lobe_pdf). Within the lobe, light
      // sampling is MIS-weighted against the lobe's own sampling; classify_hit weighs
      // emission found by the lobe's ray with the same two densities.
      float w = ls.is_delta ? 1.0f : mis_power(pdf_light, lobe_diffuse_pdf(wo, wi));
      float3 contrib = ps_throughput(ps) * f * ls.le * (w / (pdf_light * lobe_pdf));
      if (max3(contrib) > 0.0f) shade_emit_shadow(ps, p, ng, ls, light, contrib);
    }
  }
  float2 u = rng_2d(rp->seed, PS_U(ps, pixel), PS_U(ps, sample), PS_U(ps, bounce), AW_DIM_BSDF);
  LobeSample s = lobe_diffuse_sample(albedo, wo, u);
  s.wi = frame_to_world(s.wi, t, b, n);
  // gi off (the documentation's "no GI" examples): no indirect diffuse. The bounce is still
  // traced, but only to find lights (the MIS partner of the light sample above).
  if (!rp->gi) PS_U(ps, flags) |= AW_PATH_EMITTERS_ONLY;
  return shade_continue(ps, rp, p, ng, s);
}

#endif
