// The Architectural material at a shading point: how much of the incoming energy each lobe
// gets (docs/material.md §2: reflection first, then refraction, then diffuse) and which lobe a
// path takes. The lobes themselves live in kernels/lobes/, one file each.
#ifndef AW_MATERIAL_ARCHITECTURAL_H
#define AW_MATERIAL_ARCHITECTURAL_H

#include "common/compat.h"
#include "common/features.h"
#include "common/lanes.h"
#include "common/sampling.h"
#include "lobes/fresnel.h"
#include "lobes/lobe.h"
#include "lobes/microfacet.h"
#include "material/lobe_list.h"
#include "types/material.h"

// A material to read, on lanes (common/lanes.h): at W = 1 a pointer to one material (the
// scene's, or the slot's textured copy: integrator/shading_material.h); at W > 1 each lane's
// material in a table, its fields gathered per lane. Code on lanes reads fields with MAT_F
// (float) and MAT_U (uint); at W = 1 these are m->field.
// On lanes a table of at most AW_SMALL_TABLE materials is read by selects, not gathered
// (L_TABLE, common/lanes.h).
#if AW_LANES == 1
typedef const AW_GLOBAL MaterialGpu* MatL;
#define MAT_F(m, field) ((m)->field)
#define MAT_U(m, field) ((m)->field)
#else
typedef struct {
  const AW_GLOBAL MaterialGpu* table;
  uint n;  // the table's size (RenderParams.num_materials)
  luint i;
} MatL;
#define MAT_F(m, field) L_TABLE(float, (m).table, (m).n, (m).i, field)
#define MAT_U(m, field) L_TABLE(uint, (m).table, (m).n, (m).i, field)
#endif
#define MAT_F3(m, field) make_lfloat3(MAT_F(m, field[0]), MAT_F(m, field[1]), MAT_F(m, field[2]))

// The diffuse lobe's albedo: colour times weight (docs/material.md §1).
AW_FN lfloat3 material_diffuse_color(MatL m) {
  return l3_scale(make_lfloat3(MAT_F(m, diffuse_color[0]), MAT_F(m, diffuse_color[1]), MAT_F(m, diffuse_color[2])),
                  MAT_F(m, diffuse_weight));
}

// refraction.thin_walled, in builds that have thin walls (common/features.h: a material that
// sets it without reflecting or transmitting anything is shaded the same either way).
AW_FN lmask material_is_thin(MatL m) {
  return AW_FEAT_THIN_WALLED && (MAT_U(m, flags) & AW_MAT_THIN_WALLED) != 0u;
}

// Per-lobe factors at one shading point. `scale` multiplies the lobe's own value (its eval
// and sample weight already contain the lobe's colour and, for reflection, Fresnel at the
// microfacet). `prob` is the probability that classify_hit sends the path to that lobe.
// On lanes (common/lanes.h) each entry holds W paths' values.
typedef struct {
  lfloat3 scale[AW_LID_COUNT];
  lfloat prob[AW_LID_COUNT];
  lfloat albedo[AW_LID_COUNT];  // luminance of each lobe's estimated contribution
} LobeWeights;

AW_FN lmask positive3(lfloat3 c) { return c.x > 0.0f || c.y > 0.0f || c.z > 0.0f; }

// Whether reflection lobe i carries energy at all (weight and colour): a lobe without it is
// never chosen, so it needs no code and never splits.
AW_FN lmask material_reflection_used(MatL m, uint i) {
  return MAT_F(m, refl[i].weight) > 0.0f && positive3(MAT_F3(m, refl[i].color));
}

