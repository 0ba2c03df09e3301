// From: RAY (after intersect_closest) / To: one lobe queue (LOBE + lid), PASS (a cutout: the
// same ray goes on beyond the surface) or DONE.
// Adds what the ray saw if it ended (a light, or the environment), otherwise builds the
// shading point and chooses the lobe that will scatter the path. classify_hit at the end of
// this file reads as the list of its steps.
// Written on lanes (common/lanes.h): at W > 1 a block of W paths, those of PS_LIVE. What is
// still one path per call is left out there with #if AW_LANES == 1: fog, instances, textures
// and bump maps, AOVs, anisotropic tangents, the reflection lobes' sampled split for Beckmann
// and Ashikhmin-Shirley lobes (material_sampled_fresnel), the light tree's and the environment
// map's densities; the host builds this stage on lanes only for
// scenes that need none of them (host/render/wavefront.cpp, build_lanes_program).
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

#if AW_LANES == 1
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

#endif

// The shading point of a triangle hit, both normals facing the side the ray came from.
typedef struct {
  lfloat3 p;       // on the triangle's plane
  lfloat3 n;       // shading normal
  lfloat3 ng;      // geometric normal
  lfloat3 p0, p1, p2;
  lfloat b0, b1, b2;  // barycentrics of p
  lmask front;     // the ray arrived on the outside of the surface
  lmask sphere;    // an analytic sphere (p0..p2 and the barycentrics unused): its UV is uv
  lfloat2 uv;
  lfloat err;      // how far rays leaving p are offset along ng (common/ray.h, offset_ray_origin)
} HitPoint;

// Per lane: a when m, else b.
AW_FN HitPoint hit_point_sel(lmask m, HitPoint a, HitPoint b) {
  HitPoint h;
  h.p = l3_sel(m, a.p, b.p);
  h.n = l3_sel(m, a.n, b.n);
  h.ng = l3_sel(m, a.ng, b.ng);
  h.p0 = l3_sel(m, a.p0, b.p0);
  h.p1 = l3_sel(m, a.p1, b.p1);
  h.p2 = l3_sel(m, a.p2, b.p2);
  h.b0 = L_SEL(m, a.b0, b.b0);
  h.b1 = L_SEL(m, a.b1, b.b1);
  h.b2 = L_SEL(m, a.b2, b.b2);
  h.front = L_SEL(m, a.front, b.front);
  h.sphere = L_SEL(m, a.sphere, b.sphere);
  h.uv = make_lfloat2(L_SEL(m, a.uv.x, b.uv.x), L_SEL(m, a.uv.y, b.uv.y));
  h.err = L_SEL(m, a.err, b.err);
  return h;
}

// The hit primitive's vertices in world space: positions, shading normals (has_n: the mesh
// has them), the bound on their own error (an instance's transform), whether the instance
// mirrors, and for an analytic sphere (types/bvh.h: one vertex, its centre; v1 = v2 = v0)
// its radius. At W = 1 also the whole vertices, whose UVs and tangents textures and
// anisotropy read; on lanes the positions and normals are gathered per lane (no instances).
typedef struct {
  lfloat3 p[3];
  lfloat3 n[3];
  lmask has_n;
  lfloat3 vert_err;
  lmask mirrored;
  lmask sphere;
  lfloat radius;
#if AW_LANES == 1
  VertexData v[3];
#endif
} HitVertices;

