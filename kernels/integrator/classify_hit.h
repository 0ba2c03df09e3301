// From: RAY (after intersect_closest) / To: one lobe queue (LOBE + lid), PASS (a cutout: the
// same ray goes on beyond the surface) or DONE.
// Adds what the ray saw if it ended (a light, or the environment), otherwise builds the
// shading point and chooses the lobe that will scatter the path. classify_hit at the end of
// this file reads as the list of its steps.
#ifndef AW_INTEGRATOR_CLASSIFY_HIT_H
#define AW_INTEGRATOR_CLASSIFY_HIT_H

#include "common/rng.h"
#include "common/sampling.h"
#include "integrator/aov.h"
#include "integrator/path_state.h"
#include "integrator/queues.h"
#include "integrator/scene_ref.h"
#include "common/features.h"
#include "common/ray.h"
#include "integrator/light_select.h"
#include "integrator/shading_material.h"
#include "bvh/instance.h"
#include "lobes/fog.h"
#include "material/architectural.h"
#include "material/lobe_list.h"

// The vertex in world space, as a private copy: world geometry's own; an instance's (types/bvh.h)
// with its position, normal and tangent carried through the instance's transform as the loader
// transforms a mesh it does not share (host/scene/geometry.cpp, finalize_mesh): positions and
// tangents by the matrix, normals by its inverse transpose, both renormalised, the tangent made
// orthogonal to the normal again and its handedness flipped by a mirroring transform.
AW_FN VertexData vertex_world(SceneRef sc, uint inst, uint index) {
  VertexData v = sc.verts[index];
  if (!(AW_FEAT_INSTANCE && inst != AW_NONE)) return v;
  const AW_GLOBAL InstanceGpu* in = &sc.insts[inst];
  float3 p = xform_point(in->o2w, make_float3(v.p[0], v.p[1], v.p[2]));
  v.p[0] = p.x; v.p[1] = p.y; v.p[2] = p.z;
  float3 n = xform_normal(in->w2o, make_float3(v.n[0], v.n[1], v.n[2]));
  float ln = dot(n, n);
  if (ln > 0.0f) n = n / sqrt(ln);
  v.n[0] = n.x; v.n[1] = n.y; v.n[2] = n.z;
  float3 t = xform_vector(in->o2w, make_float3(v.t[0], v.t[1], v.t[2]));
  if (v.n[3] != 0.0f) t = t - n * dot(n, t);
  float lt = dot(t, t);
  if (lt > 0.0f) t = t / sqrt(lt);
  v.t[0] = t.x; v.t[1] = t.y; v.t[2] = t.z;
  if (in->flags & AW_INSTANCE_MIRROR) v.t[3] = -v.t[3];
  return v;
}

// The bound on the error of vertex_world's positions for the vertices of one triangle (or a
// sphere's centre), each component of o2w p rounded three times (pbrt-v4 Sec. 6.8.3): gamma(3)
// (|m_i0 x| + |m_i1 y| + |m_i2 z| + |m_i3|), taken at the largest magnitude of each object-space
// coordinate among them. Zero for world geometry, whose vertices are the intersector's own.
AW_FN float3 instance_vertex_error(SceneRef sc, uint inst, const AW_GLOBAL TriangleInfo* tri, int sphere) {
  if (!(AW_FEAT_INSTANCE && inst != AW_NONE)) return make_float3(0.0f, 0.0f, 0.0f);
  float3 a = make_float3(0.0f, 0.0f, 0.0f);
  for (int k = 0; k < (sphere ? 1 : 3); ++k) {
    const AW_GLOBAL VertexData* v = &sc.verts[tri->v[k]];
    a = fmax(a, fabs(make_float3(v->p[0], v->p[1], v->p[2])));
  }
  const AW_GLOBAL float* m = sc.insts[inst].o2w;
  float g = aw_gamma(3.0f);
  return make_float3(g * (fabs(m[0]) * a.x + fabs(m[1]) * a.y + fabs(m[2]) * a.z + fabs(m[3])),
                     g * (fabs(m[4]) * a.x + fabs(m[5]) * a.y + fabs(m[6]) * a.z + fabs(m[7])),
                     g * (fabs(m[8]) * a.x + fabs(m[9]) * a.y + fabs(m[10]) * a.z + fabs(m[11])));
}

