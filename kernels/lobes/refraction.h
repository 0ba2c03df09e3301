// Refraction lobe: the TRANSMITTED part of a dielectric boundary, smooth (delta) or rough
// (Walter et al. 2007, "Microfacet Models for Refraction through Rough Surfaces", EGSR).
//
// Energy split. The material splits the energy before the lobes (docs/material.md §2): reflection
// takes F(theta_o) and this lobe gets what is left. So this lobe carries NO Fresnel factor:
// it is Walter's BTDF without its (1 - F) term. Smooth glass (reflection F, refraction 1 - F)
// is then lossless. Total internal reflection: where no refracted direction exists the sample
// fails (flags 0); fresnel_dielectric returns F = 1 there, so the material gives all the
// energy to reflection and nothing is lost (kernels/lobes/fresnel.h).
//
// Conventions (the caller sets them up):
// - Local frame with +z = the normal on the side of wo; the caller flips the frame when the
//   ray arrives from inside, so wo.z > 0 always and a transmitted wi has wi.z < 0.
// - eta = n(far side, where wi goes) / n(side of wo): 1.5 entering glass from air, 1/1.5
//   leaving it. In Walter's notation (i = wi, o = wo) eta = eta_i / eta_o; only the ratio
//   matters (Walter's formulas are invariant under scaling both indices), so eta_o = 1 below.
//
// Radiance scaling. We transport radiance (camera paths: wo points to the camera, wi to the
// light). Across a smooth boundary L / n^2 is conserved apart from the Fresnel factor (Veach
// 1997, "Robust Monte Carlo Methods for Light Transport Simulation", Sec. 5.2), so
// the radiance leaving towards wo is L_o = (n_o / n_i)^2 (1 - F) L_i = (1 / eta^2)(1 - F) L_i.
// A camera path entering a denser medium (eta > 1) therefore gets the factor 1/eta^2 < 1, one
// leaving it gets eta^2, and a path in and back out through parallel faces gets exactly 1.
// The BTDF is correspondingly not symmetric: f(wo -> wi; eta) * eta^2 = f(wi -> wo; 1/eta)
// (Veach 1997, Sec. 5.2, the generalised reciprocity f(a -> b) / n_b^2 = f(b -> a) / n_a^2;
// tests/lobes/test_refraction.cpp checks both). Measured as importance (times eta^2) the
// transmitted part of a smooth surface has albedo exactly 1, the rough one at most 1; measured
// as radiance they are 1/eta^2 and at most 1/eta^2.
//
// IOR 1: |eta - 1| < 1e-3 is a straight pass-through (wi = -wo exactly, weight 1) whatever the
// roughness (docs/material.md §1: glossiness has "no effect when IOR = 1"; §3.5).
#ifndef AW_LOBES_REFRACTION_H
#define AW_LOBES_REFRACTION_H

#include "common/compat.h"
#include "lobes/lobe.h"
#include "lobes/microfacet.h"

typedef struct {
  Microfacet mf;  // roughness of the interface; below AW_MF_MIRROR_ALPHA the lobe is a delta
  float eta;      // n(far side) / n(side of wo)
} RefractionParams;

// |eta - 1| below this is no interface at all (docs/material.md §3.5 "Refraction").
#define AW_REFRACTION_PASS_THROUGH_EPS 1e-3f

// Density reported for a delta sample: the probability mass of the chosen direction (the
// only one). Integrators recognise delta samples by AW_LOBE_SPECULAR, never by this value.
#define AW_REFRACTION_DELTA_PDF 1.0f

AW_FN RefractionParams refraction_params(float glossiness, uint dist, float eta) {
  RefractionParams p;
  float a = glossiness_to_alpha(glossiness);
  p.mf.ax = a;
  p.mf.ay = a;
  p.mf.dist = dist;
  p.eta = eta;
  return p;
}

AW_FN int refraction_is_pass_through(float eta) { return fabs(eta - 1.0f) < AW_REFRACTION_PASS_THROUGH_EPS; }

// Delta lobe: pass-through, or an interface smoother than the microfacet model resolves.
AW_FN int refraction_is_delta(RefractionParams p) {
  return refraction_is_pass_through(p.eta) || fmax(p.mf.ax, p.mf.ay) < AW_MF_MIRROR_ALPHA;
}

// Radiance factor of the transmitted part of a smooth boundary (see the header comment).
AW_FN float refraction_radiance_scale(float eta) { return 1.0f / (eta * eta); }