// The split itself, given each reflection lobe's reflectance f1, f2 in [0, 1] (0 for a lobe
// without weight). Written on lanes; each field is read once.
AW_FN LobeWeights material_lobe_weights_f(MatL m, lfloat f1, lfloat f2, lmask entering) {
  LobeWeights lw;
  lmask thin = material_is_thin(m);
  luint flags = MAT_U(m, flags);
  lmask metal = (flags & AW_MAT_METAL) != 0u;
  lfloat3 diffuse = material_diffuse_color(m);
  lfloat refr_weight = MAT_F(m, refr_weight);
  lfloat3 refr_color = MAT_F3(m, refr_color);
  const lfloat3 zero = l3_splat((lfloat)(0.0f));

  // Reflection: rho1 = weight * color * F1(theta_o) (x diffuse colour when metal).
  lfloat3 rho1 = zero, rho2 = zero;
  lfloat lum1 = (lfloat)(0.0f), lum2 = (lfloat)(0.0f), keep2 = (lfloat)(1.0f);
  lfloat weight1 = (lfloat)(0.0f), weight2 = (lfloat)(0.0f);
  if (AW_FEAT_REFLECTION) {
    weight1 = MAT_F(m, refl[0].weight);
    weight2 = MAT_F(m, refl[1].weight);
    lfloat3 tint1 = MAT_F3(m, refl[0].color);
    tint1 = l3_sel(metal, l3_mul(tint1, diffuse), tint1);
    rho1 = l3_scale(tint1, weight1 * f1);
    lum1 = fmin((lfloat)(1.0f), l_luminance(rho1));
    // Reflection 2 gets what reflection 1 leaves.
    keep2 = 1.0f - lum1;
    rho2 = l3_scale(MAT_F3(m, refl[1].color), weight2 * f2 * keep2);
    lum2 = l_luminance(rho2);
  }
  // Whatever reflection leaves is transmitted (refraction, translucency) or diffuse.
  lfloat rest = 1.0f - fmin((lfloat)(1.0f), lum1 + lum2);
  lfloat w_t = refr_weight * rest;
  lfloat w_transl = (lfloat)(0.0f);
  if (AW_FEAT_TRANSLUCENCY) w_transl = L_SEL((flags & AW_MAT_TRANSLUCENCY) != 0u, w_t * MAT_F(m, transl_weight), w_transl);
  lfloat w_refr = w_t - w_transl;
  lfloat w_d = rest;
  // (A variable, not "AW_FEAT_REFRACTION || AW_FEAT_TRANSLUCENCY" in the condition: clang and
  // gcc warn on a condition made of constants.)
  const int transmissive = AW_FEAT_REFRACTION + AW_FEAT_TRANSLUCENCY;
  if (transmissive)
    w_d = w_d * (1.0f - refr_weight * l_luminance(refr_color));
  else
    w_refr = (lfloat)(0.0f);
  w_d = L_SEL(metal, w_d * (1.0f - lum1), w_d);

  // Skip weak internal reflections: inside a refractive object, partial reflections are not
  // traced (total internal reflection, f = 1, still is). Biased by design: an optimisation.
  lmask skip_weak = !entering && !thin && refr_weight > 0.0f && (flags & AW_MAT_SKIP_WEAK_INTERNAL) != 0u;
  rho1 = l3_sel(skip_weak && f1 < 1.0f, zero, rho1);
  rho2 = l3_sel(skip_weak && f2 < 1.0f, zero, rho2);

  lw.scale[AW_LID_DIFFUSE] = l3_splat(w_d);
  lw.scale[AW_LID_TRANSLUCENCY] = l3_splat(w_transl);
  // The reflection lobes carry tint and Fresnel themselves; scale is the rest of rho.
  lfloat s1 = L_SEL(l_luminance(rho1) > 0.0f, weight1, (lfloat)(0.0f));
  lfloat s2 = L_SEL(l_luminance(rho2) > 0.0f, weight2 * keep2, (lfloat)(0.0f));
  lw.scale[AW_LID_REFLECTION] = l3_splat(s1);
  lw.scale[AW_LID_REFLECTION2] = l3_splat(s2);
  lw.scale[AW_LID_REFRACTION] = l3_scale(refr_color, w_refr);

  // Selection in proportion to each lobe's estimated contribution.
  lw.albedo[AW_LID_DIFFUSE] = w_d * l_luminance(diffuse);
  // (w_transl is 0 in builds without translucency: its colour is not read there.)
  lw.albedo[AW_LID_TRANSLUCENCY] = AW_FEAT_TRANSLUCENCY ? w_transl * l_luminance(MAT_F3(m, transl_color)) : (lfloat)(0.0f);
  lw.albedo[AW_LID_REFLECTION] = l_luminance(rho1);
  lw.albedo[AW_LID_REFLECTION2] = l_luminance(rho2);
  lw.albedo[AW_LID_REFRACTION] = l_luminance(lw.scale[AW_LID_REFRACTION]);
  lfloat total = (lfloat)(0.0f);
  for (uint i = 0; i < AW_LID_COUNT; ++i) {
    lw.albedo[i] = fmax(lw.albedo[i], 0.0f);
    total += lw.albedo[i];
  }
  for (uint i = 0; i < AW_LID_COUNT; ++i) lw.prob[i] = L_SEL(total > 0.0f, lw.albedo[i] / total, (lfloat)(0.0f));
  return lw;
}

