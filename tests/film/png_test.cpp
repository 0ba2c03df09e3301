#include <gtest/gtest.h>
#include <png.h>

#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <vector>

#include "host/film/image_io.h"
#include "tests/film/film_test_util.h"

namespace aw {
namespace {

using film_test::ScratchDirTest;
using PngTest = ScratchDirTest;

struct RawPng {
  bool ok = false;
  png_uint_32 width = 0, height = 0;
  int bit_depth = 0, color_type = 0;
  bool has_srgb_chunk = false;
  std::vector<unsigned char> rgb;  // rows top first
};

// Plain-C reader with the low-level API and no transforms, so the test sees the exact bytes
// stored in the file. Only trivially destructible locals live across setjmp, since libpng
// reports errors by longjmp.
bool read_png_c(const char* path, png_uint_32* w, png_uint_32* h, int* depth, int* ctype, int* srgb,
                unsigned char** pixels) {
  FILE* f = std::fopen(path, "rb");
  if (!f) return false;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    std::fclose(f);
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    std::fclose(f);
    return false;
  }
  png_init_io(png, f);
  png_read_png(png, info, PNG_TRANSFORM_IDENTITY, nullptr);
  *w = png_get_image_width(png, info);
  *h = png_get_image_height(png, info);
  *depth = png_get_bit_depth(png, info);
  *ctype = png_get_color_type(png, info);
  *srgb = png_get_valid(png, info, PNG_INFO_sRGB) != 0;
  const size_t rowbytes = png_get_rowbytes(png, info);
  png_bytepp rows = png_get_rows(png, info);
  *pixels = static_cast<unsigned char*>(std::malloc(rowbytes * *h));
  for (png_uint_32 y = 0; y < *h; ++y)
    for (size_t x = 0; x < rowbytes; ++x) (*pixels)[y * rowbytes + x] = rows[y][x];
  png_destroy_read_struct(&png, &info, nullptr);
  std::fclose(f);
  return true;
}

RawPng read_png(const std::string& path) {
  RawPng r;
  unsigned char* pixels = nullptr;
  int srgb = 0;
  r.ok = read_png_c(path.c_str(), &r.width, &r.height, &r.bit_depth, &r.color_type, &srgb, &pixels);
  if (r.ok) {
    r.has_srgb_chunk = srgb != 0;
    r.rgb.assign(pixels, pixels + size_t(r.width) * r.height * 3);
  }
  std::free(pixels);
  return r;
}

Image row_image(const std::vector<float>& values) {
  Image img;
  img.width = int(values.size() / 3);
  img.height = 1;
  img.rgb = values;
  return img;
}

// Writes a one-row image of grey pixels and returns the stored R bytes (checking G == B == R).
std::vector<int> grey_bytes(const std::string& p, const std::vector<float>& greys, float exposure) {
  std::vector<float> rgb;
  for (float g : greys) rgb.insert(rgb.end(), {g, g, g});
  write_png_preview(p, row_image(rgb), exposure);
  const RawPng png = read_png(p);
  EXPECT_TRUE(png.ok);
  EXPECT_EQ(png.width, greys.size());
  EXPECT_EQ(png.height, 1u);
  std::vector<int> out;
  for (size_t i = 0; i < greys.size() && 3 * i + 2 < png.rgb.size(); ++i) {
    EXPECT_EQ(png.rgb[3 * i], png.rgb[3 * i + 1]);
    EXPECT_EQ(png.rgb[3 * i], png.rgb[3 * i + 2]);
    out.push_back(png.rgb[3 * i]);
  }
  return out;
}

TEST_F(PngTest, IsEightBitRgbTaggedSrgb) {
  const std::string p = path("fmt.png");
  write_png_preview(p, row_image({0.1f, 0.2f, 0.3f}), 1.0f);
  const RawPng png = read_png(p);
  ASSERT_TRUE(png.ok);
  EXPECT_EQ(png.bit_depth, 8);
  EXPECT_EQ(png.color_type, PNG_COLOR_TYPE_RGB);
  EXPECT_TRUE(png.has_srgb_chunk);
  EXPECT_FALSE(exists(p + ".tmp"));
}

TEST_F(PngTest, MatchesSrgbCurveAtKnownPoints) {
  // 0.0031308: end of the linear segment, 12.92 * 0.0031308 * 255 = 10.31.
  // 0.18: mid grey, 1.055 * 0.18^(1/2.4) - 0.055 = 0.4613 -> 117.6.
  // 0.5: 0.7354 -> 187.5. 0.001: 12.92 * 0.001 * 255 = 3.29.
  const std::vector<int> got =
      grey_bytes(path("curve.png"), {0.0f, 1.0f, 0.0031308f, 0.0031309f, 0.5f, 0.18f, 0.001f}, 1.0f);
  EXPECT_EQ(got, (std::vector<int>{0, 255, 10, 10, 188, 118, 3}));
}

TEST_F(PngTest, ClampsOutOfRange) {
  const std::vector<int> got = grey_bytes(path("clamp.png"), {-1.0f, 2.0f, 1e30f, -0.0f}, 1.0f);
  EXPECT_EQ(got, (std::vector<int>{0, 255, 255, 0}));
}

TEST_F(PngTest, ExposureScaleMultipliesBeforeTheCurve) {
  EXPECT_EQ(grey_bytes(path("e2.png"), {0.25f, 0.5f, 0.09f}, 2.0f), (std::vector<int>{188, 255, 118}));
  EXPECT_EQ(grey_bytes(path("e0.png"), {0.5f, 1.0f}, 0.0f), (std::vector<int>{0, 0}));
  // A finite value the scale pushes past float range is still just "very bright".
  EXPECT_EQ(grey_bytes(path("big.png"), {3e38f}, 100.0f), (std::vector<int>{255}));
}

TEST_F(PngTest, NonFinitePixelsBecomeBlack) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const std::string p = path("nan.png");
  write_png_preview(p,
                    row_image({nan, 0.5f, 0.5f,    //
                               0.5f, inf, 0.5f,    //
                               0.5f, 0.5f, -inf,   //
                               0.5f, 0.5f, 0.5f}),  // a normal neighbour stays intact
                    1.0f);
  const RawPng png = read_png(p);
  ASSERT_TRUE(png.ok);
  EXPECT_EQ(png.rgb, (std::vector<unsigned char>{0, 0, 0, 0, 0, 0, 0, 0, 0, 188, 188, 188}));
}