AW_FN float3 vertex_position(const VertexData* v) { return make_float3(v->p[0], v->p[1], v->p[2]); }
AW_FN float3 vertex_normal(const VertexData* v) { return make_float3(v->n[0], v->n[1], v->n[2]); }

// Tangent from the UV parametrisation (dP/du of the triangle), made orthogonal to n; falls
// back to an arbitrary frame where the UVs are degenerate. The anisotropic frame for
// anisotropy.orientation = "uv" (constant per triangle, in UV set `set`: anisotropy.uv_set),
// and the mesh tangent's fallback (set 0).
AW_FN float3 triangle_tangent(const VertexData* v0, const VertexData* v1,
                              const VertexData* v2, float3 p0, float3 p1, float3 p2, float3 n, uint set) {
  const float* a = set == 1u ? v0->uv2 : v0->uv;
  const float* b1 = set == 1u ? v1->uv2 : v1->uv;
  const float* b2 = set == 1u ? v2->uv2 : v2->uv;
  float du1 = b1[0] - a[0], dv1 = b1[1] - a[1];
  float du2 = b2[0] - a[0], dv2 = b2[1] - a[1];
  float det = du1 * dv2 - du2 * dv1;
  float3 t;
  if (fabs(det) > 1e-12f) {
    // Solve [dp1 dp2] = [dpdu dpdv] [[du1 du2] [dv1 dv2]] for dpdu (pbrt-v3 Sec. 3.6.2).
    t = ((p1 - p0) * dv2 - (p2 - p0) * dv1) / det;
    t = t - n * dot(n, t);
    float l2 = dot(t, t);
    if (l2 > 1e-20f && isfinite(l2)) return t / sqrt(l2);
  }
  float3 b;
  make_frame(n, &t, &b);
  return t;
}

// Mesh tangent (anisotropy.orientation = "tangent"): the per-vertex tangents (analytic for
// built-in shapes, generated for meshes: host/scene/tangents.h) blended with the hit's
// barycentrics, as the shading normal is, then Gram-Schmidt against the interpolated normal
// n, to which the blend is not exactly orthogonal. The blend of unit vectors has length
// <= 1; below 1e-3 after the projection (tangents that cancel, one along n, or zeros where
// the host generated none) its direction is rounding noise, so the UV frame is used instead.
AW_FN float3 interpolated_tangent(const VertexData* v0, const VertexData* v1,
                                  const VertexData* v2, float b0, float b1, float b2, float3 p0,
                                  float3 p1, float3 p2, float3 n) {
  float3 t = b0 * make_float3(v0->t[0], v0->t[1], v0->t[2]) + b1 * make_float3(v1->t[0], v1->t[1], v1->t[2]) +
             b2 * make_float3(v2->t[0], v2->t[1], v2->t[2]);
  t = t - n * dot(n, t);
  float l2 = dot(t, t);
  if (l2 > 1e-6f && isfinite(l2)) return t / sqrt(l2);
  return triangle_tangent(v0, v1, v2, p0, p1, p2, n, 0u);
}

// The shading point of a triangle hit, both normals facing the side the ray came from.
typedef struct {
  float3 p;       // on the triangle's plane
  float3 n;       // shading normal
  float3 ng;      // geometric normal
  float3 p0, p1, p2;
  float b0, b1, b2;  // barycentrics of p
  int front;      // the ray arrived on the outside of the surface
  int sphere;     // an analytic sphere (p0..p2 and the barycentrics unused): its UV is uv
  float2 uv;
  float err;      // how far rays leaving p are offset along ng (common/ray.h, offset_ray_origin)
} HitPoint;