// The features material m uses, as AW_FEATBIT_* bits. The one definition of "uses": the host
// ORs it over the scene's materials to choose what to compile (host/render/features.cpp) and
// every hit checks it against the build, so a specialised build can never silently render a
// material differently. On lanes: each lane's material's features.
#define AW_MAT_FEATURE_IF(m, bit) L_SEL((m), (luint)(bit), (luint)(0u))
AW_FN luint material_features(MatL m) {
  luint f = (luint)(0u);
  lmask refl = (lmask)(0);
  for (uint i = 0u; i < 2u; ++i) {
    lmask used = material_reflection_used(m, i);
    luint brdf = MAT_U(m, refl[i].brdf), fresnel = MAT_U(m, refl[i].fresnel_mode);
    refl = refl || used;
    f |= AW_MAT_FEATURE_IF(used && brdf == AW_BRDF_BECKMANN, AW_FEATBIT_BRDF_BECKMANN);
    f |= AW_MAT_FEATURE_IF(used && (brdf == AW_BRDF_ASHIKHMIN_SHIRLEY || brdf == AW_BRDF_ASHIKHMIN_SHIRLEY_LEGACY),
                           AW_FEATBIT_BRDF_AS);
    f |= AW_MAT_FEATURE_IF(used && fresnel == AW_FRESNEL_CONDUCTOR, AW_FEATBIT_FRESNEL_CONDUCTOR);
    f |= AW_MAT_FEATURE_IF(used && fresnel == AW_FRESNEL_CURVE, AW_FEATBIT_FRESNEL_CURVE);
  }
  luint flags = MAT_U(m, flags);
  lfloat transl_weight = MAT_F(m, transl_weight);
  lmask transmit = MAT_F(m, refr_weight) > 0.0f;
  lmask transl = transmit && (flags & AW_MAT_TRANSLUCENCY) != 0u && transl_weight > 0.0f;
  lmask refr = transmit && !(transl && transl_weight >= 1.0f);
  luint bump = MAT_U(m, bump_binding);
  f |= AW_MAT_FEATURE_IF(transl, AW_FEATBIT_TRANSLUCENCY);
  f |= AW_MAT_FEATURE_IF(refl, AW_FEATBIT_REFLECTION);
  f |= AW_MAT_FEATURE_IF(refr, AW_FEATBIT_REFRACTION);
  f |= AW_MAT_FEATURE_IF(MAT_F(m, diffuse_roughness) > 0.0f, AW_FEATBIT_ROUGH_DIFFUSE);
  f |= AW_MAT_FEATURE_IF(refl && MAT_F(m, aniso_amount) != 0.0f, AW_FEATBIT_ANISOTROPY);
  f |= AW_MAT_FEATURE_IF(refr && MAT_F(m, fog_distance) > 0.0f, AW_FEATBIT_FOG);
  f |= AW_MAT_FEATURE_IF(MAT_F(m, cutout_opacity) < 0.5f || MAT_U(m, cutout_binding) != AW_NONE, AW_FEATBIT_CUTOUT);
  f |= AW_MAT_FEATURE_IF(MAT_U(m, tex_count) > 0u, AW_FEATBIT_TEXTURE);
  f |= AW_MAT_FEATURE_IF(bump != AW_NONE, AW_FEATBIT_BUMP | AW_FEATBIT_TEXTURE);
  f |= AW_MAT_FEATURE_IF(positive3(MAT_F3(m, incandescent)), AW_FEATBIT_INCANDESCENCE);
  f |= AW_MAT_FEATURE_IF((flags & AW_MAT_THIN_WALLED) != 0u && (refl || transmit), AW_FEATBIT_THIN_WALLED);
  f |= AW_MAT_FEATURE_IF(MAT_U(m, ao_samples) > 0u, AW_FEATBIT_AO);
  return f;
}
#undef AW_MAT_FEATURE_IF

