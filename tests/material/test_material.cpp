// The whole Architectural material (docs/material.md §2) as the renderer uses it: the energy split
// of kernels/material/architectural.h, the lobe choice, and each lobe's sample, exactly as
// shade_surface runs them. White furnace: the expected throughput after one scattering,
// E[scale/prob * sample weight], is <= 1 for every parameter set, and = 1 for lossless ones.
// Transmission is measured as importance (x eta^2, kernels/lobes/refraction.h) so that a
// smooth dielectric conserves exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "kernels/integrator/shade_surface.h"

namespace {

MaterialGpu base_material() {
  MaterialGpu m;
  std::memset(&m, 0, sizeof(m));
  for (int c = 0; c < 3; ++c) {
    m.diffuse_color[c] = 1.0f;
    m.refr_color[c] = 1.0f;
    m.transl_color[c] = 1.0f;
    m.refl[0].color[c] = m.refl[1].color[c] = 1.0f;
  }
  for (int i = 0; i < 2; ++i) {
    m.refl[i].glossiness = 1.0f;
    m.refl[i].brdf = AW_BRDF_GGX;
    m.refl[i].fresnel_mode = AW_FRESNEL_DIELECTRIC;
    m.refl[i].fresnel_ior = 1.5f;
    m.refl[i].facing = 0.2f;
    m.refl[i].perpendicular = 1.0f;
    m.refl[i].curve = 5.0f;
  }
  m.diffuse_weight = 1.0f;
  m.refr_glossiness = 1.0f;
  m.refr_ior = 1.5f;
  m.highlight_vs_reflection = 1.0f;
  m.refl_depth = m.refr_depth = 8;
  return m;
}

struct Albedo {
  double mean, stderr_;
};

Albedo furnace(const MaterialGpu& m, float cos_o, int n = 200000, uint32_t seed = 7, int entering = 1) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> U(0.0f, 0.99999994f);
  float3 wo(std::sqrt(std::max(0.0f, 1.0f - cos_o * cos_o)), 0.0f, cos_o);
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < n; ++i) {
    // As classify_hit and shade_surface: the split takes the reflection lobes' Fresnel at the
    // microfacet that the lobe's sample draws from the same random numbers u.
    float2 u(U(rng), U(rng));
    LobeWeights lw = material_lobe_weights_sampled(&m, wo, u, entering);
    uint32_t lid = material_pick_lobe(&lw, U(rng));
    double v = 0.0;
    if (lid < AW_LID_COUNT) {
      LobeSetup l = lobe_setup(&m, lid, entering);
      LobeSample s = lobe_sample(&l, wo, u);
      if (s.flags) {
        float3 w = s.weight * lw.scale[lid] / lw.prob[lid];
        v = luminance(w);
        if (lid == AW_LID_REFRACTION && !l.thin && (s.flags & AW_LOBE_TRANSMISSION))
          v *= double(l.refr.eta) * l.refr.eta;  // importance
      }
    }
    EXPECT_TRUE(std::isfinite(v));
    sum += v;
    sum2 += v * v;
  }
  double mean = sum / n;
  double var = std::max(0.0, sum2 / n - mean * mean);
  return {mean, std::sqrt(var / n)};
}

TEST(MaterialFurnace, LosslessConfigurationsGiveOne) {
  const float cosines[] = {1.0f, 0.7f, 0.3f, 0.05f};
  {  // Lambert, albedo 1, no reflection
    MaterialGpu m = base_material();
    m.refl[0].weight = 0.0f;
    for (float c : cosines) {
      Albedo a = furnace(m, c);
      EXPECT_NEAR(a.mean, 1.0, 1e-5) << "Lambert at cos " << c;
    }
  }
  {  // smooth dielectric: reflection F + refraction (1 - F)
    MaterialGpu m = base_material();
    m.refl[0].weight = 1.0f;
    m.refr_weight = 1.0f;
    for (float c : cosines) {
      Albedo a = furnace(m, c);
      EXPECT_NEAR(a.mean, 1.0, 4.0 * a.stderr_ + 1e-4) << "smooth glass at cos " << c;
    }
  }
  {  // smooth thin pane: both faces' reflections R' (lobe and split alike) plus the
     // straight-through T' = 1 - R'
    MaterialGpu m = base_material();
    m.refl[0].weight = 1.0f;
    m.refr_weight = 1.0f;
    m.flags |= AW_MAT_THIN_WALLED;
    for (float c : cosines) {
      Albedo a = furnace(m, c);
      EXPECT_NEAR(a.mean, 1.0, 4.0 * a.stderr_ + 1e-4) << "thin pane at cos " << c;
    }
  }
  {  // inside smooth glass: below the critical angle reflection F + refraction 1 - F; past it,
     // total internal reflection takes everything, also with reflection.weight < 1 (the
     // refraction share is reflected). Default weight 0.6.
    MaterialGpu m = base_material();
    m.refl[0].weight = 0.6f;
    m.refr_weight = 1.0f;
    for (float c : {1.0f, 0.9f, 0.5f /* past the critical angle of 1/1.5 */, 0.1f}) {
      Albedo a = furnace(m, c, 200000, 9, /*entering=*/0);
      EXPECT_LE(a.mean, 1.0 + 4.0 * a.stderr_ + 1e-4) << "inside glass at cos " << c;
      if (c < 0.74f) {
        EXPECT_NEAR(a.mean, 1.0, 1e-5) << "total internal reflection at cos " << c;
      }
    }
  }
  {  // perfect mirror (curve 1/1)
    MaterialGpu m = base_material();
    m.refl[0].weight = 1.0f;
    m.refl[0].fresnel_mode = AW_FRESNEL_CURVE;
    m.refl[0].facing = m.refl[0].perpendicular = 1.0f;
    for (float c : cosines) EXPECT_NEAR(furnace(m, c).mean, 1.0, 1e-5) << "mirror at cos " << c;
  }
}