// The shading point of an analytic sphere hit (bvh/intersect_sphere.h): the point projected
// onto the sphere, normals along the radius (the exact surface: the shading normal is the
// geometric one), its UV by the sphere's parametrisation.
AW_FN HitPoint classify_sphere_point(PathRef ps, const VertexData* c, float3 dir, float3 vert_err) {
  HitPoint h;
  float3 center = make_float3(c->p[0], c->p[1], c->p[2]);
  float3 w = ps_ray_origin(ps) + dir * PS_F(ps, hit_t) - center;
  float l2 = dot(w, w);
  w = l2 > 0.0f ? w / sqrt(l2) : -dir;
  h.p = center + w * c->p[3];
  h.p0 = h.p1 = h.p2 = h.p;
  h.b0 = 1.0f;
  h.b1 = h.b2 = 0.0f;
  h.sphere = 1;
  h.uv = sphere_uv(w, make_float3(c->n[0], c->n[1], c->n[2]), make_float3(c->t[0], c->t[1], c->t[2]));
  h.front = dot(w, dir) < 0.0f;
  h.n = h.ng = h.front ? w : -w;
  h.err = sphere_point_error(h.p, w, c->p[3], vert_err, h.ng);
  return h;
}

// dP/du and dP/dv of an analytic sphere at the hit's UV.
AW_FN void classify_sphere_dpduv(const VertexData* c, HitPoint h, float3* dpdu, float3* dpdv) {
  sphere_dpduv(h.uv, c->p[3], make_float3(c->n[0], c->n[1], c->n[2]), make_float3(c->t[0], c->t[1], c->t[2]), dpdu, dpdv);
}

// Fog: the segment just traced ran inside a foggy object (Beer-Lambert, docs/material.md §3.7).
AW_FN void classify_fog(PathRef ps, SceneRef sc) {
  if (!(AW_FEAT_FOG && PS_U(ps, medium) != AW_NONE)) return;
  const AW_GLOBAL MaterialGpu* fm = &sc.materials[PS_U(ps, medium)];
  float3 tr = fog_transmittance(load_f3(fm->fog_end_color), fm->fog_distance,
                                (fm->flags & AW_MAT_FOG_END_COLOR) != 0u, PS_F(ps, hit_t));
  ps_set_throughput(ps, ps_throughput(ps) * tr);
}

// Emission seen by the ray when it hit a light: MIS against light sampling, which could have
// produced the same direction (Veach 1997, Sec. 9.2). Camera rays and delta bounces cannot
// be light-sampled, so they take the full contribution.
// The selection probability is the one light sampling had at the previous vertex, whose
// position the shading point fields still hold (classify_store_shading_point comes later).
AW_FN float classify_light_mis(PathRef ps, SceneRef sc, const RenderParams* rp, uint light, float3 dir) {
  if (PS_U(ps, bounce) == 0u || (PS_U(ps, flags) & AW_PATH_SPECULAR)) return 1.0f;
  float pdf_light = light_select_pmf(sc, rp, light, ps_sp_position(ps)) *
                    light_pdf(light_load(sc.lights, light), ps_ray_origin(ps), dir, PS_F(ps, hit_t));
  return mis_power(PS_F(ps, bsdf_pdf), pdf_light);
}

AW_FN void classify_light_hit(PathRef ps, SceneRef sc, const RenderParams* rp, uint light, float3 dir, float3 thr) {
  float3 le = light_emitted(light_load(sc.lights, light), dir);
  float w = classify_light_mis(ps, sc, rp, light, dir);
  ps_add_radiance(ps, thr * le * (w * PS_F(ps, emit_scale)));
}

// The ray left the scene. The constant environment is not light-sampled (a uniform sphere
// of directions is what cosine-weighted BSDF sampling already draws well), so BSDF sampling
// takes all of it. The lights at infinity, lights[0, num_infinite), are: the environment map
// and soft suns are MIS-weighted against their light samples exactly as area lights are in
// classify_light_hit (a hard sun is a delta, which no escaping ray can hit).
AW_FN void classify_environment(PathRef ps, SceneRef sc, const RenderParams* rp, float3 dir, float3 thr) {
  float3 le = load_f3p(rp->env_radiance);
  int mis = PS_U(ps, bounce) > 0u && !(PS_U(ps, flags) & AW_PATH_SPECULAR);
  for (uint i = 0u; (AW_FEAT_LIGHT_SUN | AW_FEAT_ENV_MAP) && i < rp->num_infinite; ++i) {
    const AW_GLOBAL LightGpu* l = &sc.lights[i];
    float3 li;
    float pdf;
    if (AW_FEAT_ENV_MAP && l->type == AW_LIGHT_ENV) {
      li = env_radiance(sc.env, rp, dir);
      pdf = mis ? env_pdf(sc.env, rp, dir) : 0.0f;
    } else if (AW_FEAT_LIGHT_SUN && l->type == AW_LIGHT_SUN) {
      pdf = sun_pdf(light_load(sc.lights, i), dir);
      // Outside the disc, a hard sun, or a sun that camera rays do not see (light.visible).
      if (!(pdf > 0.0f) || (PS_U(ps, bounce) == 0u && !(l->flags & AW_LIGHT_VISIBLE))) continue;
      li = load_f3(l->radiance);
    } else {
      continue;
    }
    le += li * (mis ? mis_power(PS_F(ps, bsdf_pdf), l->select_pdf * pdf) : 1.0f);
  }
  ps_add_radiance(ps, thr * le * PS_F(ps, emit_scale));
}

