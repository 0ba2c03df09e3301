// The material's texture-bound inputs at a surface point: the material the stages read
// (material_apply_textures), cutout opacity inside the traversal (material_opaque_at) and the
// bumped shading normal (bump_normal). Shared by the device and the host scalar path.
#ifndef AW_TEXTURE_MATERIAL_TEXTURES_H
#define AW_TEXTURE_MATERIAL_TEXTURES_H

#include "bvh/intersect_sphere.h"
#include "common/compat.h"
#include "texture/texture.h"
#include "types/bvh.h"
#include "types/material.h"

// The pointers texture lookups need, bundled (the traversal takes this, not the whole scene).
typedef struct {
  const AW_GLOBAL TriangleInfo* tri_info;
  const AW_GLOBAL VertexData* verts;
  const AW_GLOBAL MaterialGpu* materials;
  const AW_GLOBAL TextureGpu* textures;
  const AW_GLOBAL TexBindingGpu* bindings;
  const AW_GLOBAL uchar* texels;
} TextureScene;

// A binding's value from its texture's RGBA: offset + multiplier * channel, clamped to the
// input's documented range.
AW_FN float binding_scalar(const AW_GLOBAL TexBindingGpu* b, float4 c, uint channel) {
  return clamp(b->offset + b->multiplier * texture_channel(c, channel), b->lo, b->hi);
}

AW_FN float binding_eval_scalar(TextureScene ts, const AW_GLOBAL TexBindingGpu* b, float u, float v, float fuv) {
  return binding_scalar(b, texture_eval(&ts.textures[b->texture], ts.texels, u, v, fuv), b->channel);
}

// A surface point's texture coordinates in both UV sets: (u, v) and the footprint there in UV
// units (texture/texture.h), for set 0 and set 1.
typedef struct {
  float u, v, f;
  float u2, v2, f2;
} SurfaceUv;

// The binding's UV set at the point: (u, v, footprint).
AW_FN float3 surface_uv_for(SurfaceUv s, const AW_GLOBAL TexBindingGpu* b) {
  return b->uv_set == 1u ? make_float3(s.u2, s.v2, s.f2) : make_float3(s.u, s.v, s.f);
}

// Writes material m with every bound input replaced by its texture's value at the point (in
// the binding's UV set) into *r. The inputs are whole 32-bit words of MaterialGpu
// (TexBindingGpu.word); a colour is three.
AW_FN void material_apply_textures(AW_GLOBAL MaterialGpu* r, const AW_GLOBAL MaterialGpu* m, TextureScene ts,
                                   SurfaceUv s) {
  *r = *m;
  AW_GLOBAL float* w = (AW_GLOBAL float*)r;
  for (uint i = 0u; i < m->tex_count; ++i) {
    const AW_GLOBAL TexBindingGpu* b = &ts.bindings[m->tex_first + i];
    float3 t = surface_uv_for(s, b);
    float4 c = texture_eval(&ts.textures[b->texture], ts.texels, t.x, t.y, t.z);
    if (b->channel == AW_TEXCH_RGB) {
      w[b->word + 0u] = binding_scalar(b, c, AW_TEXCH_R);
      w[b->word + 1u] = binding_scalar(b, c, AW_TEXCH_G);
      w[b->word + 2u] = binding_scalar(b, c, AW_TEXCH_B);
    } else {
      float x = binding_scalar(b, c, b->channel);
      for (uint k = 0u; k < b->count; ++k) w[b->word + k] = x;
    }
  }
}

// The UV (set 0 or 1) of barycentrics (b1, b2) on triangle prim.
AW_FN float2 triangle_uv(TextureScene ts, uint prim, float b1, float b2, uint set) {
  const AW_GLOBAL TriangleInfo* tri = &ts.tri_info[prim];
  const AW_GLOBAL VertexData* v0 = &ts.verts[tri->v[0]];
  const AW_GLOBAL VertexData* v1 = &ts.verts[tri->v[1]];
  const AW_GLOBAL VertexData* v2 = &ts.verts[tri->v[2]];
  float b0 = 1.0f - b1 - b2;
  const AW_GLOBAL float* a = set == 1u ? v0->uv2 : v0->uv;
  const AW_GLOBAL float* b = set == 1u ? v1->uv2 : v1->uv;
  const AW_GLOBAL float* c = set == 1u ? v2->uv2 : v2->uv;
  return make_float2(b0 * a[0] + b1 * b[0] + b2 * c[0], b0 * a[1] + b1 * b[1] + b2 * c[1]);
}