// Every combination on the grid conserves energy (<= 1 + 4 sigma).
TEST(MaterialFurnace, NeverCreatesEnergy) {
  const uint32_t brdfs[] = {AW_BRDF_BECKMANN, AW_BRDF_GGX, AW_BRDF_ASHIKHMIN_SHIRLEY, AW_BRDF_ASHIKHMIN_SHIRLEY_LEGACY};
  const float gloss[] = {0.05f, 0.5f, 0.9f, 1.0f};
  const uint32_t fresnel[] = {AW_FRESNEL_DIELECTRIC, AW_FRESNEL_CONDUCTOR, AW_FRESNEL_CURVE};
  int cases = 0;
  for (uint32_t b : brdfs)
    for (float g : gloss)
      for (uint32_t f : fresnel)
        for (int variant = 0; variant < 7; ++variant) {
          MaterialGpu m = base_material();
          m.refl[0].weight = 1.0f;
          m.refl[0].brdf = b;
          m.refl[0].glossiness = g;
          m.refl[0].fresnel_mode = f;
          m.refl[0].fresnel_k = 2.0f;
          m.refl[1].weight = 0.5f;
          m.refl[1].glossiness = 1.0f - g * 0.5f;
          m.diffuse_roughness = 0.5f;
          if (variant == 1) m.flags |= AW_MAT_METAL;
          if (variant == 2) m.refr_weight = 1.0f, m.refr_glossiness = g;
          if (variant == 3) m.refr_weight = 0.7f, m.flags |= AW_MAT_TRANSLUCENCY, m.transl_weight = 0.5f;
          if (variant == 4) m.refr_weight = 1.0f, m.flags |= AW_MAT_THIN_WALLED, m.aniso_amount = 0.8f;
          // Smooth refraction takes all that the split leaves, so nothing hides a rough
          // reflection lobe that reflects more than it was given (isotropic and anisotropic).
          if (variant == 5) m.refr_weight = 1.0f;
          if (variant == 6) m.refr_weight = 1.0f, m.aniso_amount = -0.8f;
          for (float c : {1.0f, 0.5f, 0.1f}) {
            Albedo a = furnace(m, c, 40000, 11 + cases);
            ++cases;
            EXPECT_LE(a.mean, 1.0 + 4.0 * a.stderr_ + 1e-4)
                << "brdf " << b << " glossiness " << g << " fresnel " << f << " variant " << variant << " cos " << c;
          }
        }
  EXPECT_EQ(cases, 4 * 4 * 3 * 7 * 3);
}

// The case that showed the split must take Fresnel where the lobe does: glass (smooth
// refraction takes all the split leaves) with a rough Beckmann reflection (little masking).
// With the reflectance taken at the view angle this returned 1.0028 +- 0.0001 at cos 0.7 and,
// anisotropic, 1.0059 +- 0.0001 at cos 0.5 (400k samples): energy created. Taken at the
// sampled microfacet (material_lobe_weights_sampled) it must stay <= 1 + 4 sigma.
TEST(MaterialFurnace, RoughBeckmannOverSmoothGlassCreatesNoEnergy) {
  for (float aniso : {0.0f, 0.8f})
    for (float c : {0.9f, 0.7f, 0.5f}) {
      MaterialGpu m = base_material();
      m.refl[0].weight = 1.0f;
      m.refl[0].brdf = AW_BRDF_BECKMANN;
      m.refl[0].glossiness = 0.5f;
      m.aniso_amount = aniso;
      m.refr_weight = 1.0f;
      Albedo a = furnace(m, c, 400000, 5);
      EXPECT_LE(a.mean, 1.0 + 4.0 * a.stderr_ + 1e-4) << "anisotropy " << aniso << " cos " << c;
    }
}

// docs/material.md §2: the order reflection -> refraction -> diffuse; a mirror wins.
TEST(MaterialWeights, OrderAndMirrorWins) {
  MaterialGpu m = base_material();
  m.refl[0].weight = 1.0f;
  m.refl[0].fresnel_mode = AW_FRESNEL_CURVE;
  m.refl[0].facing = m.refl[0].perpendicular = 1.0f;
  m.refr_weight = 1.0f;
  LobeWeights lw = material_lobe_weights(&m, 0.8f, 1);
  EXPECT_EQ(lw.prob[AW_LID_DIFFUSE], 0.0f);
  EXPECT_EQ(lw.prob[AW_LID_REFRACTION], 0.0f);
  EXPECT_FLOAT_EQ(lw.prob[AW_LID_REFLECTION], 1.0f);
  // Half reflective: refraction takes the rest, diffuse gets what refraction leaves.
  m.refl[0].facing = m.refl[0].perpendicular = 0.5f;
  m.refr_weight = 0.6f;
  lw = material_lobe_weights(&m, 0.8f, 1);
  EXPECT_NEAR(lw.scale[AW_LID_REFRACTION].x, 0.6f * 0.5f, 1e-6);
  EXPECT_NEAR(lw.scale[AW_LID_DIFFUSE].x, 0.5f * (1.0f - 0.6f), 1e-6);
  // Equal facing and perpendicular: the split does not depend on the view angle.
  LobeWeights a = material_lobe_weights(&m, 1.0f, 1), b = material_lobe_weights(&m, 0.05f, 1);
  for (uint32_t i = 0; i < AW_LID_COUNT; ++i) EXPECT_FLOAT_EQ(a.prob[i], b.prob[i]);
}

}  // namespace