AW_FN HitVertices classify_vertices(PathRef ps, SceneRef sc, luint prim) {
  HitVertices hv;
#if AW_LANES == 1
  const AW_GLOBAL TriangleInfo* tri = &sc.tri_info[prim];
  uint inst = AW_FEAT_INSTANCE ? PS_U(ps, hit_inst) : AW_NONE;
  hv.mirrored = AW_FEAT_INSTANCE && inst != AW_NONE && (sc.insts[inst].flags & AW_INSTANCE_MIRROR);
  hv.sphere = AW_FEAT_SPHERE && tri->v[1] == AW_SPHERE_MARK;
  hv.v[0] = vertex_world(sc, inst, tri->v[0]);
  hv.v[1] = vertex_world(sc, inst, hv.sphere ? tri->v[0] : tri->v[1]);
  hv.v[2] = vertex_world(sc, inst, tri->v[2]);
  hv.vert_err = instance_vertex_error(sc, inst, tri, hv.sphere);
  for (int k = 0; k < 3; ++k) {
    hv.p[k] = vertex_position(&hv.v[k]);
    hv.n[k] = vertex_normal(&hv.v[k]);
  }
  hv.has_n = hv.v[0].n[3] != 0.0f;
  hv.radius = hv.v[0].p[3];
#else
  luint i0 = L_GATHER(uint, sc.tri_info, prim, v[0]);
  luint i1 = L_GATHER(uint, sc.tri_info, prim, v[1]);
  luint i2 = L_GATHER(uint, sc.tri_info, prim, v[2]);
  hv.mirrored = (lmask)(0);
  hv.sphere = AW_FEAT_SPHERE && i1 == AW_SPHERE_MARK;
  i1 = L_SEL(hv.sphere, i0, i1);
  hv.vert_err = l3_splat((lfloat)(0.0f));
  hv.p[0] = L_GATHER3(sc.verts, i0, p);
  hv.p[1] = L_GATHER3(sc.verts, i1, p);
  hv.p[2] = L_GATHER3(sc.verts, i2, p);
  hv.n[0] = L_GATHER3(sc.verts, i0, n);
  hv.n[1] = L_GATHER3(sc.verts, i1, n);
  hv.n[2] = L_GATHER3(sc.verts, i2, n);
  hv.has_n = L_GATHER(float, sc.verts, i0, n[3]) != 0.0f;
  hv.radius = L_GATHER(float, sc.verts, i0, p[3]);
#endif
  return hv;
}

// The shading point of an analytic sphere hit (bvh/intersect_sphere.h): the point projected
// onto the sphere, normals along the radius (the exact surface: the shading normal is the
// geometric one), its UV by the sphere's parametrisation (at W = 1: only textures and
// anisotropy read it).
AW_FN HitPoint classify_sphere_point(PathRef ps, const HitVertices* hv, lfloat3 dir) {
  HitPoint h;
  lfloat3 center = hv->p[0];
  lfloat3 w = l3_sub(l3_add(ps_ray_origin(ps), l3_scale(dir, PS_LF(ps, hit_t))), center);
  lfloat l2 = l3_dot(w, w);
  w = l3_sel(l2 > 0.0f, l3_div(w, sqrt(l2)), l3_neg(dir));
  h.p = l3_add(center, l3_scale(w, hv->radius));
  h.p0 = h.p1 = h.p2 = h.p;
  h.b0 = (lfloat)(1.0f);
  h.b1 = h.b2 = (lfloat)(0.0f);
  h.sphere = hv->sphere;
#if AW_LANES == 1
  const VertexData* c = &hv->v[0];
  h.uv = sphere_uv(w, make_float3(c->n[0], c->n[1], c->n[2]), make_float3(c->t[0], c->t[1], c->t[2]));
#else
  h.uv = make_lfloat2((lfloat)(0.0f), (lfloat)(0.0f));
#endif
  h.front = l3_dot(w, dir) < 0.0f;
  h.n = h.ng = l3_sel(h.front, w, l3_neg(w));
  h.err = sphere_point_error(h.p, w, hv->radius, hv->vert_err, h.ng);
  return h;
}

#if AW_LANES == 1
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

#endif

// Emission seen by the ray when it hit a light: MIS against light sampling, which could have
// produced the same direction (Veach 1997, Sec. 9.2). Camera rays and delta bounces cannot
// be light-sampled, so they take the full contribution.
// The selection probability is the one light sampling had at the previous vertex, whose
// position the shading point fields still hold (classify_store_shading_point comes later).
AW_FN lfloat classify_light_mis(PathRef ps, SceneRef sc, const RenderParams* rp, luint light, lfloat3 dir) {
  lmask full = PS_LU(ps, bounce) == 0u || (PS_LU(ps, flags) & AW_PATH_SPECULAR) != 0u;
  if (L_ALL(full)) return (lfloat)(1.0f);
  lfloat pdf_light = light_select_pmf(sc, rp, light, ps_sp_position(ps)) *
                     light_pdf(light_load(sc.lights, rp->num_lights, light), ps_ray_origin(ps), dir, PS_LF(ps, hit_t));
  return L_SEL(full, (lfloat)(1.0f), mis_power(PS_LF(ps, bsdf_pdf), pdf_light));
}