// At W = 1 the material as shaded (textured inputs applied: integrator/shading_material.h) is
// judged at the hit. A lane program is built only for scenes without textures, where the
// material shaded is the table's, so it reads the bits the host computed with
// material_features from that very entry (MaterialGpu.features, pack_scene): one field per lane
// instead of twenty, which had been 15% of classification on lanes (perf with line numbers,
// Intel's runtime; docs/performance.md, "State fields, sorted hits in slot order, accumulate on lanes").
AW_FN lmask material_uses_missing_feature(MatL m) {
#if AW_LANES == 1
  return (material_features(m) & ~(uint)(AW_FEAT_COMPILED_MATERIAL_MASK)) != 0u;
#else
  return (MAT_U(m, features) & ~(uint)(AW_FEAT_COMPILED_MATERIAL_MASK)) != 0u;
#endif
}

// Picks a lobe with probability prob[]; returns AW_LID_COUNT when no lobe has weight. On
// lanes: each lane's pick, the first lobe whose running sum passes u.
AW_FN luint material_pick_lobe(const LobeWeights* lw, lfloat u) {
  lfloat acc = (lfloat)(0.0f);
  luint last = (luint)(AW_LID_COUNT), pick = (luint)(AW_LID_COUNT);
  lmask found = (lmask)(0);
  for (uint i = 0; i < AW_LID_COUNT; ++i) {
    lmask has = lw->prob[i] > 0.0f;
    acc = L_SEL(has, acc + lw->prob[i], acc);
    last = L_SEL(has, (luint)(i), last);
    lmask here = has && !found && u < acc;
    pick = L_SEL(here, (luint)(i), pick);
    found = found || here;
  }
  return L_SEL(found, pick, last);  // round-off: the last lobe with weight
}

// Relative IOR n_far / n_near for a ray arriving from the `entering` side. Thin walls look
// the same from both sides. On lanes, each lane's.
AW_FN lfloat material_eta(lfloat ior, lmask entering, lmask thin) {
  return L_SEL(entering || thin, ior, 1.0f / ior);
}

// Reflection lobe i's Fresnel (0 = reflection, 1 = reflection2). Thin walls reflect from both
// faces (docs/material.md §3.6 "Thin walled"): a dielectric Fresnel becomes the pane's
// R' = R + T^2 R / (1 - R^2), in the lobe and in the energy split alike, so a pane's R' + T' = 1.
// A conductor or the artist curve is a reflectance as given (no light crosses a metal; the
// curve is the user's). Written on lanes: each lane's material.
AW_FN FresnelParams material_fresnel(MatL m, uint i, lmask entering) {
  lmask thin = material_is_thin(m);
  luint mode = MAT_U(m, refl[i].fresnel_mode);
  lfloat ior = MAT_F(m, refl[i].fresnel_ior);
  FresnelParams f;
  f.mode = L_SEL(thin && mode == AW_FRESNEL_DIELECTRIC, (luint)(AW_FRESNEL_THIN_DIELECTRIC), mode);
  f.eta = L_SEL(mode == AW_FRESNEL_CONDUCTOR, ior, material_eta(ior, entering, thin));
  f.k = MAT_F(m, refl[i].fresnel_k);
  f.facing = MAT_F(m, refl[i].facing);
  f.perpendicular = MAT_F(m, refl[i].perpendicular);
  f.curve = MAT_F(m, refl[i].curve);
  return f;
}

