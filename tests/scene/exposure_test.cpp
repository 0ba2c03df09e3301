// Camera exposure (docs/scene-format.md, camera.exposure): the photographic constant and its
// stops, white balance and vignetting, applied by aw::apply_exposure to a rendered image.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "host/scene/scene.h"

namespace {

aw::CameraDesc photographic(float iso, float shutter, float f_number) {
  aw::CameraDesc c;
  c.exposure.mode = aw::ExposureDesc::Mode::Photographic;
  c.exposure.iso = iso;
  c.exposure.shutter = shutter;
  c.exposure.f_number = f_number;
  return c;
}

TEST(Exposure, DoublingIsoOrTimeOrOpeningByRootTwoIsOneStop) {
  const float k = aw::exposure_scale(photographic(100, 100, 16).exposure);
  EXPECT_FLOAT_EQ(k, 1.0f / 25600.0f);  // sunny 16: (1/100) * 100 / (16^2 * 100)
  EXPECT_FLOAT_EQ(aw::exposure_scale(photographic(200, 100, 16).exposure), 2.0f * k);
  EXPECT_FLOAT_EQ(aw::exposure_scale(photographic(100, 50, 16).exposure), 2.0f * k);
  EXPECT_NEAR(aw::exposure_scale(photographic(100, 100, 16.0f / std::sqrt(2.0f)).exposure), 2.0f * k, 1e-6f * k);
  aw::ExposureDesc s;
  s.stops = 1;
  EXPECT_FLOAT_EQ(aw::exposure_scale(s), 2.0f);
}

TEST(Exposure, WhitePointTurnsItsColourGreyOfTheSameLuminance) {
  aw::CameraDesc c = photographic(100, 100, 16);
  c.exposure.whitepoint = glm::vec3(1.0f, 0.8f, 0.5f);
  std::vector<float> img = {1.0f, 0.8f, 0.5f};
  aw::apply_exposure(c, 1, 1, img.data());
  const float k = 1.0f / 25600.0f;
  const float lum = 0.2126f * 1.0f + 0.7152f * 0.8f + 0.0722f * 0.5f;
  for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(img[ch], lum * k, 1e-6f * lum * k) << ch;
  // The same white point in stops mode is ignored.
  c.exposure.mode = aw::ExposureDesc::Mode::Stops;
  std::vector<float> img2 = {1.0f, 0.8f, 0.5f};
  aw::apply_exposure(c, 1, 1, img2.data());
  EXPECT_FLOAT_EQ(img2[2], 0.5f);
}

TEST(Exposure, VignettingFollowsTheCosFourthLaw) {
  aw::CameraDesc c = photographic(100, 100, 16);
  c.fov = 90.0f;  // tan(45 deg) = 1: the pixel centre at image x in [-1, 1] has tan(theta) = x
  const int w = 3, h = 1;
  const float k = 1.0f / 25600.0f;
  for (float vig : {0.0f, 1.0f, 2.0f}) {
    c.exposure.vignetting = vig;
    std::vector<float> img(size_t(w) * h * 3, 1.0f);
    aw::apply_exposure(c, w, h, img.data());
    EXPECT_NEAR(img[3 * 1] / k, 1.0f, 1e-6f) << "the centre pixel is on the axis";
    // Left pixel centre: u = (2 * 0.5 / 3 - 1) * tan(45) * aspect 3 = -2, v = 0: cos^2 = 1/5.
    const double expected = std::pow(1.0 / 25.0, double(vig));
    EXPECT_NEAR(img[0] / k, expected, 1e-6 + 1e-5 * expected) << "vignetting " << vig;
  }
}

}  // namespace