AW_FN void classify_light_hit(PathRef ps, SceneRef sc, const RenderParams* rp, luint light, lfloat3 dir, lfloat3 thr) {
  lfloat3 le = light_emitted(light_load(sc.lights, rp->num_lights, light), dir);
  lfloat w = classify_light_mis(ps, sc, rp, light, dir);
  ps_add_radiance(ps, l3_scale(l3_mul(thr, le), w * PS_LF(ps, emit_scale)));
}

// The ray left the scene. The constant environment is not light-sampled (a uniform sphere
// of directions is what cosine-weighted BSDF sampling already draws well), so BSDF sampling
// takes all of it. The lights at infinity, lights[0, num_infinite), are: the environment map
// and soft suns are MIS-weighted against their light samples exactly as area lights are in
// classify_light_hit (a hard sun is a delta, which no escaping ray can hit). On lanes every
// lane looks at the same light i; the environment map's density is one path per call.
AW_FN void classify_environment(PathRef ps, SceneRef sc, const RenderParams* rp, lfloat3 dir, lfloat3 thr) {
  lfloat3 le = make_lfloat3((lfloat)(rp->env_radiance[0]), (lfloat)(rp->env_radiance[1]), (lfloat)(rp->env_radiance[2]));
  lmask mis = PS_LU(ps, bounce) > 0u && (PS_LU(ps, flags) & AW_PATH_SPECULAR) == 0u;
  for (uint i = 0u; (AW_FEAT_LIGHT_SUN | AW_FEAT_ENV_MAP) && i < rp->num_infinite; ++i) {
    const AW_GLOBAL LightGpu* l = &sc.lights[i];
    lfloat3 li;
    lfloat pdf;
    lmask seen;
#if AW_LANES == 1
    if (AW_FEAT_ENV_MAP && l->type == AW_LIGHT_ENV) {
      li = env_radiance(sc.env, rp, dir);
      pdf = mis ? env_pdf(sc.env, rp, dir) : 0.0f;
      seen = 1;
    } else
#endif
    if (AW_FEAT_LIGHT_SUN && l->type == AW_LIGHT_SUN) {
      pdf = sun_pdf(light_load(sc.lights, rp->num_lights, (luint)(i)), dir);
      // Outside the disc, a hard sun, or a sun that camera rays do not see (light.visible).
      seen = pdf > 0.0f && !(PS_LU(ps, bounce) == 0u && (l->flags & AW_LIGHT_VISIBLE) == 0u);
      if (!L_ANY(seen)) continue;
      li = make_lfloat3((lfloat)(l->radiance[0]), (lfloat)(l->radiance[1]), (lfloat)(l->radiance[2]));
    } else {
      continue;
    }
    lfloat w = L_SEL(mis, mis_power(PS_LF(ps, bsdf_pdf), l->select_pdf * pdf), (lfloat)(1.0f));
    le = l3_sel(seen, l3_add(le, l3_scale(li, w)), le);
  }
  ps_add_radiance(ps, l3_scale(l3_mul(thr, le), PS_LF(ps, emit_scale)));
}

#if AW_LANES == 1
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

#endif

