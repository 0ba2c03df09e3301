// Diffuse reflection: the energy-preserving Oren–Nayar model "EON" (Portsmouth, Kutz & Hill
// 2025, "EON: A Practical Energy-Preserving Rough Diffuse BRDF", JCGT 14(1); arXiv:2410.18026;
// "EON paper" below). Roughness 0 is exactly Lambert (docs/material.md §3.1), through its own code
// path, so renders without roughness do not change by a single bit.
//
// The model, in the paper's notation (sigma = roughness in [0, 1], rho = albedo,
// mu_i = cos theta_i, mu_o = cos theta_o, both directions above the surface):
//
//  1. Single scattering: Fujii's "improved" qualitative Oren–Nayar model (FON; Fujii 2013,
//     "A tiny improvement of Oren-Nayar reflectance model"), the EON paper's starting point:
//       f_ss = (rho / pi) A_F (1 + sigma s / t),   A_F = 1 / (1 + c1 sigma),
//       s = dot(wi, wo) - mu_i mu_o  (= sin theta_i sin theta_o cos(phi_i - phi_o)),
//       t = max(mu_i, mu_o) where s > 0, else 1,
//       c1 = 1/2 - 2/(3 pi)  (A_F normalises FON so its albedo is 1 at grazing, see 2.).
//  2. Its directional albedo at rho = 1 in closed form (the paper's analytic E_FON):
//       E_F(mu) = A_F (1 + sigma G(mu) / pi),
//       G(mu) = S (acos(mu) - S mu) + (2/3) ((S / mu)(1 - S^3) - S),   S = sqrt(1 - mu^2),
//     and its cosine-weighted average  E_avg = A_F (1 + c2 sigma),  c2 = 2/3 - 28/(15 pi).
//  3. Energy compensation (the paper's multiple-scattering lobe, in the form of Kulla & Conty
//     2017, "Revisiting Physically Based Shading at Imageworks"):
//       f_ms = (rho_ms / pi) (1 - E_F(mu_o)) (1 - E_F(mu_i)) / (1 - E_avg),
//       rho_ms = rho^2 E_avg / (1 - rho (1 - E_avg)).
//     With rho = 1, rho_ms = 1 and f_ms integrates to exactly 1 - E_F(mu_o): the albedo of
//     f_ss + f_ms is 1 at every angle and roughness (white furnace = 1, tested).
//  4. Directional albedo of the whole lobe:  E(mu_o) = rho E_F(mu_o) + rho_ms (1 - E_F(mu_o)).
//
// Numerics (ours, not the paper's): 1 - E_F and 1 - E_avg are formed without subtraction,
//   1 - E_F(mu) = sigma A_F (c1 - G(mu)/pi),   1 - E_avg = sigma A_F (c1 - c2),
// so f_ms stays accurate (and 0/0-free) as sigma -> 0; and (S/mu)(1 - S^3) is rewritten as
// S mu (1 + S + S^2) / (1 + S) (using 1 - S = mu^2 / (1 + S)), which is finite at mu = 0.
//
// Sampling: cosine-weighted for every roughness (docs/material.md §3.1 asks for it; the paper's
// CLTC importance sampling is not implemented). The pdf is exactly cos/pi, so sample weights
// are pi f: 1 at sigma = 0, and bounded by rho A_F (1 + sigma tan theta_o) + the (smaller)
// multiple-scattering term otherwise — largest at grazing view, where CLTC would reduce
// variance.
#ifndef AW_LOBES_DIFFUSE_H
#define AW_LOBES_DIFFUSE_H

#include "common/sampling.h"
#include "lobes/lobe.h"

#define AW_EON_C1 (0.5f - 2.0f / (3.0f * M_PI_F))             // 1/2 - 2/(3 pi)
#define AW_EON_C2 (2.0f / 3.0f - 28.0f / (15.0f * M_PI_F))    // 2/3 - 28/(15 pi)