// The rest of the material is one path per call: not in a program built on lanes, which is
// built only for scenes whose materials need none of it (material/lobe_list.h,
// AW_LOBE_LIST_ON_LANES).
#if AW_LANES == 1

#include "lobes/reflection.h"
#include "lobes/thin_walled.h"

// Fresnel reflectance at the view angle (the split of docs/material.md §2 read literally).
AW_FN float material_view_fresnel(MatL m, uint i, float cos_o, int entering) {
  return clamp(fresnel_eval(material_fresnel(m, i, entering), cos_o), 0.0f, 1.0f);
}

// Reflection lobe i (0 = reflection, 1 = reflection2) as the shading stage samples it.
AW_FN ReflectionParams material_reflection_params(const AW_GLOBAL MaterialGpu* m, uint i, int entering) {
  const AW_GLOBAL ReflectionGpu* r = &m->refl[i];
  float3 tint = load_f3(r->color);
  if (i == 0u && (m->flags & AW_MAT_METAL)) tint = tint * material_diffuse_color(m);
  return reflection_params_make(tint, r->brdf, r->glossiness, m->aniso_amount, material_fresnel(m, i, entering));
}

// Rotates the tangent about n by 2 pi * rotation (anisotropy.rotation, docs/material.md §3.3).
AW_FN float3 rotate_tangent(float3 t, float3 n, float rotation) {
  if (rotation == 0.0f) return t;
  float a = 2.0f * M_PI_F * rotation;
  return cos(a) * t + sin(a) * cross(n, t);
}

// The frame the reflection lobes shade in: the rotated surface tangent for anisotropic
// materials, any frame around n otherwise. (The other lobes are isotropic: any frame.)
AW_FN void material_reflection_frame(const AW_GLOBAL MaterialGpu* m, float3 n, float3 tangent, float3* t, float3* b) {
  if (AW_FEAT_ANISOTROPY && m->aniso_amount != 0.0f) {
    // The tangent is orthogonal to the bumped normal; a lobe with disable_bump shades with
    // the other one, so it is made orthogonal to n again.
    if (AW_FEAT_BUMP && m->bump_binding != AW_NONE) {
      float3 tp = tangent - n * dot(n, tangent);
      float l2 = dot(tp, tp);
      if (l2 > 1e-12f) tangent = tp / sqrt(l2);
    }
    *t = rotate_tangent(tangent, n, m->aniso_rotation);
    *b = cross(n, *t);
  } else {
    make_frame(n, t, b);
  }
}

// docs/material.md §2 at view cosine cos_o, with the reflectances taken at the view angle;
// `entering` = the ray arrives on the outside of the surface (a ray arriving from inside a
// refractive object is subject to skip_weak_internal_reflections).
AW_FN LobeWeights material_lobe_weights(const AW_GLOBAL MaterialGpu* m, float cos_o, int entering) {
  float f1 = m->refl[0].weight > 0.0f ? material_view_fresnel(m, 0u, cos_o, entering) : 0.0f;
  float f2 = m->refl[1].weight > 0.0f ? material_view_fresnel(m, 1u, cos_o, entering) : 0.0f;
  return material_lobe_weights_f(m, f1, f2, entering);
}