// `hv->mirrored`: the triangle belongs to an instance whose transform mirrors, which reverses
// the winding in world space (the loader swaps two corners of a mirrored mesh it flattens
// instead).
AW_FN HitPoint classify_hit_point(PathRef ps, const HitVertices* hv, lfloat3 dir) {
  HitPoint h;
  h.b1 = PS_LF(ps, hit_u);
  h.b2 = PS_LF(ps, hit_v);
  h.b0 = 1.0f - h.b1 - h.b2;
  h.p0 = hv->p[0];
  h.p1 = hv->p[1];
  h.p2 = hv->p[2];
  // Position from barycentrics rather than o + t d: exact on the triangle's plane, so the
  // ray offset below starts from the surface and not from a point slightly behind it.
  h.p = l3_add(l3_add(l3_scale(h.p0, h.b0), l3_scale(h.p1, h.b1)), l3_scale(h.p2, h.b2));
  lfloat3 ng = l3_cross(l3_sub(h.p1, h.p0), l3_sub(h.p2, h.p0));
  lfloat ng_len2 = l3_dot(ng, ng);
  // Degenerate triangles are never hit by the watertight test, but a nearly degenerate one
  // can be: fall back to facing the ray.
  ng = l3_sel(ng_len2 > 0.0f, l3_div(ng, sqrt(ng_len2)), l3_neg(dir));
  ng = l3_sel(hv->mirrored, l3_neg(ng), ng);
  lfloat3 nshade = ng;
  lmask has_n = (lmask)(0);
  if (L_ANY(hv->has_n)) {
    lfloat3 n = l3_add(l3_add(l3_scale(hv->n[0], h.b0), l3_scale(hv->n[1], h.b1)), l3_scale(hv->n[2], h.b2));
    lfloat n_len2 = l3_dot(n, n);
    has_n = hv->has_n && n_len2 > 0.0f && isfinite(n_len2);
    nshade = l3_sel(has_n, l3_div(n, sqrt(n_len2)), nshade);
  }
  // The outside of the surface: where the shading normals point (robust to winding), or the
  // winding's normal for meshes without normals.
  ng = l3_sel(has_n && l3_dot(nshade, ng) < 0.0f, l3_neg(ng), ng);
  h.front = l3_dot(ng, dir) < 0.0f;
  // From here on both normals face the side the ray came from.
  ng = l3_sel(h.front, ng, l3_neg(ng));
  nshade = l3_sel(h.front, nshade, l3_neg(nshade));
  // Interpolated normals can face away from the viewer near silhouettes even though the
  // triangle faces it; every lobe would then reject wo. Use the true surface there.
  nshade = l3_sel(l3_dot(nshade, ng) < 0.0f || l3_dot(nshade, dir) >= 0.0f, ng, nshade);
  h.n = nshade;
  h.ng = ng;
  h.err = triangle_point_error(h.p, h.p0, h.p1, h.p2, h.b0, h.b1, h.b2, hv->vert_err, ng);
  h.sphere = hv->sphere;
  h.uv = make_lfloat2((lfloat)(0.0f), (lfloat)(0.0f));
  return h;
}

// Writes the shading point for the lobe stage; returns the tangent (zero unless the material
// is anisotropic: only the reflection frame reads it; anisotropy is one path per call).
AW_FN lfloat3 classify_store_shading_point(PathRef ps, MatL m, luint material, HitPoint h, const HitVertices* hv) {
  PS_SET_F(ps, sp_px, h.p.x); PS_SET_F(ps, sp_py, h.p.y); PS_SET_F(ps, sp_pz, h.p.z);
  PS_SET_F(ps, sp_nx, h.n.x); PS_SET_F(ps, sp_ny, h.n.y); PS_SET_F(ps, sp_nz, h.n.z);
  PS_SET_F(ps, sp_gx, h.ng.x); PS_SET_F(ps, sp_gy, h.ng.y); PS_SET_F(ps, sp_gz, h.ng.z);
  PS_SET_F(ps, sp_err, h.err);
  PS_SET_U(ps, material, material);
  luint flags = PS_LU(ps, flags);
  PS_SET_U(ps, flags, L_SEL(h.front, flags | AW_PATH_FRONT, flags & ~AW_PATH_FRONT));
  lfloat3 tangent = l3_splat((lfloat)(0.0f));
#if AW_LANES == 1
  const VertexData* v0 = &hv->v[0];
  const VertexData* v1 = &hv->v[1];
  const VertexData* v2 = &hv->v[2];
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
#endif
  return tangent;
}

// Ends the paths of `missing`, marked as having met a feature this build lacks (the host
// counts them and refuses the image); *ps keeps the others. Returns whether any is left.
AW_FN int classify_end_missing(PathRef* ps, lmask missing) {
  if (L_ANY(missing)) {
    PathRef pm = *ps;
    PS_KEEP(pm, missing);
    PS_SET_U(pm, flags, PS_LU(pm, flags) | AW_PATH_MISSING_FEATURE);
  }
  lmask left = !missing;
  PS_KEEP(*ps, left);
  return L_ANY(left);
}

