// Fresnel reflectance: exact unpolarised dielectric (with total internal reflection), exact
// conductor with a scalar complex IOR n + ik, and the artist curve of the Architectural
// material (docs/material.md §3.4). No lobe state; written on lanes (below).
//
// All three take cos_i, the cosine between the incident direction and the normal ON THE
// INCIDENT SIDE (so >= 0; it is clamped to [0, 1]). Inside a microfacet lobe this is the
// microfacet angle, dot(wo, wm).
#ifndef AW_LOBES_FRESNEL_H
#define AW_LOBES_FRESNEL_H

#include "common/compat.h"
#include "common/features.h"
#include "common/lanes.h"

// The modes (AW_FRESNEL_*) are the values of ReflectionGpu.fresnel_mode: types/material.h.
#include "types/material.h"

// Passed by value (OpenCL C has no references). `eta` is n_transmitted / n_incident for the
// dielectric and the conductor's n for the conductor (its k in `k`); the curve uses
// facing / perpendicular / curve. Written on lanes (common/lanes.h): at W = 1 the plain
// scalars; at W > 1 each lane's reflection (the energy split of classify_hit on lanes,
// material/architectural.h), every branch a select per lane, so each lane computes what W = 1
// computes for its path.
typedef struct {
  luint mode;
  lfloat eta;
  lfloat k;
  lfloat facing;
  lfloat perpendicular;
  lfloat curve;
} FresnelParams;

// Exact unpolarised reflectance of a smooth dielectric interface, eta = n_t / n_i > 0.
//
// The Fresnel amplitude coefficients (Born & Wolf, "Principles of Optics", 7th ed., Sec.
// 1.5.2, the Fresnel formulae), with c = cos_i and cos_t from Snell's law:
//   r_s = (c - eta cos_t) / (c + eta cos_t),   r_p = (eta c - cos_t) / (eta c + cos_t),
//   R = (r_s^2 + r_p^2) / 2  (unpolarised light: the mean of the two polarisations).
// Written with g = eta cos_t = sqrt(eta^2 - 1 + c^2) (the form of Cook & Torrance 1982 and
// Walter et al. 2007, Eq. 22): r_s = (c - g)/(c + g), r_p = (eta^2 c - g)/(eta^2 c + g)
// (r_p multiplied through by eta). g^2 takes eta^2 - 1 as (eta - 1)(eta + 1) and never forms
// 1 - sin^2, so there is no cancellation near eta = 1 or at grazing angles.
// g^2 < 0 is total internal reflection (sin_t > 1): R = 1. eta == 1 is no interface: R = 0
// exactly (also at c = 0, where the formula would be 0/0). (Those two cases are selected
// over the formula's value, which may be NaN there and is then not used.)
AW_FN lfloat fresnel_dielectric(lfloat cos_i, lfloat eta) {
  lmask none = eta == 1.0f;
  eta = fmin(eta, 1e6f);  // eta = inf would make r_s = inf/inf; R is within 4e-6 of 1 there anyway
  lfloat c = clamp(cos_i, 0.0f, 1.0f);
  lfloat g2 = (eta - 1.0f) * (eta + 1.0f) + c * c;
  lmask tir = !(g2 > 0.0f);  // total internal reflection (and the critical angle itself)
  lfloat g = sqrt(fmax(g2, 0.0f));
  lfloat rs = (c - g) / (c + g);
  lfloat e2c = eta * eta * c;
  lfloat rp = (e2c - g) / (e2c + g);
  return L_SEL(none, (lfloat)(0.0f), L_SEL(tir, (lfloat)(1.0f), 0.5f * (rs * rs + rp * rp)));
}