// The material's reflectance at view cosine cos_o, for the albedo AOV (integrator/aov.h):
// each lobe's weight times its colour, reflection with Fresnel at the view angle. The
// reflection lobes' colours are their tints scaled to the luminance their weights carry
// (rho = weight * F * tint, so tint * lum(rho) / lum(tint) is rho itself).
AW_FN float3 material_albedo(const AW_GLOBAL MaterialGpu* m, float cos_o, int entering) {
  LobeWeights lw = material_lobe_weights(m, cos_o, entering);
  float3 a = lw.scale[AW_LID_DIFFUSE] * material_diffuse_color(m) +
             lw.scale[AW_LID_TRANSLUCENCY] * load_f3(m->transl_color) + lw.scale[AW_LID_REFRACTION];
  if (AW_FEAT_REFLECTION) {
    float3 t1 = load_f3(m->refl[0].color);
    if (m->flags & AW_MAT_METAL) t1 = t1 * material_diffuse_color(m);
    float3 t2 = load_f3(m->refl[1].color);
    float l1 = luminance(t1), l2 = luminance(t2);
    if (l1 > 0.0f) a = a + t1 * (lw.albedo[AW_LID_REFLECTION] / l1);
    if (l2 > 0.0f) a = a + t2 * (lw.albedo[AW_LID_REFLECTION2] / l2);
  }
  return a;
}


#endif  // AW_LANES == 1

// Reflection lobe i's reflectance for the split below: Fresnel at the microfacet normal that
// its sample draws from u (the surface normal for a mirror), wo in the reflection frame. On
// lanes the lobe is isotropic GGX or a mirror: a lane classify_hit is built only for scenes
// whose reflection lobes are (no Beckmann, Ashikhmin-Shirley or anisotropy:
// host/render/wavefront.cpp, build_lanes_program), and for those reflection_sample_normal
// (lobes/reflection.h) is exactly this.
AW_FN lfloat material_sampled_fresnel(MatL m, uint i, lfloat3 wo, lfloat2 u, lmask entering) {
#if AW_LANES == 1
  ReflectionParams p = material_reflection_params(m, i, entering);
  float3 h = reflection_sample_normal(p, wo, u);
  FresnelParams f = p.fresnel;
#else
  Microfacet mf;
  mf.ax = mf.ay = glossiness_to_alpha(MAT_F(m, refl[i].glossiness));
  mf.dist = (luint)(AW_MF_GGX);
  lfloat3 h = l3_sel(mf.ax < AW_MF_MIRROR_ALPHA, make_lfloat3((lfloat)(0.0f), (lfloat)(0.0f), (lfloat)(1.0f)),
                     mf_sample_visible(mf, wo, u));
  FresnelParams f = material_fresnel(m, i, entering);
#endif
  return clamp(fresnel_eval(f, clamp(l3_dot(wo, h), 0.0f, 1.0f)), 0.0f, 1.0f);
}

// The split the renderer uses: each reflection lobe's reflectance is its Fresnel at the
// microfacet normal that the lobe's own sample will draw from the same random numbers u
// (wo in the reflection frame, material_reflection_frame). Why: the lobe carries Fresnel at
// the microfacet (docs/material.md §3.4), so it reflects E[F(wo.h) g(h)] with g <= 1 (G2/G1 for
// Beckmann/GGX, cos_i / max(cos_i, cos_o) for Ashikhmin-Shirley), while a split at the view
// angle sets aside F(theta_o) < E[F(wo.h)] for rough lobes (F is convex): a rough Beckmann
// reflection over a smooth refraction returned up to 0.6% more energy than it received.
// With F(wo.h) in the split, reflection gets E[F g] <= E[F] and the rest E[1 - F], so the
// material never creates energy; for a mirror h = n and this is the view-angle split exactly.
// Unbiased: the lobe is chosen with probability p(h) and weighted 1/p(h) (NEE and BSDF
// sampling alike), so E over h of the indicator / p(h) is 1 for any h-dependent choice.
AW_FN LobeWeights material_lobe_weights_sampled(MatL m, lfloat3 wo, lfloat2 u, lmask entering) {
  lfloat f[2] = {(lfloat)(0.0f), (lfloat)(0.0f)};
  for (uint i = 0u; AW_FEAT_REFLECTION && i < 2u; ++i) {
    lmask has = MAT_F(m, refl[i].weight) > 0.0f;
    if (!L_ANY(has)) continue;
    f[i] = L_SEL(has, material_sampled_fresnel(m, i, wo, u, entering), (lfloat)(0.0f));
  }
  return material_lobe_weights_f(m, f[0], f[1], entering);
}

#endif