// Lane `lid`'s entry of the weights: its scale over its probability (lid < AW_LID_COUNT).
AW_FN lfloat3 lobe_weight_of(const LobeWeights* lw, luint lid) {
  lfloat3 scale = lw->scale[0];
  lfloat prob = lw->prob[0];
  for (uint i = 1u; i < AW_LID_COUNT; ++i) {
    lmask is = lid == i;
    scale = l3_sel(is, lw->scale[i], scale);
    prob = L_SEL(is, lw->prob[i], prob);
  }
  return l3_div(scale, prob);
}

// Lobe choice (docs/material.md §2): in proportion to each lobe's share of the energy, the
// reflection lobes' Fresnel taken at the microfacet their sample will use: the same frame
// and the same random numbers as shade_surface (material_lobe_weights_sampled says why).
// Materials without reflection need neither the frame nor the random numbers. On lanes the
// reflection lobes are isotropic (material_sampled_fresnel), so their frame is make_frame's,
// as material_reflection_frame's for an isotropic material; the split runs when any lane's
// material reflects, and a lane whose material does not gets f = 0 from it, which is the
// split without reflection. Returns each path's lobe queue, or DONE when no lobe has energy.
AW_FN luint classify_choose_lobe(PathRef ps, MatL m, const RenderParams* rp, lfloat3 dir, lfloat3 n, lfloat3 tangent,
                                 lmask front) {
  const luint done = (luint)(AW_Q_DONE);
  luint bounce = PS_LU(ps, bounce);
  LobeWeights lw;
  lmask reflects = AW_FEAT_REFLECTION && (MAT_F(m, refl[0].weight) > 0.0f || MAT_F(m, refl[1].weight) > 0.0f);
  if (L_ANY(reflects)) {
    // The reflection's own normal (with bump mapping, the one its disable_bump chooses).
    n = shading_normal_for_lobe(ps, m, AW_LID_REFLECTION);
    lfloat3 rt, rb;
#if AW_LANES == 1
    material_reflection_frame(m, n, tangent, &rt, &rb);
#else
    (void)tangent;
    make_frame(n, &rt, &rb);
#endif
    lfloat2 u_bsdf = rng_2d(rp_sampler(rp), PS_LU(ps, pixel), PS_LU(ps, sample), bounce, AW_DIM_BSDF);
    lw = material_lobe_weights_sampled(m, frame_to_local(l3_neg(dir), rt, rb, n), u_bsdf, front);
  } else {
    lw = material_lobe_weights_f(m, (lfloat)(0.0f), (lfloat)(0.0f), front);
  }
  // Refraction past its depth returns black (docs/material.md §5). (Without the refraction
  // feature its probability is 0 already, and the depths are not kept.)
  if (AW_FEAT_REFRACTION)
    lw.prob[AW_LID_REFRACTION] =
      L_SEL((PS_LU(ps, depths) >> 16) >= MAT_U(m, refr_depth), (lfloat)(0.0f), lw.prob[AW_LID_REFRACTION]);
  lfloat total = (lfloat)(0.0f);
  for (uint i = 0; i < AW_LID_COUNT; ++i) total += lw.prob[i];
  lmask energy = total > 0.0f;
  PS_KEEP(ps, energy);
  if (!L_ANY(energy)) return done;
  luint with_energy = (luint)(0u);
  for (uint i = 0; i < AW_LID_COUNT; ++i) {
    lw.prob[i] /= total;
    with_energy += L_SEL(lw.prob[i] > 0.0f, (luint)(1u), (luint)(0u));
  }
  // One lobe with energy (a Lambert surface, a plain mirror): material_pick_lobe returns it for
  // any u, so no random number is drawn for it (a Sobol' sample costs about as much as the rest
  // of the choice; docs/performance.md, "Random numbers only where a choice exists").
  lmask choice = with_energy > 1u;
  lfloat u_lobe = (lfloat)(0.0f);
  if (L_ANY(choice))
    u_lobe = L_SEL(choice, rng_1d(rp_sampler(rp), PS_LU(ps, pixel), PS_LU(ps, sample), bounce, AW_DIM_LOBE), u_lobe);
  luint lid = material_pick_lobe(&lw, u_lobe);
  lmask picked = lid < AW_LID_COUNT;
  PS_KEEP(ps, picked);
  if (!L_ANY(picked)) return done;
  // Unreachable after the material check in classify_hit; kept as a guard.
  lmask missing = (lmask)(0);
  for (uint i = 0u; i < AW_LID_COUNT; ++i)
    if (!lobe_compiled(i)) missing = missing || lid == i;
  if (!classify_end_missing(&ps, missing)) return done;
  lfloat3 w = lobe_weight_of(&lw, lid);
  PS_SET_F(ps, lobe_wr, w.x); PS_SET_F(ps, lobe_wg, w.y); PS_SET_F(ps, lobe_wb, w.z);
  PS_SET_U(ps, lobe, lid);
  return L_SEL(PS_LIVE(ps), (luint)(AW_Q_LOBE) + lid, done);
}

