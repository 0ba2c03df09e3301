#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "host/film/image_io.h"

namespace aw {
namespace {

Image constant_image(int w, int h, float v) {
  Image img;
  img.width = w;
  img.height = h;
  img.rgb.assign(size_t(w) * h * 3, v);
  return img;
}

TEST(CompareImages, IdenticalImages) {
  const Image a = constant_image(4, 3, 0.25f);
  const ImageDiff d = compare_images(a, a, 0.0, 0.0);
  EXPECT_DOUBLE_EQ(d.mean_a, 0.25);
  EXPECT_DOUBLE_EQ(d.mean_b, 0.25);
  EXPECT_EQ(d.rel_mean_diff, 0.0);
  EXPECT_EQ(d.frac_pixels_within, 1.0);
  EXPECT_EQ(d.max_abs_diff, 0.0);
}

TEST(CompareImages, OneChannelOutsideToleranceFailsItsPixel) {
  const Image a = constant_image(2, 2, 1.0f);
  Image b = a;
  b.rgb[4] = 1.1f;  // pixel 1, green: rel diff 0.1/1.1 = 0.0909
  b.rgb[9] = 1.02f; // pixel 3, red: rel diff 0.0196, inside 5%
  const ImageDiff d = compare_images(a, b, 0.05, 0.0);
  EXPECT_DOUBLE_EQ(d.frac_pixels_within, 0.75);
  EXPECT_NEAR(d.max_abs_diff, 0.1, 1e-6);
  EXPECT_DOUBLE_EQ(d.mean_a, 1.0);
  EXPECT_NEAR(d.mean_b, (12.0 + 0.1 + 0.02) / 12.0, 1e-7);
  EXPECT_NEAR(d.rel_mean_diff, (0.12 / 12.0) / ((12.0 + 0.12) / 12.0), 1e-7);

  // A looser tolerance lets the green channel through too.
  EXPECT_DOUBLE_EQ(compare_images(a, b, 0.1, 0.0).frac_pixels_within, 1.0);
}

TEST(CompareImages, RelativeDifferenceIsSymmetric) {
  Image a = constant_image(1, 1, 1.0f);
  Image b = constant_image(1, 1, 2.0f);
  // |1-2| / max(1,2) = 0.5 either way round.
  EXPECT_DOUBLE_EQ(compare_images(a, b, 0.5, 0.0).frac_pixels_within, 1.0);
  EXPECT_DOUBLE_EQ(compare_images(b, a, 0.5, 0.0).frac_pixels_within, 1.0);
  EXPECT_DOUBLE_EQ(compare_images(b, a, 0.49, 0.0).frac_pixels_within, 0.0);
}

TEST(CompareImages, AbsFloorForgivesNoiseNearBlack) {
  const Image a = constant_image(1, 1, 0.0f);
  const Image b = constant_image(1, 1, 1e-4f);
  // Without a floor 0 vs 1e-4 is a 100% difference; with floor 0.01 it is 1%.
  EXPECT_DOUBLE_EQ(compare_images(a, b, 0.05, 0.0).frac_pixels_within, 0.0);
  EXPECT_DOUBLE_EQ(compare_images(a, b, 0.05, 0.01).frac_pixels_within, 1.0);
}

TEST(CompareImages, BlackImagesAreEqual) {
  const Image a = constant_image(3, 1, 0.0f);
  const ImageDiff d = compare_images(a, a, 0.0, 0.0);
  EXPECT_EQ(d.rel_mean_diff, 0.0);
  EXPECT_EQ(d.frac_pixels_within, 1.0);
}

TEST(CompareImages, NanNeverCountsAsWithin) {
  const Image a = constant_image(2, 1, 0.5f);
  Image b = a;
  b.rgb[0] = std::numeric_limits<float>::quiet_NaN();
  const ImageDiff d = compare_images(a, b, 1.0, 1.0);
  EXPECT_DOUBLE_EQ(d.frac_pixels_within, 0.5);
  EXPECT_TRUE(std::isnan(d.max_abs_diff));
  EXPECT_TRUE(std::isnan(d.mean_b));
  EXPECT_FALSE(d.rel_mean_diff < 1.0);  // a tolerance check on it must fail
}

TEST(CompareImages, EqualInfinitiesMatch) {
  Image a = constant_image(1, 1, 1.0f);
  a.rgb[1] = std::numeric_limits<float>::infinity();
  EXPECT_DOUBLE_EQ(compare_images(a, a, 0.0, 0.0).frac_pixels_within, 1.0);
}

TEST(CompareImages, SizeMismatchThrows) {
  EXPECT_THROW(compare_images(constant_image(2, 3, 0), constant_image(3, 2, 0), 0.1, 0.0),
               std::invalid_argument);
  Image broken = constant_image(2, 2, 0);
  broken.rgb.pop_back();
  EXPECT_THROW(compare_images(broken, constant_image(2, 2, 0), 0.1, 0.0), std::invalid_argument);
  EXPECT_THROW(compare_images(constant_image(1, 1, 0), constant_image(1, 1, 0), -1.0, 0.0),
               std::invalid_argument);
}

}  // namespace
}  // namespace aw