// G(mu) of the FON directional albedo (item 2 above), for mu in [0, 1]; G(1) = 0 and
// G(0) = pi/2 - 2/3 = pi c1 (so E_F(0) = 1).
AW_FN lfloat eon_g(lfloat mu) {
  mu = clamp(mu, 0.0f, 1.0f);
  lfloat s = l_safe_sqrt(1.0f - mu * mu);
  lfloat s_over_mu_term = s * mu * (1.0f + s + s * s) / (1.0f + s);  // (S/mu)(1 - S^3)
  return s * (l_acos(mu) - s * mu) + (2.0f / 3.0f) * (s_over_mu_term - s);
}

// (1 - E_F(mu)) / (sigma A_F) = c1 - G(mu)/pi >= 0 (item 2, without cancellation in sigma).
AW_FN lfloat eon_one_minus_ef_scaled(lfloat mu) {
  return fmax(AW_EON_C1 - eon_g(mu) * (1.0f / M_PI_F), (lfloat)(0.0f));
}

// rho_ms (item 3) for one channel, sigma > 0. The denominator is >= E_avg > 0.8 for rho <= 1;
// the floor only keeps out-of-range albedos (> 6) from dividing by zero.
AW_FN lfloat eon_rho_ms(lfloat rho, lfloat e_avg, lfloat one_minus_e_avg) {
  return rho * rho * e_avg / fmax(1.0f - rho * one_minus_e_avg, (lfloat)(1e-6f));
}

AW_FN lfloat3 eon_rho_ms3(lfloat3 rho, lfloat e_avg, lfloat one_minus_e_avg) {
  return make_lfloat3(eon_rho_ms(rho.x, e_avg, one_minus_e_avg), eon_rho_ms(rho.y, e_avg, one_minus_e_avg),
                      eon_rho_ms(rho.z, e_avg, one_minus_e_avg));
}

// f * cos theta_i. On lanes (common/lanes.h): Lambert for every path, EON computed only when
// some path is rough (at W = 1: only for a rough path, as a branch) and selected for those.
AW_FN lfloat3 lobe_diffuse_eval(lfloat3 albedo, lfloat roughness, lfloat3 wo, lfloat3 wi) {
  lmask none = wo.z <= 0.0f || wi.z <= 0.0f;
  lmask rough = roughness != 0.0f;
  lfloat3 r = l3_scale(albedo, wi.z * (1.0f / M_PI_F));  // Lambert, unchanged
  if (L_ANY(rough && !none)) {
    lfloat sigma = clamp(roughness, 0.0f, 1.0f);
    lfloat mu_i = fmin(wi.z, 1.0f), mu_o = fmin(wo.z, 1.0f);
    lfloat a_f = 1.0f / (1.0f + AW_EON_C1 * sigma);
    // Item 1 times cos theta_i: f_ss mu_i = (rho/pi) A_F (mu_i + sigma s mu_i / t). Written with
    // mu_i / t <= 1 (t = max(mu_i, mu_o) when s > 0) it stays bounded by (rho/pi) A_F
    // (mu_i + sigma) even where s / t alone grows without bound (both directions grazing).
    lfloat s = l3_dot(wi, wo) - mu_i * mu_o;
    lfloat s_mu_over_t = L_SEL(s > 0.0f, s * (mu_i / fmax(mu_i, mu_o)), s * mu_i);
    lfloat ss = a_f * (1.0f / M_PI_F) * (mu_i + sigma * s_mu_over_t);
    // Item 3 with item 2's cancellation-free forms: the common sigma A_F factors give
    //   f_ms = (rho_ms / pi) sigma A_F (c1 - G_o/pi)(c1 - G_i/pi) / (c1 - c2).
    lfloat e_avg = a_f * (1.0f + AW_EON_C2 * sigma);
    lfloat one_minus_e_avg = sigma * a_f * (AW_EON_C1 - AW_EON_C2);
    lfloat ms = sigma * a_f * eon_one_minus_ef_scaled(mu_o) * eon_one_minus_ef_scaled(mu_i) /
                (AW_EON_C1 - AW_EON_C2) * (1.0f / M_PI_F) * mu_i;
    lfloat3 rho_ms = eon_rho_ms3(albedo, e_avg, one_minus_e_avg);
    // 1 + sigma s/t >= 0 (s/t >= -1, sigma <= 1), so only rounding could make this negative.
    lfloat3 eon = l3_fmax(l3_add(l3_scale(albedo, ss), l3_scale(rho_ms, ms)),
                          make_lfloat3((lfloat)(0.0f), (lfloat)(0.0f), (lfloat)(0.0f)));
    r = l3_sel(rough, eon, r);
  }
  return l3_sel(none, make_lfloat3((lfloat)(0.0f), (lfloat)(0.0f), (lfloat)(0.0f)), r);
}