// Textures (texture/texture.h): the hit's UV, and the path's ray cone carried to the hit, its
// width there turned into a footprint in UV units, width / |cos| (the cone's section on the
// surface) times sqrt(UV area / world area) of the triangle (Akenine-Möller et al. 2019, Ray
// Tracing Gems ch. 20, eq. 20.2's texel-to-world ratio). Every surface hit widens the cone,
// textured or not, so that a textured surface seen in a reflection gets the whole path's.
AW_FN void classify_texture_point(PathRef ps, const VertexData* v0, const VertexData* v1,
                                  const VertexData* v2, HitPoint h, float3 dir) {
  float w = PS_F(ps, cone_w) + PS_F(ps, cone_s) * PS_F(ps, hit_t);
  PS_F(ps, cone_w) = w;
  float cos_v = fmax(fabs(dot(h.ng, dir)), 1e-2f);
  if (AW_FEAT_SPHERE && h.sphere) {
    // |dP/du x dP/dv| = 2 pi^2 r^2 sin(theta), the sphere's area per unit UV area.
    float3 dpdu, dpdv;
    classify_sphere_dpduv(v0, h, &dpdu, &dpdv);
    float3 c = cross(dpdu, dpdv);
    float a = sqrt(dot(c, c));
    float f = a > 0.0f ? (w / cos_v) / sqrt(a) : 0.0f;
    // A sphere has one UV set: set 1 reads set 0.
    PS_F(ps, sp_tu) = PS_F(ps, sp_tu2) = h.uv.x;
    PS_F(ps, sp_tv) = PS_F(ps, sp_tv2) = h.uv.y;
    PS_F(ps, sp_tf) = PS_F(ps, sp_tf2) = isfinite(f) ? f : 0.0f;
    return;
  }
  float3 c = cross(h.p1 - h.p0, h.p2 - h.p0);
  float world2 = sqrt(dot(c, c));  // twice the world area
  // Each UV set has its own texel-to-world ratio.
  for (uint set = 0u; set < 2u; ++set) {
    const float* a = set ? v0->uv2 : v0->uv;
    const float* b = set ? v1->uv2 : v1->uv;
    const float* e = set ? v2->uv2 : v2->uv;
    float u = h.b0 * a[0] + h.b1 * b[0] + h.b2 * e[0];
    float v = h.b0 * a[1] + h.b1 * b[1] + h.b2 * e[1];
    float du1 = b[0] - a[0], dv1 = b[1] - a[1];
    float du2 = e[0] - a[0], dv2 = e[1] - a[1];
    float uv2 = fabs(du1 * dv2 - du2 * dv1);  // twice the UV area
    float f = world2 > 0.0f ? (w / cos_v) * sqrt(uv2 / world2) : 0.0f;
    f = isfinite(f) ? f : 0.0f;
    if (set) {
      PS_F(ps, sp_tu2) = u; PS_F(ps, sp_tv2) = v; PS_F(ps, sp_tf2) = f;
    } else {
      PS_F(ps, sp_tu) = u; PS_F(ps, sp_tv) = v; PS_F(ps, sp_tf) = f;
    }
  }
}