// The material of each lane's triangle: the scene's table entry (textures come later, one
// path per call).
AW_FN MatL classify_material(SceneRef sc, const RenderParams* rp, luint material) {
#if AW_LANES == 1
  (void)rp;
  return &sc.materials[material];
#else
  MatL m;
  m.table = sc.materials;
  m.n = rp->num_materials;
  m.i = material;
  return m;
#endif
}

AW_FN luint classify_hit_body(PathRef ps, SceneRef sc, const RenderParams* rp) {
  const luint done = (luint)(AW_Q_DONE);
  lfloat3 dir = ps_ray_dir(ps);
#if AW_LANES == 1
  classify_fog(ps, sc);
#endif
  lfloat3 thr = ps_throughput(ps);

  // 1. The ray ended: on a light, or in the environment.
  luint light = PS_LU(ps, hit_light);
  luint prim = PS_LU(ps, hit_prim);
  lmask on_light = light != AW_NONE;
  lmask escaped = !on_light && prim == AW_NONE;
  if (L_ANY(on_light)) {
    PathRef pl = ps;
    PS_KEEP(pl, on_light);
    classify_light_hit(pl, sc, rp, L_SEL(PS_LIVE(pl), light, (luint)(0u)), dir, thr);
  }
  if (L_ANY(escaped)) {
    PathRef pe = ps;
    PS_KEEP(pe, escaped);
    classify_environment(pe, sc, rp, dir, thr);
  }
  lmask surface = !on_light && !escaped;
  PS_KEEP(ps, surface);
  if (!L_ANY(surface)) return done;

  // 2. The surface it hit: its vertices in world space (an instance's carried there by its
  // transform) and the shading point. (A lane that is not a path reads triangle 0.)
  prim = L_SEL(PS_LIVE(ps), prim, (luint)(0u));
  HitVertices hv = classify_vertices(ps, sc, prim);
  luint material = L_GATHER(uint, sc.tri_info, prim, material);
  MatL m = classify_material(sc, rp, material);
#if AW_LANES == 1
  HitPoint h = hv.sphere ? classify_sphere_point(ps, &hv, dir) : classify_hit_point(ps, &hv, dir);
#else
  // Both forms, selected per lane. (Computing the sphere's only when any() lane hit one, the
  // triangle's likewise, made PoCL 3.1 write garbage into every lane's path flags in a scene
  // with spheres, Intel's runtime not; measured, the cause inside PoCL not isolated.)
  HitPoint h = classify_hit_point(ps, &hv, dir);
  if (AW_FEAT_SPHERE) h = hit_point_sel(hv.sphere, classify_sphere_point(ps, &hv, dir), h);
#endif

  // 3. The feature guard. The host derived the features from this very scene, so this cannot
  // happen; if it does, it is counted and the host refuses the image rather than render it wrong.
  lmask missing = material_uses_missing_feature(m);
  if (!classify_end_missing(&ps, missing)) return done;

#if AW_LANES == 1
  // 4. Textures: the hit's UV and the path's footprint there, the material with its textured
  // inputs applied (integrator/shading_material.h), the bump-mapped normal. (Cutout holes were
  // never hit: the traversal skips them, integrator/ray_cast.h.)
  if (AW_FEAT_TEXTURE) {
    classify_texture_point(ps, &hv.v[0], &hv.v[1], &hv.v[2], h, dir);
    PS_U(ps, material) = material;
    m = shading_material(ps, sc, rp);
    if (AW_FEAT_BUMP && m->bump_binding != AW_NONE) h.n = classify_bump(ps, sc, m, h, &hv.v[0], &hv.v[1], &hv.v[2], dir);
  }
  // The AOVs of the first hit (integrator/aov.h): the ray's direction is a unit vector, so
  // hit_t is the distance from the camera.
  if (aov_on(rp) && PS_U(ps, bounce) == 0u)
    aov_surface(ps, rp, material_albedo(m, fabs(dot(dir, h.n)), h.front), h.n, h.p, PS_F(ps, hit_t), material);
#endif

  // 5. A path that has used up its scattering events ends here. (Its last ray was still
  // traced: light it finds completes the MIS pair of the previous vertex's light sample.)
  // Ambient occlusion runs only where the path scatters on (ambient_occlusion.h).
  lmask ends = PS_LU(ps, bounce) >= rp->max_depth || (PS_LU(ps, flags) & AW_PATH_EMITTERS_ONLY) != 0u;
  lmask ao = AW_FEAT_AO && MAT_U(m, ao_samples) > 0u && !ends;

  // 6. Incandescence: emission added to the shaded result at every hit. Found by BSDF sampling
  // alone (weight 1), unless the triangle belongs to a light-sampled object: then it is a
  // light, MIS-weighted against the light samples that could have found it, and AO never dims
  // it. Otherwise AO in multiply mode with apply_to_incandescence darkens it: the AO stage
  // adds it then.
  if (AW_FEAT_INCANDESCENCE) {
    luint tri_light = triangle_light(sc, rp, prim);
    lmask is_light = tri_light != AW_NONE;
    luint ao_flags = MAT_U(m, ao_flags);
    lfloat3 inc = MAT_F3(m, incandescent);
    lmask adds = (is_light || !(ao && (ao_flags & AW_AO_MULTIPLY) != 0u && (ao_flags & AW_AO_INCANDESCENCE) != 0u)) &&
                 l3_max3(inc) > 0.0f;
    if (L_ANY(adds)) {
      lfloat w = (lfloat)(1.0f);
      if (L_ANY(is_light))
        w = L_SEL(is_light, classify_light_mis(ps, sc, rp, L_SEL(is_light, tri_light, (luint)(0u)), dir), w);
      PathRef pi = ps;
      PS_KEEP(pi, adds);
      ps_add_radiance(pi, l3_scale(l3_mul(thr, inc), w * PS_LF(ps, emit_scale)));
    }
  }
  lmask goes_on = !ends;
  PS_KEEP(ps, goes_on);
  if (!L_ANY(goes_on)) return done;

  // 7. The shading point for the lobe stage, and the lobe that scatters the path; with AO, the
  // AO stage first, which hands the path on to that lobe (or ends it when there is none).
  lfloat3 tangent = classify_store_shading_point(ps, m, material, h, &hv);
  luint q = classify_choose_lobe(ps, m, rp, dir, h.n, tangent, h.front);
  if (L_ANY(ao)) {
    lmask no_lobe = ao && q == done;
    if (L_ANY(no_lobe)) {
      PathRef pn = ps;
      PS_KEEP(pn, no_lobe);
      PS_SET_U(pn, lobe, AW_NONE);
    }
    q = L_SEL(ao && (PS_LU(ps, flags) & AW_PATH_MISSING_FEATURE) == 0u, (luint)(AW_Q_AO), q);
  }
  return L_SEL(PS_LIVE(ps), q, done);
}

// classify_hit_body, and the AOVs' record of what the first hit gathered (integrator/aov.h).
AW_FN luint classify_hit(PathRef ps, SceneRef sc, const RenderParams* rp) {
#if AW_LANES == 1
  uint bounce = PS_U(ps, bounce);
  int q = classify_hit_body(ps, sc, rp);
  aov_first_classified(ps, rp, bounce);
  return q;
#else
  return classify_hit_body(ps, sc, rp);
#endif
}

#endif
