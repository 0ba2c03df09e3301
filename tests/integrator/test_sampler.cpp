// The samplers of kernels/common/rng.h (docs/architecture.md, "Random numbers"): the
// Owen-scrambled Sobol' sampler's stratification, which is what makes it converge faster
// than white noise, its decorrelation across dimensions and pixels, and the independent
// sampler kept as it was.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "kernels/common/ray.h"
#include "kernels/common/rng.h"
#include "kernels/common/sampling.h"
#include "tests/lobes/lobe_harness.h"

namespace {

// 24-bit fixed point of a sample (rng_to_unit keeps the top 24 bits exactly).
uint32_t fixed24(float u) { return uint32_t(double(u) * 16777216.0); }

// The points of (pixel, sample) pairs `ps` of one (bounce, dim) set fall one per elementary
// interval of area 2^-k, k = log2 of their count, for every shape 2^a x 2^(k-a): a
// (0,k,2)-net. `what` names the case in failure messages.
void expect_net(Sampler smp, const std::vector<std::pair<uint32_t, uint32_t>>& ps, uint32_t bounce, uint32_t dim,
                const std::string& what) {
  const uint32_t n = uint32_t(ps.size());
  int k = 0;
  while ((1u << k) < n) ++k;
  ASSERT_EQ(1u << k, n);
  std::vector<uint32_t> x(n), y(n);
  for (uint32_t i = 0; i < n; ++i) {
    float2 u = rng_2d(smp, ps[i].first, ps[i].second, bounce, dim);
    ASSERT_TRUE(u.x >= 0.0f && u.x < 1.0f && u.y >= 0.0f && u.y < 1.0f);
    x[i] = fixed24(u.x);
    y[i] = fixed24(u.y);
  }
  for (int a = 0; a <= k; ++a) {
    std::vector<int> cells(n, 0);
    for (uint32_t i = 0; i < n; ++i) {
      uint32_t cx = a == 0 ? 0u : x[i] >> (24 - a), cy = k - a == 0 ? 0u : y[i] >> (24 - (k - a));
      ++cells[(cx << (k - a)) | cy];
    }
    for (uint32_t c = 0; c < n; ++c)
      ASSERT_EQ(cells[c], 1) << "k=" << k << " shape 2^" << a << " x 2^" << k - a << " cell " << c << " " << what;
  }
}

// The points i in [first, first + 2^k) of one (seed, pixel, bounce, dim) set of `sobol`.
void expect_2d_net(uint32_t seed, uint32_t pixel, uint32_t bounce, uint32_t dim, int k, uint32_t first) {
  std::vector<std::pair<uint32_t, uint32_t>> ps;
  for (uint32_t i = 0; i < (1u << k); ++i) ps.push_back({pixel, first + i});
  expect_net(sampler_make(AW_SAMPLER_SOBOL, seed, 0u, 0u, 0u), ps, bounce, dim,
             "seed " + std::to_string(seed) + " pixel " + std::to_string(pixel) + " bounce " + std::to_string(bounce) +
                 " dim " + std::to_string(dim) + " first " + std::to_string(first));
}

TEST(SobolSampler, FirstPowerOfTwoSamplesOfEveryPixelAndSetAreNets) {
  for (uint32_t seed : {0u, 7u})
    for (uint32_t pixel : {0u, 1u, 12345u})
      for (uint32_t bounce : {0u, 3u})
        for (uint32_t dim : {uint32_t(AW_DIM_CAMERA), uint32_t(AW_DIM_LIGHT), uint32_t(AW_DIM_BSDF)})
          for (int k = 0; k <= 10; ++k) expect_2d_net(seed, pixel, bounce, dim, k, 0u);
}

// Lobe-splitting children draw sample + s * spp (integrator/split.h): with a power-of-two spp
// each child's block of indices is an aligned block, and stratified too.
TEST(SobolSampler, AlignedLaterBlocksAreNetsToo) {
  for (uint32_t m : {1u, 3u, 17u}) expect_2d_net(1u, 42u, 0u, AW_DIM_BSDF, 6, m << 6);
}

TEST(SobolSampler, OneDimensionalSetsAreStratified) {
  for (uint32_t dim : {uint32_t(AW_DIM_LOBE), uint32_t(AW_DIM_LIGHT_PICK), uint32_t(AW_DIM_RR)})
    for (uint32_t pixel : {0u, 99u})
      for (int k = 0; k <= 12; ++k) {
        const uint32_t n = 1u << k;
        std::vector<int> cells(n, 0);
        for (uint32_t i = 0; i < n; ++i) {
          float u = rng_1d(sampler_make(AW_SAMPLER_SOBOL, 3u, 0u, 0u, 0u), pixel, i, 2u, dim);
          ASSERT_TRUE(u >= 0.0f && u < 1.0f);
          ++cells[k == 0 ? 0u : fixed24(u) >> (24 - k)];
        }
        for (uint32_t c = 0; c < n; ++c) ASSERT_EQ(cells[c], 1) << "dim " << dim << " k " << k << " cell " << c;
      }
}

// Sample correlation of two sequences of N numbers.
double correlation(const std::vector<double>& a, const std::vector<double>& b) {
  double ma = 0, mb = 0;
  for (size_t i = 0; i < a.size(); ++i) ma += a[i], mb += b[i];
  ma /= double(a.size());
  mb /= double(b.size());
  double sab = 0, saa = 0, sbb = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}

// Without the per-set shuffle, the sets of one pixel would share the index order, and the
// first digits of, say, the lobe choice and Russian roulette would be equal or opposite for
// every sample (correlation +-1). Independent sets have a correlation of about N^-1/2; the
// bound is 5 of those (two-sided significance about 6e-7 per pair for independent numbers).
TEST(SobolSampler, SetsAndPixelsAreDecorrelated) {
  const int n = 4096;
  const double bound = 5.0 / std::sqrt(double(n));
  auto seq = [&](uint32_t pixel, uint32_t bounce, uint32_t dim, bool y) {
    std::vector<double> v(n);
    for (int i = 0; i < n; ++i) {
      float2 u = rng_2d(sampler_make(AW_SAMPLER_SOBOL, 5u, 0u, 0u, 0u), pixel, uint32_t(i), bounce, dim);
      v[size_t(i)] = y ? u.y : u.x;
    }
    return v;
  };
  auto one = [&](uint32_t pixel, uint32_t bounce, uint32_t dim) {
    std::vector<double> v(n);
    for (int i = 0; i < n; ++i) v[size_t(i)] = rng_1d(sampler_make(AW_SAMPLER_SOBOL, 5u, 0u, 0u, 0u), pixel, uint32_t(i), bounce, dim);
    return v;
  };
  EXPECT_LT(std::fabs(correlation(one(10, 0, AW_DIM_LOBE), one(10, 0, AW_DIM_RR))), bound);
  EXPECT_LT(std::fabs(correlation(one(10, 0, AW_DIM_LOBE), one(10, 1, AW_DIM_LOBE))), bound);
  EXPECT_LT(std::fabs(correlation(seq(10, 0, AW_DIM_BSDF, false), seq(10, 0, AW_DIM_LIGHT, false))), bound);
  EXPECT_LT(std::fabs(correlation(seq(10, 0, AW_DIM_BSDF, true), seq(10, 0, AW_DIM_LIGHT, true))), bound);
  EXPECT_LT(std::fabs(correlation(seq(10, 0, AW_DIM_BSDF, false), seq(11, 0, AW_DIM_BSDF, false))), bound);
  EXPECT_LT(std::fabs(correlation(seq(10, 2, AW_DIM_CAMERA, false), seq(10, 2, AW_DIM_CAMERA, true))), bound);
}

// The same pixel, set and index give the same number in the same call made twice or from
// the 1-D and 2-D interfaces (classify_hit and shade_surface must agree on the BSDF numbers).
TEST(SobolSampler, PureFunctionOfItsArguments) {
  for (uint32_t i = 0; i < 100; ++i) {
    float2 a = rng_2d(sampler_make(AW_SAMPLER_SOBOL, 9u, 0u, 0u, 0u), 77u, i, 1u, AW_DIM_BSDF);
    float2 b = rng_2d(sampler_make(AW_SAMPLER_SOBOL, 9u, 0u, 0u, 0u), 77u, i, 1u, AW_DIM_BSDF);
    EXPECT_EQ(a.x, b.x);
    EXPECT_EQ(a.y, b.y);
    EXPECT_EQ(rng_1d(sampler_make(AW_SAMPLER_SOBOL, 9u, 0u, 0u, 0u), 77u, i, 1u, AW_DIM_BSDF), a.x);
  }
  EXPECT_NE(rng_2d(sampler_make(AW_SAMPLER_SOBOL, 9u, 0u, 0u, 0u), 77u, 0u, 1u, AW_DIM_BSDF).x, rng_2d(sampler_make(AW_SAMPLER_SOBOL, 10u, 0u, 0u, 0u), 77u, 0u, 1u, AW_DIM_BSDF).x);
}

// The independent sampler is the hash archwave used before the Sobol' sampler, unchanged:
// pcg4d of (pixel, sample, bounce << 8 | dim, seed), top 24 bits.
TEST(IndependentSampler, IsThePcg4dHash) {
  for (uint32_t i = 0; i < 50; ++i) {
    uint32_t v[4] = {123u, i, (2u << 8) | uint32_t(AW_DIM_LIGHT), 8u};
    pcg4d(v);
    float2 u = rng_2d(sampler_make(AW_SAMPLER_INDEPENDENT, 8u, 0u, 0u, 0u), 123u, i, 2u, AW_DIM_LIGHT);
    EXPECT_EQ(u.x, float(v[0] >> 8) / 16777216.0f);
    EXPECT_EQ(u.y, float(v[1] >> 8) / 16777216.0f);
    EXPECT_EQ(rng_1d(sampler_make(AW_SAMPLER_INDEPENDENT, 8u, 0u, 0u, 0u), 123u, i, 2u, AW_DIM_LIGHT), u.x);
  }
}

TEST(SobolPrimitives, GeneratorsAndScrambles) {
  EXPECT_EQ(reverse_bits32(1u), 0x80000000u);
  EXPECT_EQ(reverse_bits32(0x12345678u), 0x1e6a2c48u);
  // Sobol' dimension 1's first points: 0, 1/2, 3/4, 1/4 (Joe & Kuo's table for x + 1).
  EXPECT_EQ(sobol_dim1(0u), 0u);
  EXPECT_EQ(sobol_dim1(1u), 0x80000000u);
  EXPECT_EQ(sobol_dim1(2u), 0xc0000000u);
  EXPECT_EQ(sobol_dim1(3u), 0x40000000u);
  // The superset-XOR form of dimension 1 equals the direction-number loop, and the fused
  // scrambles of rng_sobol_2d equal scrambling sobol_dim0/1 of the shuffled index.
  std::mt19937 rng(3);
  for (int k = 0; k < 20000; ++k) {
    uint32_t i = k < 1000 ? uint32_t(k) : uint32_t(rng());
    uint32_t x = 0, v = 0x80000000u;
    for (uint32_t j = i; j != 0u; j >>= 1, v ^= v >> 1)
      if (j & 1u) x ^= v;
    ASSERT_EQ(sobol_dim1(i), x) << i;
    uint32_t s[4];
    sobol_set_seeds(4u, 17u, 2u, AW_DIM_BSDF, s);
    uint32_t idx = nested_uniform_scramble(i, s[0]);
    float2 u = rng_2d(sampler_make(AW_SAMPLER_SOBOL, 4u, 0u, 0u, 0u), 17u, i, 2u, AW_DIM_BSDF);
    ASSERT_EQ(u.x, rng_to_unit(nested_uniform_scramble(sobol_dim0(idx), s[1])));
    ASSERT_EQ(u.y, rng_to_unit(nested_uniform_scramble(sobol_dim1(idx), s[2])));
  }
  // An Owen scramble is a bijection that keeps prefixes together: numbers that share their
  // top d bits still do after it.
  for (uint32_t seed : {0u, 0xdeadbeefu}) {
    uint32_t a = nested_uniform_scramble(0x12345678u, seed), b = nested_uniform_scramble(0x1234ffffu, seed);
    EXPECT_EQ(a >> 16, b >> 16);
    EXPECT_NE(nested_uniform_scramble(0x12345678u, seed), nested_uniform_scramble(0x12345679u, seed));
  }
}

// ---- zsobol: the same (0,2)-sequence, one per set for the whole image, in Z order ----------

// A zsobol sampler for a width x height image at spp samples per pixel, laid out as the host
// lays it out (sampler_for_image).
Sampler zsobol(uint32_t seed, uint32_t width, uint32_t height, uint32_t spp) {
  return sampler_for_image(AW_SAMPLER_ZSOBOL, seed, width, height, spp);
}

// Each pixel's samples are an aligned block of the set's sequence: a net, as with `sobol`,
// for even and odd log2(spp) (the odd case ends in a base-2 digit).
TEST(ZSobolSampler, EveryPixelsSamplesAreANet) {
  for (uint32_t spp : {1u, 2u, 8u, 16u, 64u}) {
    Sampler z = zsobol(3u, 40u, 24u, spp);
    for (uint32_t pixel : {0u, 1u, 41u, 959u})
      for (uint32_t dim : {uint32_t(AW_DIM_CAMERA), uint32_t(AW_DIM_BSDF)}) {
        std::vector<std::pair<uint32_t, uint32_t>> ps;
        for (uint32_t i = 0; i < spp; ++i) ps.push_back({pixel, i});
        expect_net(z, ps, 1u, dim, "pixel " + std::to_string(pixel) + " spp " + std::to_string(spp));
      }
  }
}

// What makes the error blue: the pixels of an aligned 2^j x 2^j square share one aligned
// block of the sequence, so all their samples together are a net too (white-noise or
// per-pixel-scrambled samples are not: their union is just random).
TEST(ZSobolSampler, AlignedSquaresOfPixelsTogetherAreANet) {
  const uint32_t w = 32u, h = 32u;
  for (uint32_t spp : {1u, 2u, 4u}) {
    Sampler z = zsobol(11u, w, h, spp);
    for (uint32_t j : {1u, 2u, 3u})
      for (uint32_t x0 : {0u, 8u})
        for (uint32_t y0 : {0u, 16u}) {
          std::vector<std::pair<uint32_t, uint32_t>> ps;
          for (uint32_t y = y0; y < y0 + (1u << j); ++y)
            for (uint32_t x = x0; x < x0 + (1u << j); ++x)
              for (uint32_t i = 0; i < spp; ++i) ps.push_back({y * w + x, i});
          expect_net(z, ps, 0u, AW_DIM_LIGHT, "square 2^" + std::to_string(j) + " at " + std::to_string(x0) + "," + std::to_string(y0));
        }
  }
}

// The reordering is a bijection: over a whole (power-of-two) image every index of the set's
// sequence is used exactly once, whatever the spp's parity.
TEST(ZSobolSampler, IndexOrderIsABijection) {
  for (uint32_t spp : {1u, 2u, 8u}) {
    Sampler z = zsobol(5u, 16u, 16u, spp);
    std::vector<int> seen(size_t(1) << z.bits, 0);
    for (uint32_t p = 0; p < 256u; ++p)
      for (uint32_t i = 0; i < spp; ++i) {
        uint64_t k = rng_zsobol_index(z, p, i, 0x1234u);
        ASSERT_LT(k, seen.size());
        ++seen[size_t(k)];
      }
    for (size_t k = 0; k < seen.size(); ++k) ASSERT_EQ(seen[k], 1) << "spp " << spp << " index " << k;
  }
}

// Sample indices past a pixel's block (lobe-splitting children) take the `sobol` numbers;
// the sets stay decorrelated (the bound of SetsAndPixelsAreDecorrelated); non-square images
// and a non-power-of-two spp work; and the function is pure.
TEST(ZSobolSampler, ChildrenSetsAndPurity) {
  Sampler z = zsobol(9u, 200u, 120u, 48u);  // spp 48: blocks of 64
  for (uint32_t i : {64u, 100u, 48u * 3u}) {
    float2 a = rng_2d(z, 777u, i, 0u, AW_DIM_BSDF);
    float2 b = rng_2d(sampler_make(AW_SAMPLER_SOBOL, 9u, 0u, 0u, 0u), 777u, i, 0u, AW_DIM_BSDF);
    EXPECT_EQ(a.x, b.x);
    EXPECT_EQ(a.y, b.y);
  }
  const int n = 4096;
  const double bound = 5.0 / std::sqrt(double(n));
  Sampler big = zsobol(9u, 64u, 64u, 1u);  // one sample per pixel: n pixels
  auto seq = [&](uint32_t bounce, uint32_t dim, bool y) {
    std::vector<double> v(n);
    for (int p = 0; p < n; ++p) {
      float2 u = rng_2d(big, uint32_t(p), 0u, bounce, dim);
      v[size_t(p)] = y ? u.y : u.x;
    }
    return v;
  };
  EXPECT_LT(std::fabs(correlation(seq(0, AW_DIM_LOBE, false), seq(0, AW_DIM_RR, false))), bound);
  EXPECT_LT(std::fabs(correlation(seq(0, AW_DIM_BSDF, false), seq(1, AW_DIM_BSDF, false))), bound);
  EXPECT_LT(std::fabs(correlation(seq(0, AW_DIM_BSDF, true), seq(0, AW_DIM_LIGHT, true))), bound);
  EXPECT_LT(std::fabs(correlation(seq(2, AW_DIM_CAMERA, false), seq(2, AW_DIM_CAMERA, true))), bound);
  for (uint32_t i = 0; i < 48; ++i) {
    float2 a = rng_2d(z, 12345u, i, 2u, AW_DIM_LIGHT);
    EXPECT_EQ(rng_1d(z, 12345u, i, 2u, AW_DIM_LIGHT), a.x);
    EXPECT_EQ(rng_2d(z, 12345u, i, 2u, AW_DIM_LIGHT).y, a.y);
  }
}

TEST(ZSobolPrimitives, MortonAndPermutations) {
  EXPECT_EQ(morton2(0u, 0u), 0u);
  EXPECT_EQ(morton2(1u, 0u), 1u);
  EXPECT_EQ(morton2(0u, 1u), 2u);
  EXPECT_EQ(morton2(3u, 5u), 0x27u);  // x = 011, y = 101 -> y2 x2 y1 x1 y0 x0 = 100111
  EXPECT_EQ(morton2(0xffffu, 0xffffu), 0xffffffffu);
  EXPECT_EQ(morton2(0xffffu, 0u), 0x55555555u);
  // The 24 table entries are the 24 distinct permutations of {0, 1, 2, 3}.
  std::vector<uint32_t> codes;
  for (uint32_t p = 0; p < 24u; ++p) {
    uint32_t code = 0, used = 0;
    for (uint32_t d = 0; d < 4u; ++d) {
      uint32_t e = base4_permute(p, d);
      used |= 1u << e;
      code |= e << (2u * d);
    }
    EXPECT_EQ(used, 0xfu) << p;
    codes.push_back(code);
  }
  std::sort(codes.begin(), codes.end());
  EXPECT_EQ(std::unique(codes.begin(), codes.end()), codes.end());
  EXPECT_EQ(base4_permute(0u, 2u), 2u);   // the identity first
  EXPECT_EQ(base4_permute(23u, 0u), 3u);  // 3 2 1 0 last
}


// The samplers written on lanes (common/lanes.h): built with 16 paths per work-item
// (kernels/tests/probe_lanes.cl, vector loads of 16 pixels, samples and bounces), every
// number equals, bit for bit, what the host's one-path C++ build of the same functions gives:
// Sobol' and the independent sampler, two seeds, every dimension, sample indices and bounces
// across their range (0, the top of the 32 bits, random). Runs on every device (@intel, @gpu).
TEST(SamplerLanes, SixteenPathsPerWorkItemEqualTheHostBitForBit) {
  const uint32_t n = 4096;  // a multiple of 16
  std::mt19937 rng(1204);
  std::vector<uint32_t> pixel(n), sample(n), bounce(n);
  for (uint32_t i = 0; i < n; ++i) {
    pixel[i] = i % 7 == 0 ? 0xffffffffu - i : uint32_t(rng() % 4000000u);
    sample[i] = i % 5 == 0 ? 0xffffffffu - i : i % 3 == 0 ? i : uint32_t(rng());
    bounce[i] = i % 11 == 0 ? 0xffffffu : uint32_t(rng() % 64u);
  }
  std::vector<float> in(3 * n);
  std::memcpy(in.data(), pixel.data(), 4 * n);
  std::memcpy(in.data() + n, sample.data(), 4 * n);
  std::memcpy(in.data() + 2 * n, bounce.data(), 4 * n);
  int cases = 0;
  for (uint32_t kind : {AW_SAMPLER_SOBOL, AW_SAMPLER_INDEPENDENT}) {
    for (uint32_t seed : {0u, 0x9e3779b9u}) {
      for (uint32_t dim = AW_DIM_CAMERA; dim <= AW_DIM_AO; ++dim) {
        uint32_t params[3] = {kind, seed, dim};
        std::vector<float> dev = aw::lobe_test::run_device_probe(
            "tests/probe_lanes.cl", "probe_sampler_lanes", in, 3, n, {{params, sizeof params}});
        Sampler smp = sampler_make(kind, seed, 0u, 0u, 0u);
        size_t differ = 0, first = n;
        for (uint32_t i = 0; i < n; ++i) {
          float2 u = rng_2d(smp, pixel[i], sample[i], bounce[i], dim);
          float v = rng_1d(smp, pixel[i], sample[i], bounce[i], dim);
          bool same = std::memcmp(&u.x, &dev[i], 4) == 0 && std::memcmp(&u.y, &dev[n + i], 4) == 0 &&
                      std::memcmp(&v, &dev[2 * n + i], 4) == 0;
          if (!same && differ++ == 0) first = i;
        }
        EXPECT_EQ(differ, 0u) << "kind " << kind << " seed " << seed << " dim " << dim << ": first at item " << first
                              << " (pixel " << (first < n ? pixel[first] : 0u) << ", sample "
                              << (first < n ? sample[first] : 0u) << ")";
        ++cases;
      }
    }
  }
  EXPECT_EQ(cases, 28);
}

// The warps, frames and MIS weight of common/sampling.h on lanes: 16 paths per work-item
// (kernels/tests/probe_lanes.cl, probe_warps_lanes) equal the host's one-path C++ bit for bit,
// for random points of the square (and its centre, edges, corners and diagonals, where the
// disk map's wedges meet or divide 0 by 0), normals in every direction (the frame's z = 0
// and -1 branches included), densities from 0 to infinity and NaN, and cones up to the
// hemisphere. Runs on every device (@intel, @gpu).
TEST(SamplingLanes, WarpsFramesAndMisEqualTheHostBitForBit) {
  const uint32_t n = 4096;
  std::mt19937 rng(41204);
  std::uniform_real_distribution<float> uni(0.0f, 1.0f);
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const float special_u[] = {0.0f, 0.5f, 1.0f, 0.25f, 0.75f, 0.99999994f};
  const float special_pdf[] = {0.0f, 1e-30f, 1.0f, 1e30f, inf, nan};
  std::vector<float> in(8 * n);
  for (uint32_t i = 0; i < n; ++i) {
    float ux = i < 36 ? special_u[i % 6] : uni(rng), uy = i < 36 ? special_u[i / 6] : uni(rng);
    if (i >= 36 && i < 64) uy = ux;  // the diagonal |a| = |b|
    float nx = 2.0f * uni(rng) - 1.0f, ny = 2.0f * uni(rng) - 1.0f, nz = 2.0f * uni(rng) - 1.0f;
    if (i % 9 == 0) nz = 0.0f;
    if (i % 13 == 0) nx = ny = 0.0f, nz = -1.0f;
    float len = std::sqrt(nx * nx + ny * ny + nz * nz);
    if (!(len > 0.0f)) nx = 1.0f, len = 1.0f;
    float vals[8] = {ux, uy, nx / len, ny / len, nz / len,
                     i % 5 == 0 ? special_pdf[i % 6] : 10.0f * uni(rng), i % 7 == 0 ? special_pdf[(i / 7) % 6] : uni(rng),
                     i % 3 == 0 ? 0.0f : uni(rng)};
    for (uint32_t k = 0; k < 8; ++k) in[k * n + i] = vals[k];
  }
  const uint32_t outs = 25;
  std::vector<float> dev = aw::lobe_test::run_device_probe("tests/probe_lanes.cl", "probe_warps_lanes", in, outs, n);
  const char* names[outs] = {"disk.x", "disk.y", "cos.x", "cos.y", "cos.z", "pdf_cos", "cone.x", "cone.y", "cone.z",
                             "sin",    "cos",    "t.x",   "t.y",   "t.z",   "b.x",     "b.y",    "b.z",    "world.x",
                             "world.y", "world.z", "local.x", "local.y", "local.z", "mis(a,b)", "mis(b,a)"};
  size_t differ = 0;
  for (uint32_t i = 0; i < n; ++i) {
    float2 u = make_float2(in[i], in[n + i]);
    float3 nn = make_float3(in[2 * n + i], in[3 * n + i], in[4 * n + i]);
    float r[outs];
    float2 d = sample_concentric_disk(u);
    float3 w = sample_cosine_hemisphere(u);
    float3 cone = sample_uniform_cone(u, in[7 * n + i]);
    float3 t, b;
    make_frame(nn, &t, &b);
    float3 ww = frame_to_world(w, t, b, nn), wl = frame_to_local(ww, t, b, nn);
    float vals[outs] = {d.x, d.y, w.x, w.y, w.z, pdf_cosine_hemisphere(w.z), cone.x, cone.y, cone.z, 0.0f, 0.0f,
                        t.x, t.y, t.z, b.x, b.y, b.z, ww.x, ww.y, ww.z, wl.x, wl.y, wl.z,
                        mis_power(in[5 * n + i], in[6 * n + i]), mis_power(in[6 * n + i], in[5 * n + i])};
    std::memcpy(r, vals, sizeof r);
    sincos_turn(u.x, &r[9], &r[10]);
    for (uint32_t k = 0; k < outs; ++k) {
      if (std::memcmp(&r[k], &dev[k * n + i], 4) != 0 && differ++ < 10)
        ADD_FAILURE() << names[k] << " at item " << i << " (u " << u.x << ", " << u.y << "): host " << r[k]
                      << ", 16 lanes " << dev[k * n + i];
    }
  }
  EXPECT_EQ(differ, 0u);
}

// The robust ray origins of common/ray.h on lanes: offset_ray_origin and its one-float step,
// 16 paths per work-item, equal the host's one-path C++ bit for bit: points near zero, at
// every scale to 1e30, normals with zero components (no step), errors from 0 to large, and
// aw_float_step's cases (x = 0 of both signs, s = 0, both signs of both, the largest float,
// infinities, NaN). Runs on every device (@intel, @gpu).
TEST(RayLanes, OffsetOriginsEqualTheHostBitForBit) {
  const uint32_t n = 4096;
  std::mt19937 rng(51204);
  std::uniform_real_distribution<float> uni(-1.0f, 1.0f);
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const float special[] = {0.0f, -0.0f, 1.0f, -1.0f, 3.4028235e38f, -3.4028235e38f, 1e-45f, inf, -inf, nan};
  std::vector<float> in(9 * n);
  for (uint32_t i = 0; i < n; ++i) {
    float scale = std::pow(10.0f, float(int(i % 31) - 15) * 2.0f);
    float nx = uni(rng), ny = uni(rng), nz = uni(rng);
    if (i % 4 == 0) nx = 0.0f;
    if (i % 6 == 0) ny = -0.0f;
    float len = std::sqrt(nx * nx + ny * ny + nz * nz);
    if (!(len > 0.0f)) nz = 1.0f, len = 1.0f;
    float vals[9] = {i % 10 == 0 ? 0.0f : uni(rng) * scale, uni(rng) * scale, uni(rng) * scale,
                     nx / len, ny / len, nz / len, i % 8 == 0 ? 0.0f : std::fabs(uni(rng)) * scale * 1e-6f,
                     i < 100 ? special[i % 10] : uni(rng) * scale, i < 100 ? special[i / 10] : uni(rng)};
    for (uint32_t k = 0; k < 9; ++k) in[k * n + i] = vals[k];
  }
  std::vector<float> dev = aw::lobe_test::run_device_probe("tests/probe_lanes.cl", "probe_origins_lanes", in, 4, n);
  size_t differ = 0;
  for (uint32_t i = 0; i < n; ++i) {
    float3 o = offset_ray_origin(make_float3(in[i], in[n + i], in[2 * n + i]),
                                 make_float3(in[3 * n + i], in[4 * n + i], in[5 * n + i]), in[6 * n + i]);
    float r[4] = {o.x, o.y, o.z, aw_float_step(in[7 * n + i], in[8 * n + i])};
    for (uint32_t k = 0; k < 4; ++k)
      if (std::memcmp(&r[k], &dev[k * n + i], 4) != 0 && differ++ < 10)
        ADD_FAILURE() << "output " << k << " at item " << i << ": host " << r[k] << ", 16 lanes " << dev[k * n + i];
  }
  EXPECT_EQ(differ, 0u);
}

}  // namespace