// The bump-mapped shading normal (texture/material_textures.h, bump_normal), from the height
// texture's central differences at the hit's UV over a step of one texel or half the
// footprint, whichever is larger; the normal before bumping is kept for disable_bump.
AW_FN float3 classify_bump(PathRef ps, SceneRef sc, const AW_GLOBAL MaterialGpu* m, HitPoint h,
                           const VertexData* v0, const VertexData* v1,
                           const VertexData* v2, float3 dir) {
  PS_F(ps, sp_bx) = h.n.x; PS_F(ps, sp_by) = h.n.y; PS_F(ps, sp_bz) = h.n.z;
  const AW_GLOBAL TexBindingGpu* b = &sc.tex_bindings[m->bump_binding];
  const uint set = b->uv_set;  // the height texture's UV set: its parametrisation is bumped along
  float3 dpdu, dpdv;
  if (AW_FEAT_SPHERE && h.sphere) {
    classify_sphere_dpduv(v0, h, &dpdu, &dpdv);
  } else {
    const float* a = set == 1u ? v0->uv2 : v0->uv;
    const float* bb = set == 1u ? v1->uv2 : v1->uv;
    const float* e = set == 1u ? v2->uv2 : v2->uv;
    float du1 = bb[0] - a[0], dv1 = bb[1] - a[1];
    float du2 = e[0] - a[0], dv2 = e[1] - a[1];
    float det = du1 * dv2 - du2 * dv1;
    if (!(fabs(det) > 1e-20f)) return h.n;  // no UV parametrisation: nothing to bump along
    // dP/du and dP/dv of the triangle (Pharr, Jakob & Humphreys, pbrt-v3, Sec. 3.6.2).
    float3 e1 = h.p1 - h.p0, e2 = h.p2 - h.p0;
    dpdu = (e1 * dv2 - e2 * dv1) / det;
    dpdv = (e2 * du1 - e1 * du2) / det;
  }
  TextureScene ts = scene_texture_ref(sc);
  float3 at = surface_uv_for(ps_surface_uv(ps), b);
  float u = at.x, v = at.y, f = at.z;
  float d = fmax(texture_step(&sc.textures[b->texture]), 0.5f * f);
  float hu = m->bump_scale * (binding_eval_scalar(ts, b, u + d, v, f) - binding_eval_scalar(ts, b, u - d, v, f)) / (2.0f * d);
  float hv = m->bump_scale * (binding_eval_scalar(ts, b, u, v + d, f) - binding_eval_scalar(ts, b, u, v - d, f)) / (2.0f * d);
  float3 nb = bump_normal(h.n, dpdu, dpdv, hu, hv);
  return bump_keep_reflection_above(nb, h.ng, -dir);
}

// `mirrored`: the triangle belongs to an instance whose transform mirrors, which reverses the
// winding in world space (the loader swaps two corners of a mirrored mesh it flattens instead).
AW_FN HitPoint classify_hit_point(PathRef ps, const VertexData* v0, const VertexData* v1,
                                  const VertexData* v2, float3 dir, int mirrored, float3 vert_err) {
  HitPoint h;
  h.b1 = PS_F(ps, hit_u);
  h.b2 = PS_F(ps, hit_v);
  h.b0 = 1.0f - h.b1 - h.b2;
  h.p0 = vertex_position(v0);
  h.p1 = vertex_position(v1);
  h.p2 = vertex_position(v2);
  // Position from barycentrics rather than o + t d: exact on the triangle's plane, so the
  // ray offset below starts from the surface and not from a point slightly behind it.
  h.p = h.b0 * h.p0 + h.b1 * h.p1 + h.b2 * h.p2;
  float3 ng = cross(h.p1 - h.p0, h.p2 - h.p0);
  float ng_len2 = dot(ng, ng);
  // Degenerate triangles are never hit by the watertight test, but a nearly degenerate one
  // can be: fall back to facing the ray.
  ng = ng_len2 > 0.0f ? ng / sqrt(ng_len2) : -dir;
  if (mirrored) ng = -ng;
  float3 nshade = ng;
  int has_n = 0;
  if (v0->n[3] != 0.0f) {
    float3 n = h.b0 * vertex_normal(v0) + h.b1 * vertex_normal(v1) + h.b2 * vertex_normal(v2);
    float n_len2 = dot(n, n);
    if (n_len2 > 0.0f && isfinite(n_len2)) {
      nshade = n / sqrt(n_len2);
      has_n = 1;
    }
  }
  // The outside of the surface: where the shading normals point (robust to winding), or the
  // winding's normal for meshes without normals.
  if (has_n && dot(nshade, ng) < 0.0f) ng = -ng;
  h.front = dot(ng, dir) < 0.0f;
  if (!h.front) {
    ng = -ng;  // from here on both normals face the side the ray came from
    nshade = -nshade;
  }
  // Interpolated normals can face away from the viewer near silhouettes even though the
  // triangle faces it; every lobe would then reject wo. Use the true surface there.
  if (dot(nshade, ng) < 0.0f || dot(nshade, dir) >= 0.0f) nshade = ng;
  h.n = nshade;
  h.ng = ng;
  h.err = triangle_point_error(h.p, h.p0, h.p1, h.p2, h.b0, h.b1, h.b2, vert_err, ng);
  h.sphere = 0;
  h.uv = make_float2(0.0f, 0.0f);
  return h;
}

