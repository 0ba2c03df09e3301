// From: RAY (after intersect_closest) / To: one lobe queue (DIFFUSE) or DONE.
// Adds what the ray saw if it ended (a light, or the environment), otherwise builds the
// shading point and chooses the lobe that will scatter the path.
#ifndef AW_INTEGRATOR_CLASSIFY_HIT_H
#define AW_INTEGRATOR_CLASSIFY_HIT_H

#include "common/rng.h"
#include "common/sampling.h"
#include "integrator/path_state.h"
#include "integrator/queues.h"
#include "integrator/scene_ref.h"
#include "lights/lights.h"

AW_FN float3 vertex_position(const AW_GLOBAL VertexData* v) { return make_float3(v->p[0], v->p[1], v->p[2]); }
AW_FN float3 vertex_normal(const AW_GLOBAL VertexData* v) { return make_float3(v->n[0], v->n[1], v->n[2]); }

AW_FN int classify_hit(PathRef ps, SceneRef sc, const RenderParams* rp) {
  float3 dir = ps_ray_dir(ps);
  float3 thr = ps_throughput(ps);
  uint bounce = PS_U(ps, bounce);
  uint light = PS_U(ps, hit_light);

  if (light != AW_NONE) {
    // Emission seen by a BSDF-sampled ray: MIS against light sampling, which could have
    // produced the same direction (Veach 1997, Sec. 9.2). Camera rays and delta bounces
    // cannot be light-sampled, so they take the full contribution.
    const AW_GLOBAL LightGpu* l = &sc.lights[light];
    float3 le = light_emitted(l, dir);
    float w = 1.0f;
    if (bounce > 0u && !(PS_U(ps, flags) & AW_PATH_SPECULAR)) {
      float pdf_light = l->select_pdf * light_pdf(l, ps_ray_origin(ps), dir, PS_F(ps, hit_t));
      w = mis_power(PS_F(ps, bsdf_pdf), pdf_light);
    }
    ps_add_radiance(ps, thr * le * w);
    return AW_Q_DONE;
  }
  if (PS_U(ps, hit_prim) == AW_NONE) {
    // Constant environment: no light sampling for it yet, so BSDF sampling takes it all.
    ps_add_radiance(ps, thr * load_f3p(rp->env_radiance));
    return AW_Q_DONE;
  }
  // A surface. A path that has used up its scattering events ends here. (Its last ray was
  // still traced: light it finds completes the MIS pair of the previous vertex's light
  // sample, which was weighted assuming this ray would be traced.)
  if (bounce >= rp->max_depth || (PS_U(ps, flags) & AW_PATH_EMITTERS_ONLY)) return AW_Q_DONE;

  const AW_GLOBAL TriangleInfo* tri = &sc.tri_info[PS_U(ps, hit_prim)];
  const AW_GLOBAL VertexData* v0 = &sc.verts[tri->v[0]];
  const AW_GLOBAL VertexData* v1 = &sc.verts[tri->v[1]];
  const AW_GLOBAL VertexData* v2 = &sc.verts[tri->v[2]];
  float b1 = PS_F(ps, hit_u), b2 = PS_F(ps, hit_v), b0 = 1.0f - b1 - b2;
  float3 p0 = vertex_position(v0), p1 = vertex_position(v1), p2 = vertex_position(v2);
  // Position from barycentrics rather than o + t d: exact on the triangle's plane, so the
  // ray offset below starts from the surface and not from a point slightly behind it.
  float3 p = b0 * p0 + b1 * p1 + b2 * p2;
  float3 ng = cross(p1 - p0, p2 - p0);
  float ng_len2 = dot(ng, ng);
  // Degenerate triangles are never hit by the watertight test, but a nearly degenerate one
  // can be: fall back to facing the ray.
  ng = ng_len2 > 0.0f ? ng / sqrt(ng_len2) : -dir;
  if (dot(ng, dir) > 0.0f) ng = -ng;  // face the side the ray came from
  float3 ns = ng;
  if (v0->n[3] != 0.0f) {
    float3 n = b0 * vertex_normal(v0) + b1 * vertex_normal(v1) + b2 * vertex_normal(v2);
    float n_len2 = dot(n, n);
    if (n_len2 > 0.0f && isfinite(n_len2)) {
      n = n / sqrt(n_len2);
      ns = dot(n, ng) < 0.0f ? -n : n;  // interpolated normals follow the facing of ng
    }
  }
  PS_F(ps, sp_px) = p.x; PS_F(ps, sp_py) = p.y; PS_F(ps, sp_pz) = p.z;
  PS_F(ps, sp_nx) = ns.x; PS_F(ps, sp_ny) = ns.y; PS_F(ps, sp_nz) = ns.z;
  PS_F(ps, sp_gx) = ng.x; PS_F(ps, sp_gy) = ng.y; PS_F(ps, sp_gz) = ng.z;
  PS_U(ps, material) = tri->material;

  // Lobe choice. The foundation's material has one lobe; the material issue picks among the
  // lobes by their weights here (AW_DIM_LOBE) and records the probability in lobe_pdf.
  const AW_GLOBAL MaterialGpu* m = &sc.materials[tri->material];
  if (max3(load_f3(m->diffuse_color)) <= 0.0f) return AW_Q_DONE;
  PS_F(ps, lobe_pdf) = 1.0f;
  return AW_Q_DIFFUSE;
}

#endif