// cos(theta_t) >= 0 of the refracted direction for cos(theta_i) = cos_i (clamped to [0, 1]),
// or -1 under total internal reflection. Snell's law n_i sin_i = n_t sin_t with
// eta = n_t / n_i (pbrt-v4, Sec. 9.3) gives eta^2 cos_t^2 = eta^2 - 1 + cos_i^2; it is formed
// as g^2 = (eta - 1)(eta + 1) + cos_i^2, the same expression fresnel_dielectric uses (Walter
// et al. 2007, Eq. 22), so that "no refracted direction" here and "F = 1" there agree bit
// for bit (the material relies on it: all energy to reflection exactly when this fails). It
// also avoids the cancellation of 1 - sin_t^2 near grazing refraction. g^2 <= 0 (the critical
// angle included, where the refracted ray would be tangent) is total internal reflection.
AW_FN float refraction_cos_t(float cos_i, float eta) {
  float c = clamp(cos_i, 0.0f, 1.0f);
  if (!(eta > 0.0f)) return -1.0f;
  float g2 = (eta - 1.0f) * (eta + 1.0f) + c * c;
  if (!(g2 > 0.0f)) return -1.0f;  // total internal reflection
  return fmin(sqrt(g2) / eta, 1.0f);
}

// Refracts wo (unit, pointing away from the surface on the side n points to: dot(wo, n) >= 0)
// through the interface with normal n into the far side; returns 0 under total internal
// reflection (or when wo is below n) and leaves *wt untouched. The vector form of Snell's law
// (as in pbrt-v4's Refract(), Sec. 9.3, with wo pointing away from the surface):
//   wt = -wo / eta + (cos_i / eta - cos_t) n.
// eta exactly 1 returns wt = -wo exactly (no rounding through the formula).
AW_FN int refract_dir(float3 wo, float3 n, float eta, float3* wt) {
  float cos_i = dot(wo, n);
  if (!(cos_i >= 0.0f)) return 0;
  if (eta == 1.0f) {
    *wt = -wo;
    return 1;
  }
  float cos_t = refraction_cos_t(cos_i, eta);
  if (cos_t < 0.0f) return 0;
  float inv_eta = 1.0f / eta;
  float3 t = -wo * inv_eta + (fmin(cos_i, 1.0f) * inv_eta - cos_t) * n;
  float len = length(t);
  if (!(len > 0.0f)) return 0;
  *wt = t / len;
  return 1;
}

// Generalised half vector for transmission, Walter et al. 2007, Eq. 16:
// h_t = -(eta_i i + eta_o o) / |...| with i = wi, o = wo, eta_i = eta, eta_o = 1, oriented to
// +z. Returns 0 when the configuration is not a refraction through a microfacet h: wo must be
// in front of h and wi behind it (o.h and i.h of opposite signs, as Walter requires for a
// transmission half vector; with h.z > 0 that is wo.h > 0 > wi.h), or h is degenerate.
AW_FN int refraction_half_vector(float3 wo, float3 wi, float eta, float3* h) {
  float3 v = -(wo + eta * wi);
  float len = length(v);
  if (!(len > 0.0f)) return 0;
  v = v / len;
  if (v.z < 0.0f) v = -v;
  if (!(v.z > 0.0f)) return 0;
  if (!(dot(wo, v) > 0.0f) || !(dot(wi, v) < 0.0f)) return 0;
  *h = v;
  return 1;
}

// G2(wo, wi, h) / wo.z for a valid refraction configuration (wo.h > 0 > wi.h, wo.z > 0 > wi.z,
// as refraction_half_vector guarantees), with G2 the height-correlated Smith term of
// microfacet.h (Heitz 2014, Eq. 99, Lambda(wi) taken for -wi). Written with the projected
// area P(wo) = wo.z (1 + Lambda(wo)) as
//   G2 / wo.z = 1 / (wo.z (1 + Lambda(wo) + Lambda(-wi))) = 1 / (P(wo) + wo.z Lambda(-wi)),
// which stays finite and accurate as wo.z -> 0, where 1 + Lambda(wo) overflows its cap.
AW_FN float refraction_g2_over_cos_o(Microfacet m, float3 wo, float3 wi) {
  float den = mf_proj_area(m, wo) + wo.z * mf_lambda(m, -wi);
  return den > 0.0f ? 1.0f / den : 0.0f;
}

// f_t(wo, wi) |cos theta_i|. Walter et al. 2007, Eq. 21 without the (1 - F) factor, with
// eta_o = 1, eta_i = eta and h from Eq. 16:
//   f_t = |wi.h| |wo.h| / (|wi.z| |wo.z|) * G2(wo, wi) D(h) / (eta (wi.h) + (wo.h))^2
// (Walter's eta_o^2 numerator is 1 here). Times |wi.z|:
//   f_t |cos_i| = |wi.h| (wo.h) D(h) (G2 / wo.z) / (eta (wi.h) + (wo.h))^2.
// The denominator is |wo + eta wi|^2 > 0 whenever h exists. G2 is the height-correlated Smith
// term, used for transmission as pbrt-v4 does (Sec. 9.7); Heitz 2014's exact height-correlated
// transmission form (a Beta function, Sec. 6) differs slightly, and both keep the albedo
// <= 1/eta^2. Delta and pass-through lobes return 0.
AW_FN float3 lobe_refraction_eval(RefractionParams p, float3 wo, float3 wi) {
  float3 zero = make_float3(0.0f, 0.0f, 0.0f);
  if (refraction_is_delta(p) || !(p.eta > 0.0f)) return zero;
  if (!(wo.z > 0.0f) || !(wi.z < 0.0f)) return zero;
  float3 h;
  if (!refraction_half_vector(wo, wi, p.eta, &h)) return zero;
  float cos_oh = dot(wo, h);
  float cos_ih = dot(wi, h);
  float denom = p.eta * cos_ih + cos_oh;
  float d2 = denom * denom;
  if (!(d2 > 0.0f)) return zero;
  float f = fabs(cos_ih) * cos_oh * mf_D(p.mf, h) * refraction_g2_over_cos_o(p.mf, wo, wi) / d2;
  if (!(f > 0.0f) || !isfinite(f)) return zero;
  return make_float3(f, f, f);
}