// Writes the shading point for the lobe stage; returns the tangent (zero unless the material
// is anisotropic: only the reflection frame reads it).
AW_FN float3 classify_store_shading_point(PathRef ps, const AW_GLOBAL MaterialGpu* m, uint material, HitPoint h,
                                          const VertexData* v0, const VertexData* v1,
                                          const VertexData* v2) {
  PS_F(ps, sp_px) = h.p.x; PS_F(ps, sp_py) = h.p.y; PS_F(ps, sp_pz) = h.p.z;
  PS_F(ps, sp_nx) = h.n.x; PS_F(ps, sp_ny) = h.n.y; PS_F(ps, sp_nz) = h.n.z;
  PS_F(ps, sp_gx) = h.ng.x; PS_F(ps, sp_gy) = h.ng.y; PS_F(ps, sp_gz) = h.ng.z;
  PS_F(ps, sp_err) = h.err;
  PS_U(ps, material) = material;
  if (h.front) PS_U(ps, flags) |= AW_PATH_FRONT;
  else PS_U(ps, flags) &= ~AW_PATH_FRONT;
  float3 tangent = make_float3(0.0f, 0.0f, 0.0f);
  if ((AW_FEAT_ANISOTROPY & AW_FEAT_SPHERE) && m->aniso_amount != 0.0f && h.sphere) {
    // Both orientations are dP/du on a sphere (make_sphere's tangents are its direction),
    // taken as the unit (-sin p, 0, -cos p) in the sphere's frame, defined at the poles too.
    float p = 2.0f * M_PI_F * h.uv.x;
    float3 ax = make_float3(v0->n[0], v0->n[1], v0->n[2]), ay = make_float3(v0->t[0], v0->t[1], v0->t[2]);
    tangent = ax * (-sin(p)) + cross(ax, ay) * (-cos(p));
    tangent = normalize(tangent - h.n * dot(h.n, tangent));
    PS_F(ps, sp_tx) = tangent.x; PS_F(ps, sp_ty) = tangent.y; PS_F(ps, sp_tz) = tangent.z;
  } else if (AW_FEAT_ANISOTROPY && m->aniso_amount != 0.0f) {
    tangent = m->aniso_orientation == AW_ANISO_UV
                  ? triangle_tangent(v0, v1, v2, h.p0, h.p1, h.p2, h.n, (m->flags & AW_MAT_ANISO_UV_SET1) ? 1u : 0u)
                  : interpolated_tangent(v0, v1, v2, h.b0, h.b1, h.b2, h.p0, h.p1, h.p2, h.n);
    PS_F(ps, sp_tx) = tangent.x; PS_F(ps, sp_ty) = tangent.y; PS_F(ps, sp_tz) = tangent.z;
  }
  return tangent;
}

