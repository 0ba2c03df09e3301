#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>

#include "host/film/image_io.h"
#include "tests/film/film_test_util.h"

namespace aw {
namespace {

using film_test::ScratchDirTest;
using ExrTest = ScratchDirTest;

// Values chosen to catch any lossy path: denormals, -0, huge, NaN and Inf must all survive.
Image make_test_image(int w, int h) {
  Image img;
  img.width = w;
  img.height = h;
  img.rgb.resize(size_t(w) * h * 3);
  for (size_t i = 0; i < img.rgb.size(); ++i)
    img.rgb[i] = float(std::sin(double(i) * 0.7311) * std::pow(10.0, double(i % 9) - 4.0));
  img.rgb[0] = 0.0f;
  img.rgb[1] = -0.0f;
  img.rgb[2] = std::numeric_limits<float>::denorm_min();
  img.rgb[3] = std::numeric_limits<float>::max();
  img.rgb[4] = std::numeric_limits<float>::infinity();
  img.rgb[5] = std::numeric_limits<float>::quiet_NaN();
  return img;
}

void expect_bit_exact(const Image& expected, const Image& actual) {
  ASSERT_EQ(expected.width, actual.width);
  ASSERT_EQ(expected.height, actual.height);
  ASSERT_EQ(expected.rgb.size(), actual.rgb.size());
  EXPECT_EQ(0, std::memcmp(expected.rgb.data(), actual.rgb.data(), expected.rgb.size() * sizeof(float)));
  EXPECT_EQ(expected.int_attrs, actual.int_attrs);
  EXPECT_EQ(expected.string_attrs, actual.string_attrs);
}

TEST_F(ExrTest, RoundTripIsBitExactIncludingAttributes) {
  Image img = make_test_image(7, 3);
  img.int_attrs = {{"spp", 64}, {"seed", -5}, {"archwave:max_depth", std::numeric_limits<int>::max()}};
  img.string_attrs = {{"archwave:device", "pocl cpu (x86_64)"}, {"archwave:scene", "scenes/cornell.json"},
                      {"archwave:empty", ""}};
  const std::string p = path("wide.exr");
  write_exr(p, img);
  EXPECT_TRUE(exists(p));
  EXPECT_FALSE(exists(p + ".tmp"));
  expect_bit_exact(img, read_exr(p));
}

TEST_F(ExrTest, TallImageRoundTripKeepsRowOrder) {
  Image img = make_test_image(2, 9);
  const std::string p = path("tall.exr");
  write_exr(p, img);
  const Image back = read_exr(p);
  expect_bit_exact(img, back);
  // Top row first: pixel (x=1, y=8) is the last one in memory.
  EXPECT_EQ(img.rgb[(8 * 2 + 1) * 3 + 2], back.rgb.back());
}

TEST_F(ExrTest, OverwritesExistingFile) {
  const std::string p = path("out.exr");
  Image first = make_test_image(4, 4);
  write_exr(p, first);
  Image second = make_test_image(3, 5);
  second.int_attrs["spp"] = 2;
  write_exr(p, second);
  expect_bit_exact(second, read_exr(p));
}

TEST_F(ExrTest, MissingDirectoryThrowsNamingPathAndLeavesNothing) {
  const std::string p = path("no/such/dir/out.exr");
  try {
    write_exr(p, make_test_image(2, 2));
    FAIL() << "expected OutputError";
  } catch (const OutputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(p), std::string::npos) << msg;
    EXPECT_NE(msg.find("does not exist"), std::string::npos) << msg;
  }
  EXPECT_FALSE(exists(p));
  EXPECT_FALSE(exists(p + ".tmp"));
  EXPECT_FALSE(exists(path("no")));
}

TEST_F(ExrTest, ParentIsAFileThrows) {
  write_text(path("plain"), "x");
  const std::string p = path("plain/out.exr");
  try {
    write_exr(p, make_test_image(2, 2));
    FAIL() << "expected OutputError";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
  }
}

TEST_F(ExrTest, PermissionDeniedThrowsNamingReason) {
  if (::geteuid() == 0) GTEST_SKIP() << "root ignores directory permissions";
  std::filesystem::create_directory(path("ro"));
  std::filesystem::permissions(path("ro"), std::filesystem::perms::owner_read | std::filesystem::perms::owner_exec);
  const std::string p = path("ro/out.exr");
  try {
    write_exr(p, make_test_image(2, 2));
    ADD_FAILURE() << "expected OutputError";
  } catch (const OutputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(p), std::string::npos) << msg;
    EXPECT_NE(msg.find("ermission denied"), std::string::npos) << msg;
  }
  std::filesystem::permissions(path("ro"), std::filesystem::perms::owner_all);
  EXPECT_FALSE(exists(p));
}

TEST_F(ExrTest, FailedWriteKeepsPreviousFileAndRemovesTmp) {
  const std::string p = path("keep.exr");
  Image good = make_test_image(3, 2);
  good.string_attrs["archwave:device"] = "first";
  write_exr(p, good);

  // "compression" is a standard attribute of another type: OpenEXR refuses it.
  Image bad = make_test_image(5, 5);
  bad.int_attrs["compression"] = 1;
  EXPECT_THROW(write_exr(p, bad), OutputError);
  EXPECT_FALSE(exists(p + ".tmp"));
  expect_bit_exact(good, read_exr(p));
}

TEST_F(ExrTest, SameNameAsIntAndStringIsRejected) {
  Image img = make_test_image(2, 2);
  img.int_attrs["spp"] = 1;
  img.string_attrs["spp"] = "1";
  EXPECT_THROW(write_exr(path("dup.exr"), img), OutputError);
  EXPECT_FALSE(exists(path("dup.exr")));
}

TEST_F(ExrTest, InvalidImagesThrow) {
  Image empty;
  EXPECT_THROW(write_exr(path("empty.exr"), empty), OutputError);
  Image short_data = make_test_image(3, 3);
  short_data.rgb.pop_back();
  EXPECT_THROW(write_exr(path("short.exr"), short_data), OutputError);
  EXPECT_FALSE(exists(path("empty.exr")));
  EXPECT_FALSE(exists(path("short.exr")));
}

TEST_F(ExrTest, ReadErrorsNameThePath) {
  const std::string missing = path("missing.exr");
  try {
    read_exr(missing);
    FAIL() << "expected OutputError";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }

  const std::string garbage = path("garbage.exr");
  write_text(garbage, "this is not an OpenEXR file at all, just some text padding it out");
  try {
    read_exr(garbage);
    FAIL() << "expected OutputError";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find(garbage), std::string::npos) << e.what();
  }
}

TEST_F(ExrTest, TruncatedFileIsAnError) {
  const std::string p = path("trunc.exr");
  write_exr(p, make_test_image(64, 64));
  const auto size = std::filesystem::file_size(p);
  std::filesystem::resize_file(p, size / 2);
  EXPECT_THROW(read_exr(p), OutputError);
}

}  // namespace
}  // namespace aw