// Solid-angle density of lobe_refraction_sample: a visible normal h of wo (mf_sample_visible:
// Heitz 2018 for GGX, Jakob 2014 for Beckmann), then refraction about h, so
// pdf(wi) = pdf_visible(h) |dh/dwi| with the Jacobian of Walter et al. 2007, Eq. 17 written
// for the sampled direction wi (eta_i = eta, eta_o = 1):
//   |dh/dwi| = eta^2 |wi.h| / (eta (wi.h) + (wo.h))^2.
// Visible normals whose refraction is impossible (TIR at that microfacet) make the sample
// fail, so this density integrates to less than 1 where that happens.
AW_FN float lobe_refraction_pdf(RefractionParams p, float3 wo, float3 wi) {
  if (refraction_is_delta(p) || !(p.eta > 0.0f)) return 0.0f;
  if (!(wo.z > 0.0f) || !(wi.z < 0.0f)) return 0.0f;
  float3 h;
  if (!refraction_half_vector(wo, wi, p.eta, &h)) return 0.0f;
  float cos_oh = dot(wo, h);
  float cos_ih = dot(wi, h);
  float denom = p.eta * cos_ih + cos_oh;
  float d2 = denom * denom;
  if (!(d2 > 0.0f)) return 0.0f;
  float pdf = mf_pdf_visible(p.mf, wo, h) * p.eta * p.eta * fabs(cos_ih) / d2;
  return (pdf > 0.0f && isfinite(pdf)) ? pdf : 0.0f;
}

// Samples the transmitted direction. Delta cases: pass-through (wi = -wo, weight 1) and the
// smooth interface (Snell direction, weight 1/eta^2, the radiance scaling; fails under total
// internal reflection). Rough: h from the visible normals of wo, wi = refract(wo, h); the
// sample fails when that refraction is impossible or leaves wi above the surface. Its weight
// eval/pdf simplifies (D and the Jacobian cancel) to
//   G2(wo, wi) / (G1(wo) eta^2) = (G2 / wo.z) P(wo) / eta^2,
// with P(wo) = wo.z / G1(wo) the projected area; computed from the h that eval and pdf
// recompute from wi, so that weight == eval / pdf to rounding.
AW_FN LobeSample lobe_refraction_sample(RefractionParams p, float3 wo, float2 u) {
  LobeSample s = lobe_no_sample();
  if (!(wo.z > 0.0f) || !(p.eta > 0.0f)) return s;

  if (refraction_is_pass_through(p.eta)) {
    s.wi = -wo;
    s.weight = make_float3(1.0f, 1.0f, 1.0f);
    s.pdf = AW_REFRACTION_DELTA_PDF;
    s.flags = AW_LOBE_SPECULAR | AW_LOBE_TRANSMISSION;
    return s;
  }

  if (refraction_is_delta(p)) {
    float3 wi;
    if (!refract_dir(wo, make_float3(0.0f, 0.0f, 1.0f), p.eta, &wi)) return s;  // TIR
    if (!(wi.z < 0.0f)) return s;  // exactly grazing: no transmission
    float w = refraction_radiance_scale(p.eta);
    s.wi = wi;
    s.weight = make_float3(w, w, w);
    s.pdf = AW_REFRACTION_DELTA_PDF;
    s.flags = AW_LOBE_SPECULAR | AW_LOBE_TRANSMISSION;
    s.eta_scale = p.eta * p.eta;
    return s;
  }

  float3 hs = mf_sample_visible(p.mf, wo, u);
  float3 wi;
  if (!refract_dir(wo, hs, p.eta, &wi)) return s;  // TIR at this microfacet: lost
  if (!(wi.z < 0.0f)) return s;                     // refracted back above the surface
  float pdf = lobe_refraction_pdf(p, wo, wi);
  if (!(pdf > 0.0f)) return s;
  float w = refraction_g2_over_cos_o(p.mf, wo, wi) * mf_proj_area(p.mf, wo) / (p.eta * p.eta);
  if (!(w > 0.0f) || !isfinite(w)) return s;
  s.wi = wi;
  s.weight = make_float3(w, w, w);
  s.pdf = pdf;
  s.flags = AW_LOBE_GLOSSY | AW_LOBE_TRANSMISSION;
  s.eta_scale = p.eta * p.eta;
  return s;
}

#endif