// Lobe choice (docs/material.md §2): in proportion to each lobe's share of the energy, the
// reflection lobes' Fresnel taken at the microfacet their sample will use: the same frame
// and the same random numbers as shade_surface (material_lobe_weights_sampled says why).
// Materials without reflection need neither the frame nor the random numbers. Returns the
// lobe's queue, or DONE when no lobe has energy.
AW_FN int classify_choose_lobe(PathRef ps, const AW_GLOBAL MaterialGpu* m, const RenderParams* rp, float3 dir,
                               float3 n, float3 tangent, int front) {
  uint bounce = PS_U(ps, bounce);
  LobeWeights lw;
  if (AW_FEAT_REFLECTION && (m->refl[0].weight > 0.0f || m->refl[1].weight > 0.0f)) {
    // The reflection's own normal (with bump mapping, the one its disable_bump chooses).
    n = shading_normal_for_lobe(ps, m, AW_LID_REFLECTION);
    float3 rt, rb;
    material_reflection_frame(m, n, tangent, &rt, &rb);
    float2 u_bsdf = rng_2d(rp_sampler(rp), PS_U(ps, pixel), PS_U(ps, sample), bounce, AW_DIM_BSDF);
    lw = material_lobe_weights_sampled(m, frame_to_local(-dir, rt, rb, n), u_bsdf, front);
  } else {
    lw = material_lobe_weights_f(m, 0.0f, 0.0f, front);
  }
  // Refraction past its depth returns black (docs/material.md §5).
  if ((PS_U(ps, depths) >> 16) >= m->refr_depth) lw.prob[AW_LID_REFRACTION] = 0.0f;
  float total = 0.0f;
  for (uint i = 0; i < AW_LID_COUNT; ++i) total += lw.prob[i];
  if (!(total > 0.0f)) return AW_Q_DONE;
  uint with_energy = 0u;
  for (uint i = 0; i < AW_LID_COUNT; ++i) {
    lw.prob[i] /= total;
    with_energy += lw.prob[i] > 0.0f;
  }
  // One lobe with energy (a Lambert surface, a plain mirror): material_pick_lobe returns it for
  // any u, so no random number is drawn for it (a Sobol' sample costs about as much as the rest
  // of the choice; docs/performance.md, "Random numbers only where a choice exists").
  float u_lobe = with_energy > 1u ? rng_1d(rp_sampler(rp), PS_U(ps, pixel), PS_U(ps, sample), bounce, AW_DIM_LOBE)
                                  : 0.0f;
  uint lid = material_pick_lobe(&lw, u_lobe);
  if (lid >= AW_LID_COUNT) return AW_Q_DONE;
  if (!lobe_compiled(lid)) {  // unreachable after the material check in classify_hit; kept as a guard
    PS_U(ps, flags) |= AW_PATH_MISSING_FEATURE;
    return AW_Q_DONE;
  }
  float3 w = lw.scale[lid] / lw.prob[lid];
  PS_F(ps, lobe_wr) = w.x; PS_F(ps, lobe_wg) = w.y; PS_F(ps, lobe_wb) = w.z;
  PS_U(ps, lobe) = lid;
  return AW_Q_LOBE + (int)lid;
}