// Whether the surface is there at barycentrics (b1, b2) of triangle prim: cutout opacity
// >= 0.5 (docs/material.md §1). A textured opacity is read at level 0 (the traversal has no
// footprint, and a hole must be the same hole for every ray that meets it: camera, extension,
// shadow and AO rays alike).
AW_FN int material_opaque_at(TextureScene ts, uint prim, float b1, float b2) {
  const AW_GLOBAL MaterialGpu* m = &ts.materials[ts.tri_info[prim].material];
  if (m->cutout_binding == AW_NONE) return m->cutout_opacity >= 0.5f;
  const AW_GLOBAL TexBindingGpu* b = &ts.bindings[m->cutout_binding];
  float2 uv = triangle_uv(ts, prim, b1, b2, b->uv_set);
  return binding_eval_scalar(ts, b, uv.x, uv.y, 0.0f) >= 0.5f;
}

// An analytic sphere's centre vertex (types/bvh.h, AW_SPHERE_MARK), and the UV at a point on it.
AW_FN int prim_is_sphere(TextureScene ts, uint prim) { return ts.tri_info[prim].v[1] == AW_SPHERE_MARK; }
AW_FN float2 sphere_point_uv(const AW_GLOBAL VertexData* c, float3 p) {
  float3 w = p - make_float3(c->p[0], c->p[1], c->p[2]);
  float l2 = dot(w, w);
  w = l2 > 0.0f ? w / sqrt(l2) : make_float3(0.0f, 1.0f, 0.0f);
  return sphere_uv(w, make_float3(c->n[0], c->n[1], c->n[2]), make_float3(c->t[0], c->t[1], c->t[2]));
}

// material_opaque_at for an analytic sphere, at point p of the ray (inside the traversal).
AW_FN int material_opaque_at_sphere(TextureScene ts, uint prim, float3 p) {
  const AW_GLOBAL MaterialGpu* m = &ts.materials[ts.tri_info[prim].material];
  if (m->cutout_binding == AW_NONE) return m->cutout_opacity >= 0.5f;
  float2 uv = sphere_point_uv(&ts.verts[ts.tri_info[prim].v[0]], p);
  return binding_eval_scalar(ts, &ts.bindings[m->cutout_binding], uv.x, uv.y, 0.0f) >= 0.5f;
}

// Bump mapping (Blinn 1978, "Simulation of Wrinkled Surfaces", SIGGRAPH; in the form of
// Pharr, Jakob & Humphreys, pbrt-v3, Sec. 9.3, without the dn/du terms): the surface is
// displaced along the shading normal n by the height h(u, v) = bump.scale * texture, so its
// tangents become dpdu + h_u n and dpdv + h_v n and the bumped normal is their cross product.
// dpdu and dpdv are the triangle's UV parametrisation projected onto n's tangent plane, so a
// smooth (interpolated) normal is bumped, not the facet. h_u, h_v by central differences of
// step `du` in UV. Returns n unchanged where the UV parametrisation is degenerate.
AW_FN float3 bump_normal(float3 n, float3 dpdu, float3 dpdv, float h_u, float h_v) {
  float3 tu = dpdu - n * dot(n, dpdu), tv = dpdv - n * dot(n, dpdv);
  float3 nb = cross(tu + n * h_u, tv + n * h_v);
  // The cross product of the unbumped tangents points along +n or -n depending on the UV
  // parametrisation's handedness; the bumped normal keeps n's side.
  if (dot(cross(tu, tv), n) < 0.0f) nb = -nb;
  float l2 = dot(nb, nb);
  if (!(l2 > 0.0f) || !isfinite(l2)) return n;
  return nb / sqrt(l2);
}

// The terminator: a bumped normal can face away from the viewer, where every lobe would see
// wo below its hemisphere, or reflect the viewer into the geometric surface. Keeps the mirror
// reflection of wo about the returned normal at least `tau` above the geometric surface ng:
// where it is not, the reflected direction is lifted to height tau (its tangential direction
// kept) and the normal becomes the half vector between wo and that direction, the smallest
// change of the normal that does it. (The problem: Schüßler et al. 2017, "Microfacet-based
// Normal Mapping for Robust Monte Carlo Path Tracing", ACM TOG 36(6); this simpler remedy is
// in the spirit of Cycles' ensure_valid_reflection.) wo and ng face the same side.
AW_FN float3 bump_keep_reflection_above(float3 n, float3 ng, float3 wo) {
  float cos_o = dot(ng, wo);
  float tau = fmin(0.9f * cos_o, 0.01f);
  float3 r = n * (2.0f * dot(n, wo)) - wo;
  if (dot(r, ng) >= tau) return n;
  float3 rt = r - ng * dot(r, ng);
  float lt = sqrt(dot(rt, rt));
  // wo along ng (lt = 0 can only happen then, or with a degenerate r): the geometric normal.
  if (!(lt > 1e-7f) || !(tau > 0.0f)) return ng;
  float3 r2 = rt * (sqrt(fmax(0.0f, 1.0f - tau * tau)) / lt) + ng * tau;
  float3 h = wo + r2;
  float hl = sqrt(dot(h, h));
  return hl > 0.0f ? h / hl : ng;
}

#endif