TEST_F(PngTest, NonSquareImageKeepsLayout) {
  // 3 wide, 2 high; each pixel gets a distinct channel pattern.
  Image img;
  img.width = 3;
  img.height = 2;
  img.rgb = {1, 0, 0,  0, 1, 0,  0, 0, 1,    // top row
             1, 1, 0,  0, 1, 1,  0.5f, 0, 1};  // bottom row
  const std::string p = path("layout.png");
  write_png_preview(p, img, 1.0f);
  const RawPng png = read_png(p);
  ASSERT_TRUE(png.ok);
  EXPECT_EQ(png.width, 3u);
  EXPECT_EQ(png.height, 2u);
  EXPECT_EQ(png.rgb, (std::vector<unsigned char>{255, 0, 0, 0, 255, 0, 0, 0, 255,  //
                                                 255, 255, 0, 0, 255, 255, 188, 0, 255}));
}

TEST_F(PngTest, MissingDirectoryThrowsNamingPathAndLeavesNothing) {
  const std::string p = path("absent/preview.png");
  try {
    write_png_preview(p, row_image({0.5f, 0.5f, 0.5f}), 1.0f);
    FAIL() << "expected OutputError";
  } catch (const OutputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(p), std::string::npos) << msg;
    EXPECT_NE(msg.find("does not exist"), std::string::npos) << msg;
  }
  EXPECT_FALSE(exists(p));
  EXPECT_FALSE(exists(p + ".tmp"));
}

TEST_F(PngTest, InvalidArgumentsThrowOutputError) {
  const Image img = row_image({0.5f, 0.5f, 0.5f});
  EXPECT_THROW(write_png_preview(path("a.png"), img, std::numeric_limits<float>::quiet_NaN()), OutputError);
  EXPECT_THROW(write_png_preview(path("b.png"), img, -1.0f), OutputError);
  EXPECT_THROW(write_png_preview(path("c.png"), Image{}, 1.0f), OutputError);
  EXPECT_FALSE(exists(path("a.png")));
  EXPECT_FALSE(exists(path("b.png")));
  EXPECT_FALSE(exists(path("c.png")));
}

TEST(PngPathFor, ReplacesTrailingExrElseAppends) {
  EXPECT_EQ(png_path_for("out.exr"), "out.png");
  EXPECT_EQ(png_path_for("renders/cornell.exr"), "renders/cornell.png");
  EXPECT_EQ(png_path_for("SHOT.EXR"), "SHOT.png");
  EXPECT_EQ(png_path_for("out"), "out.png");
  EXPECT_EQ(png_path_for("out.exr.bak"), "out.exr.bak.png");
  EXPECT_EQ(png_path_for("my.exrfile"), "my.exrfile.png");
  EXPECT_EQ(png_path_for(""), ".png");
}

}  // namespace
}  // namespace aw