AW_FN int classify_hit_body(PathRef ps, SceneRef sc, const RenderParams* rp) {
  float3 dir = ps_ray_dir(ps);
  classify_fog(ps, sc);
  float3 thr = ps_throughput(ps);

  // 1. The ray ended: on a light, or in the environment.
  uint light = PS_U(ps, hit_light);
  if (light != AW_NONE) {
    classify_light_hit(ps, sc, rp, light, dir, thr);
    return AW_Q_DONE;
  }
  if (PS_U(ps, hit_prim) == AW_NONE) {
    classify_environment(ps, sc, rp, dir, thr);
    return AW_Q_DONE;
  }

  // 2. The surface it hit.
  const AW_GLOBAL TriangleInfo* tri = &sc.tri_info[PS_U(ps, hit_prim)];
  const AW_GLOBAL MaterialGpu* m = &sc.materials[tri->material];
  // The vertices in world space (an instance's carried there by its transform).
  uint inst = PS_U(ps, hit_inst);
  int mirrored = AW_FEAT_INSTANCE && inst != AW_NONE && (sc.insts[inst].flags & AW_INSTANCE_MIRROR);
  // An analytic sphere (types/bvh.h) has one vertex, its centre: v1 = v2 = v0.
  int sphere = AW_FEAT_SPHERE && tri->v[1] == AW_SPHERE_MARK;
  VertexData w0 = vertex_world(sc, inst, tri->v[0]);
  VertexData w1 = vertex_world(sc, inst, sphere ? tri->v[0] : tri->v[1]);
  VertexData w2 = vertex_world(sc, inst, tri->v[2]);
  const VertexData* v0 = &w0;
  const VertexData* v1 = &w1;
  const VertexData* v2 = &w2;
  float3 vert_err = instance_vertex_error(sc, inst, tri, sphere);
  HitPoint h = sphere ? classify_sphere_point(ps, v0, dir, vert_err)
                      : classify_hit_point(ps, v0, v1, v2, dir, mirrored, vert_err);

  // 3. The feature guard. The host derived the features from this very scene, so this cannot
  // happen; if it does, it is counted and the host refuses the image rather than render it wrong.
  if (material_uses_missing_feature(m)) {
    PS_U(ps, flags) |= AW_PATH_MISSING_FEATURE;
    return AW_Q_DONE;
  }

  // 4. Textures: the hit's UV and the path's footprint there, the material with its textured
  // inputs applied (integrator/shading_material.h), the bump-mapped normal. (Cutout holes were
  // never hit: the traversal skips them, integrator/ray_cast.h.)
  if (AW_FEAT_TEXTURE) {
    classify_texture_point(ps, v0, v1, v2, h, dir);
    PS_U(ps, material) = tri->material;
    m = shading_material(ps, sc);
    if (AW_FEAT_BUMP && m->bump_binding != AW_NONE) h.n = classify_bump(ps, sc, m, h, v0, v1, v2, dir);
  }
  // The AOVs of the first hit (integrator/aov.h): the ray's direction is a unit vector, so
  // hit_t is the distance from the camera.
  if (aov_on(rp) && PS_U(ps, bounce) == 0u)
    aov_surface(ps, rp, material_albedo(m, fabs(dot(dir, h.n)), h.front), h.n, h.p, PS_F(ps, hit_t), tri->material);

  // 5. A path that has used up its scattering events ends here. (Its last ray was still
  // traced: light it finds completes the MIS pair of the previous vertex's light sample.)
  // Ambient occlusion runs only where the path scatters on (ambient_occlusion.h).
  int ends = PS_U(ps, bounce) >= rp->max_depth || (PS_U(ps, flags) & AW_PATH_EMITTERS_ONLY);
  int ao = AW_FEAT_AO && m->ao_samples > 0u && !ends;

  // 6. Incandescence: emission added to the shaded result at every hit. Found by BSDF sampling
  // alone (weight 1), unless the triangle belongs to a light-sampled object: then it is a
  // light, MIS-weighted against the light samples that could have found it, and AO never dims
  // it. Otherwise AO in multiply mode with apply_to_incandescence darkens it: the AO stage
  // adds it then.
  uint tri_light = triangle_light(sc, rp, PS_U(ps, hit_prim));
  if (AW_FEAT_INCANDESCENCE &&
      (tri_light != AW_NONE || !(ao && (m->ao_flags & AW_AO_MULTIPLY) && (m->ao_flags & AW_AO_INCANDESCENCE)))) {
    float3 inc = load_f3(m->incandescent);
    float w = tri_light != AW_NONE ? classify_light_mis(ps, sc, rp, tri_light, dir) : 1.0f;
    if (max3(inc) > 0.0f) ps_add_radiance(ps, thr * inc * (w * PS_F(ps, emit_scale)));
  }
  if (ends) return AW_Q_DONE;

  // 7. The shading point for the lobe stage, and the lobe that scatters the path; with AO, the
  // AO stage first, which hands the path on to that lobe (or ends it when there is none).
  float3 tangent = classify_store_shading_point(ps, m, tri->material, h, v0, v1, v2);
  int q = classify_choose_lobe(ps, m, rp, dir, h.n, tangent, h.front);
  if (!ao) return q;
  if (q == AW_Q_DONE) PS_U(ps, lobe) = AW_NONE;
  return (PS_U(ps, flags) & AW_PATH_MISSING_FEATURE) ? q : AW_Q_AO;
}

// classify_hit_body, and the AOVs' record of what the first hit gathered (integrator/aov.h).
AW_FN int classify_hit(PathRef ps, SceneRef sc, const RenderParams* rp) {
  uint bounce = PS_U(ps, bounce);
  int q = classify_hit_body(ps, sc, rp);
  aov_first_classified(ps, rp, bounce);
  return q;
}

#endif
