// Choosing lights and finding them, over the scene: the alias table alone (few lights), or the
// lights at infinity's alias table beside the light tree (many lights, lights/light_tree.h),
// the two chosen between by their power share (RenderParams.tree_prob). The probability a
// light was chosen with is what MIS reads on both sides (light_select_pmf).
#ifndef AW_INTEGRATOR_LIGHT_SELECT_H
#define AW_INTEGRATOR_LIGHT_SELECT_H

#include "common/features.h"
#include "common/rng.h"
#include "integrator/path_state.h"
#include "integrator/scene_ref.h"
#include "lights/environment.h"
#include "lights/light_tree.h"
#include "lights/lights.h"

AW_FN int light_tree_used(const RenderParams* rp) { return AW_FEAT_LIGHT_TREE && rp->num_tree_nodes > 0u; }

// The light a triangle is (objects[].light_sampling), or AW_NONE.
AW_FN luint triangle_light(SceneRef sc, const RenderParams* rp, luint prim) {
  if (!(AW_FEAT_LIGHT_MESH && rp->has_mesh_lights)) return (luint)(AW_NONE);
  return L_GATHER_V(uint, sc.tri_light, prim);
}

// A light for next-event estimation at p from one uniform number, and its probability;
// AW_NONE when the tree finds no light that can reach p. On lanes (common/lanes.h) the alias
// table only: the light tree is one path per call still (light_tree.h), so a program with
// W > 1 lanes is built only for scenes without it.
AW_FN luint light_choose(SceneRef sc, const RenderParams* rp, lfloat3 p, lfloat u, lfloat* select_pmf) {
#if AW_LANES == 1
  if (light_tree_used(rp)) {
    if (u < rp->tree_prob) {
      float pmf;
      uint li = light_tree_sample(sc.light_tree, p, fmin(u / rp->tree_prob, 0.99999994f), &pmf);
      *select_pmf = rp->tree_prob * pmf;
      return li;
    }
    // The lights at infinity: their alias table (built over them alone, lights[0, num_infinite)).
    uint li = light_pick(sc.lights, rp->num_infinite, fmin((u - rp->tree_prob) / (1.0f - rp->tree_prob), 0.99999994f));
    *select_pmf = sc.lights[li].select_pdf;
    return li;
  }
#endif
  luint li = light_pick(sc.lights, rp->num_lights, u);
  *select_pmf = L_TABLE(float, sc.lights, rp->num_lights, li, select_pdf);
  return li;
}

// The probability light_choose picks light `li` at p (the MIS partner of a BSDF ray that hits
// it). On lanes the alias table's only, as light_choose.
AW_FN lfloat light_select_pmf(SceneRef sc, const RenderParams* rp, luint li, lfloat3 p) {
#if AW_LANES == 1
  if (light_tree_used(rp) && li >= rp->num_infinite) return rp->tree_prob * light_tree_pmf(sc.light_tree, &sc.lights[li], p);
#endif
  return L_TABLE(float, sc.lights, rp->num_lights, li, select_pdf);
}

// The closest analytic light along a ray (lights_intersect's contract), through the tree's
// boxes when there is one (one path per call: a lane program is built only for scenes
// without the tree).
AW_FN lint scene_lights_intersect(SceneRef sc, const RenderParams* rp, lfloat3 org, lfloat3 dir, lfloat t_min, lfloat* t,
                                  lmask camera_ray, lint skip) {
#if AW_LANES == 1
  if (light_tree_used(rp)) return light_tree_intersect(sc.light_tree, sc.lights, org, dir, t_min, t, camera_ray, skip);
#endif
  return lights_intersect(sc.lights, rp->num_lights, org, dir, t_min, t, camera_ray, skip);
}

// Picks a light and a point on it. Returns the sample and writes the pick into *light and
// the combined (selection × solid angle) pdf into *pdf; pdf 0 = nothing to connect to.
// On lanes: the analytic lights only (the environment map is sampled one path per call,
// lights/environment.h, so a program with W > 1 lanes is built only for scenes without it).
AW_FN LightSample shade_pick_light(PathRef ps, SceneRef sc, const RenderParams* rp, lfloat3 p,
                                   luint* light, lfloat* pdf) {
  luint pixel = PS_LU(ps, pixel), sample = PS_LU(ps, sample), bounce = PS_LU(ps, bounce);
  // One light: light_pick returns it for any u (its alias entry keeps it with probability 1),
  // so no random number is drawn for the pick.
  lfloat u_pick = (lfloat)(0.0f);
  if (rp->num_lights > 1u) u_pick = rng_1d(rp_sampler(rp), pixel, sample, bounce, AW_DIM_LIGHT_PICK);
  lfloat select_pmf;  // (not `select`: that would hide OpenCL's select(), which L_SEL is)
  *light = light_choose(sc, rp, p, u_pick, &select_pmf);
  lmask none = *light == AW_NONE;  // the tree found no light that can reach p
  LightSample nothing;
  nothing.pdf = (lfloat)(0.0f);
  nothing.is_delta = (lmask)(0);
  nothing.dist = (lfloat)(0.0f);
  nothing.le = l3_splat((lfloat)(0.0f));
  nothing.wi = make_lfloat3((lfloat)(0.0f), (lfloat)(0.0f), (lfloat)(1.0f));
  *light = L_SEL(none, (luint)(0u), *light);
  if (L_ALL(none)) {
    *pdf = (lfloat)(0.0f);
    return nothing;
  }
  LightL l = light_load(sc.lights, rp->num_lights, *light);
  lfloat2 u = rng_2d(rp_sampler(rp), pixel, sample, bounce, AW_DIM_LIGHT);
  LightSample ls;
#if AW_LANES == 1
  if (AW_FEAT_ENV_MAP && l.type == AW_LIGHT_ENV) {
    // The map's own 2-D distribution; the radiance of the very texel drawn (environment.h).
    uint texel;
    ls.wi = env_sample(sc.env, rp, u, &ls.pdf, &texel);
    ls.le = env_texel_radiance(sc.env, texel);
    ls.dist = AW_INFINITE_DISTANCE;
    ls.is_delta = 0;
  } else {
    ls = light_sample(l, p, u);
  }
#else
  ls = light_sample(l, p, u);
#endif
  ls = light_sample_sel(none, nothing, ls);
  *pdf = L_SEL(none, (lfloat)(0.0f), ls.pdf * select_pmf);
  return ls;
}

#endif