// Exact unpolarised reflectance of a conductor with complex IOR eta = n + ik relative to the
// incident medium (Born & Wolf, Ch. 14, optics of metals: the dielectric Fresnel formulae
// hold with the complex refractive index). The same g form as fresnel_dielectric with
// complex arithmetic: g = sqrt(eta^2 - 1 + c^2) (principal root: Re g, Im g >= 0, the wave
// decaying into the metal), eta^2 = (n^2 - k^2) + 2nk i, and
//   R_s = |c - g|^2 / |c + g|^2,   R_p = |eta^2 c - g|^2 / |eta^2 c + g|^2,   R = (R_s + R_p)/2.
// k = 0 is the dielectric (returned through fresnel_dielectric, so the two agree exactly).
// n and k are clamped to [0, 1e6]: squares stay far from float overflow, and beyond that the
// reflectance differs from 1 by less than 4n/(n^2 + k^2) < 4e-6.
AW_FN lfloat fresnel_conductor(lfloat cos_i, lfloat n, lfloat k) {
  n = clamp(n, 0.0f, 1e6f);
  k = clamp(k, 0.0f, 1e6f);
  lmask dielectric = k == 0.0f;
  if (L_ALL(dielectric)) return fresnel_dielectric(cos_i, n);
  lfloat c = clamp(cos_i, 0.0f, 1.0f);
  // eta^2 and g^2 = eta^2 - 1 + c^2.
  lfloat er = (n - k) * (n + k);
  lfloat ei = 2.0f * n * k;
  lfloat xr = er - 1.0f + c * c;
  lfloat xi = ei;
  // Principal complex square root of (xr, xi), xi >= 0. The root that needs no subtraction is
  // computed first; the other one from gr * gi = xi / 2 (no cancellation when xr < 0).
  lfloat r = sqrt(xr * xr + xi * xi);
  lmask xr_pos = xr >= 0.0f;
  lfloat first = sqrt(0.5f * L_SEL(xr_pos, r + xr, r - xr));  // gr where xr >= 0, else gi
  lfloat second = L_SEL(first > 0.0f, 0.5f * xi / first, (lfloat)(0.0f));
  lfloat gr = L_SEL(xr_pos, first, second);
  lfloat gi = L_SEL(xr_pos, second, first);
  lfloat rs_num = (c - gr) * (c - gr) + gi * gi;
  lfloat rs_den = (c + gr) * (c + gr) + gi * gi;
  lfloat ar = er * c, ai = ei * c;  // eta^2 c
  lfloat rp_num = (ar - gr) * (ar - gr) + (ai - gi) * (ai - gi);
  lfloat rp_den = (ar + gr) * (ar + gr) + (ai + gi) * (ai + gi);
  // Both denominators are > 0 for k > 0 (g != 0 and Re, Im of g and eta^2 c are >= 0);
  // the floor only guards the impossible case against a NaN.
  lfloat rs = rs_num / fmax(rs_den, 1e-30f);
  lfloat rp = rp_num / fmax(rp_den, 1e-30f);
  lfloat R = clamp(0.5f * (rs + rp), 0.0f, 1.0f);
  if (L_ANY(dielectric)) R = L_SEL(dielectric, fresnel_dielectric(cos_i, n), R);
  return R;
}

// The Architectural material's artist curve (docs/material.md §3.4, from the mia_material
// "BRDF curve"): R = facing + (perpendicular - facing) (1 - cos_i)^curve. Equal facing and
// perpendicular give exactly `facing` at every angle. curve < 0 is clamped to 0 (a negative
// exponent would put infinity at normal incidence); pow(0, 0) = 1 on both sides.
// A power below FLT_MIN (a subnormal, a reflectance of less than 1.2e-38) is taken as 0: PoCL
// 3.1's pow on a vector rounds subnormal results differently from its pow on one float (by up
// to 1.4e-45, found by LaneMath.PowRoundsAsOnAScalar), and the films of the lane program and
// the one-path kernels must be the same bit for bit; above FLT_MIN the two round alike.
AW_FN lfloat fresnel_curve(lfloat cos_i, lfloat facing, lfloat perpendicular, lfloat curve) {
  lfloat c = clamp(cos_i, 0.0f, 1.0f);
  lfloat p = pow(1.0f - c, fmax(curve, 0.0f));
  p = L_SEL(p < 1.17549435e-38f, (lfloat)(0.0f), p);  // FLT_MIN
  return facing + (perpendicular - facing) * p;
}

// R' of a thin pane from the single-interface reflectance R in [0, 1]: R' = 2R / (1 + R), the
// sum of the inter-reflections between its two faces (derivation in lobes/thin_walled.h).
AW_FN lfloat thin_wall_reflectance(lfloat R) {
  R = clamp(R, 0.0f, 1.0f);
  return 2.0f * R / (1.0f + R);
}

// Modes a specialised build lacks fold away (common/features.h; the dielectric is always built).
// On lanes each mode's formula runs when any lane has that mode.
AW_FN lfloat fresnel_eval(FresnelParams f, lfloat cos_i) {
  lmask conductor = AW_FEAT_FRESNEL_CONDUCTOR && f.mode == AW_FRESNEL_CONDUCTOR;
  lmask curve = AW_FEAT_FRESNEL_CURVE && f.mode == AW_FRESNEL_CURVE;
  lmask thin = AW_FEAT_THIN_WALLED && f.mode == AW_FRESNEL_THIN_DIELECTRIC;
  lmask dielectric = !conductor && !curve;
  lfloat r = (lfloat)(0.0f);
  if (L_ANY(dielectric)) {
    lfloat d = fresnel_dielectric(cos_i, f.eta);
    r = L_SEL(thin, thin_wall_reflectance(d), d);
  }
  if (L_ANY(conductor)) r = L_SEL(conductor, fresnel_conductor(cos_i, f.eta, f.k), r);
  if (L_ANY(curve)) r = L_SEL(curve, fresnel_curve(cos_i, f.facing, f.perpendicular, f.curve), r);
  return r;
}

#endif