// Cosine-weighted for every roughness (see the header comment).
AW_FN lfloat lobe_diffuse_pdf(lfloat roughness, lfloat3 wo, lfloat3 wi) {
  lmask none = wo.z <= 0.0f || wi.z <= 0.0f;
  return L_SEL(none, (lfloat)(0.0f), pdf_cosine_hemisphere(wi.z));
}

AW_FN LobeSample lobe_diffuse_sample(lfloat3 albedo, lfloat roughness, lfloat3 wo, lfloat2 u) {
  LobeSample s = lobe_no_sample();
  s.wi = sample_cosine_hemisphere(u);
  lfloat pdf = lobe_diffuse_pdf(roughness, wo, s.wi);
  lmask ok = pdf > 0.0f;
  // Lambert: f cos / pdf is exactly the albedo (the pre-EON code path, bit for bit).
  // EON: eval / pdf, with the same pdf the caller's MIS will see.
  // (A division, not a reciprocal: 1/pdf overflows for subnormal pdfs where eval/pdf does not.)
  lfloat3 weight = albedo;
  lmask rough = roughness != 0.0f;
  if (L_ANY(rough && ok)) weight = l3_sel(rough, l3_div(lobe_diffuse_eval(albedo, roughness, wo, s.wi), pdf), weight);
  // A failed sample: weight, flags and pdf 0 (wi keeps the drawn direction).
  s.weight = l3_sel(ok, weight, make_lfloat3((lfloat)(0.0f), (lfloat)(0.0f), (lfloat)(0.0f)));
  s.flags = L_SEL(ok, (luint)(AW_LOBE_DIFFUSE_REFLECTION), (luint)(0u));
  s.pdf = L_SEL(ok, pdf, (lfloat)(0.0f));
  return s;
}

// Directional albedo E(wo) = integral of f cos over the hemisphere (item 4), per channel, for
// lobe selection weights. cos_o <= 0 (view below the surface): 0, as eval.
AW_FN lfloat3 lobe_diffuse_albedo(lfloat3 albedo, lfloat roughness, lfloat cos_o) {
  lmask none = cos_o <= 0.0f;
  lmask rough = roughness != 0.0f;
  lfloat3 r = albedo;
  if (L_ANY(rough && !none)) {
    lfloat sigma = clamp(roughness, 0.0f, 1.0f);
    lfloat a_f = 1.0f / (1.0f + AW_EON_C1 * sigma);
    lfloat one_minus_ef = sigma * a_f * eon_one_minus_ef_scaled(cos_o);
    lfloat ef = 1.0f - one_minus_ef;
    lfloat e_avg = a_f * (1.0f + AW_EON_C2 * sigma);
    lfloat one_minus_e_avg = sigma * a_f * (AW_EON_C1 - AW_EON_C2);
    lfloat3 rho_ms = eon_rho_ms3(albedo, e_avg, one_minus_e_avg);
    r = l3_sel(rough, l3_add(l3_scale(albedo, ef), l3_scale(rho_ms, one_minus_ef)), r);
  }
  return l3_sel(none, make_lfloat3((lfloat)(0.0f), (lfloat)(0.0f), (lfloat)(0.0f)), r);
}

#endif
