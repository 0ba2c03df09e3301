// Textures (issue 14): lookups on the host against the device, wrap modes, sRGB decoding, the
// box-filtered checker, mip selection; cutout holes for every kind of ray, bump mapping
// against the analytic tilt, disable_bump per lobe; the wavefront against the scalar path on a
// textured scene; the loader's errors.
#include <gtest/gtest.h>
#include <unistd.h>

#include <zlib.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "host/film/image_io.h"
#include "host/render/render.h"
#include "host/render/scene_pack.h"
#include "host/render/texture_pack.h"
#include "tests/lobes/lobe_harness.h"
#include "tests/render/render_test_util.h"
#include "tests/scene/scene_test_util.h"

#include "kernels/tests/probe_texture.cl"

namespace {

using aw::TextureDesc;

// An image texture made in memory: value(x, y, c) for column x, row y (row 0 at the top).
template <class F>
TextureDesc image(int w, int h, int channels, bool eight_bit, TextureDesc::ColorSpace cs, TextureDesc::Wrap wrap, F value) {
  TextureDesc t;
  t.type = TextureDesc::Type::Image;
  t.width = w;
  t.height = h;
  t.channels = channels;
  t.eight_bit = eight_bit;
  t.colorspace = cs;
  t.wrap = wrap;
  t.texels.assign(size_t(w) * size_t(h) * 4, 1.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 4; ++c) {
        float v = value(x, y, c);
        // What the decoder hands over: grey repeated, 8-bit values on the 1/255 grid.
        if (channels <= 2 && c < 3) v = value(x, y, 0);
        if ((channels == 1 || channels == 3) && c == 3) v = 1.0f;
        if (eight_bit) v = std::round(v * 255.0f) / 255.0f;
        t.texels[(size_t(y) * size_t(w) + size_t(x)) * 4 + size_t(c)] = v;
      }
  return t;
}

TextureDesc procedural(TextureDesc::Type type, glm::vec2 scale, float rotation = 0.0f) {
  TextureDesc t;
  t.type = type;
  t.scale = scale;
  t.rotation = rotation;
  t.color1 = glm::vec3(1.0f, 0.5f, 0.25f);
  t.color2 = glm::vec3(0.0f, 0.25f, 1.0f);
  t.octaves = 5;
  return t;
}

aw::PackedTextures pack(const std::vector<TextureDesc>& textures) {
  aw::Scene s;
  s.path = "test";
  s.textures = textures;
  return aw::pack_textures(s);
}

float4 eval(const aw::PackedTextures& p, size_t i, float u, float v, float f) {
  return texture_eval(&p.textures[i], p.texels.data(), u, v, f);
}

// The same lookups through the OpenCL build of texture/texture.h (kernels/tests/
// probe_texture.cl) and the host build: every format, channel count, wrap mode and the two
// procedurals, at points and footprints from 0 to larger than the texture. Tolerance: the
// suite's 1e-5 relative (host and device share every operation but log2, whose last bit
// may differ and moves a trilinear weight by ~1e-7).
TEST(Texture, HostMatchesDevice) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> uni(0.0f, 1.0f);
  std::vector<float> noise(64 * 64 * 4);
  for (float& x : noise) x = uni(rng);
  auto from_noise = [&](int w) { return [&, w](int x, int y, int c) { return noise[size_t((y * w + x) % 4096) * 4 + size_t(c)]; }; };
  std::vector<TextureDesc> t = {
      image(37, 23, 4, false, TextureDesc::ColorSpace::Linear, TextureDesc::Wrap::Repeat, from_noise(37)),
      image(16, 16, 1, true, TextureDesc::ColorSpace::Linear, TextureDesc::Wrap::Clamp, from_noise(16)),
      image(64, 32, 3, true, TextureDesc::ColorSpace::Srgb, TextureDesc::Wrap::Mirror, from_noise(64)),
      image(8, 8, 2, true, TextureDesc::ColorSpace::Linear, TextureDesc::Wrap::Black, from_noise(8)),
      procedural(TextureDesc::Type::Checker, glm::vec2(8.0f, 5.0f), 30.0f),
      procedural(TextureDesc::Type::Noise, glm::vec2(6.0f, 6.0f)),
  };
  t[0].scale = glm::vec2(2.0f, 3.0f);
  t[0].offset = glm::vec2(0.25f, -0.5f);
  aw::PackedTextures p = pack(t);
  EXPECT_EQ(p.textures[1].format, AW_TEXFMT_U8);
  EXPECT_EQ(p.textures[2].format, AW_TEXFMT_F16);
  EXPECT_EQ(p.textures[0].format, AW_TEXFMT_F32);
  std::vector<float> in;
  const float footprints[] = {0.0f, 1e-3f, 0.01f, 0.05f, 0.3f, 2.0f};
  for (int i = 0; i < 6000; ++i) {
    in.push_back(float(i % int(t.size())));
    in.push_back(-3.0f + 6.0f * uni(rng));
    in.push_back(-3.0f + 6.0f * uni(rng));
    in.push_back(footprints[i % 6]);
  }
  const size_t n = in.size() / AW_PROBE_TEXTURE_IN;
  std::vector<float> host(n * AW_PROBE_TEXTURE_OUT);
  for (size_t i = 0; i < n; ++i)
    probe_texture_item(p.textures.data(), p.texels.data(), &in[i * AW_PROBE_TEXTURE_IN], &host[i * AW_PROBE_TEXTURE_OUT]);
  std::vector<float> device = aw::lobe_test::run_device_probe(
      "tests/probe_texture.cl", "probe_texture", in, AW_PROBE_TEXTURE_OUT, n,
      {{p.textures.data(), p.textures.size() * sizeof(TextureGpu)}, {p.texels.data(), p.texels.size()}});
  EXPECT_TRUE(aw::lobe_test::host_matches_device(host, device, aw::lobe_test::kHostDeviceRelTol,
                                                 aw::lobe_test::kHostDeviceAbsFloor, "texture_eval"));
  for (float x : host) ASSERT_TRUE(std::isfinite(x));
}

// A row of four texels 0.1 .. 0.4, read at texel centres outside [0, 1] under each wrap mode.
TEST(Texture, WrapModes) {
  auto row = [](TextureDesc::Wrap w) {
    return image(4, 1, 1, false, TextureDesc::ColorSpace::Linear, w, [](int x, int, int) { return 0.1f * float(x + 1); });
  };
  aw::PackedTextures p = pack({row(TextureDesc::Wrap::Repeat), row(TextureDesc::Wrap::Clamp),
                               row(TextureDesc::Wrap::Mirror), row(TextureDesc::Wrap::Black)});
  struct Case {
    float u;
    float want[4];  // repeat, clamp, mirror, black
  } cases[] = {
      {0.375f, {0.2f, 0.2f, 0.2f, 0.2f}},     // texel 1, inside
      {-0.125f, {0.4f, 0.1f, 0.1f, 0.0f}},    // texel -1
      {-0.375f, {0.3f, 0.1f, 0.2f, 0.0f}},    // texel -2
      {1.125f, {0.1f, 0.4f, 0.4f, 0.0f}},     // texel 4
      {2.875f, {0.4f, 0.4f, 0.4f, 0.0f}},     // texel 11 (mirror: 0 1 2 3 3 2 1 0 0 1 2 3)
      {1.875f, {0.4f, 0.4f, 0.1f, 0.0f}},     // texel 7
  };
  for (const Case& c : cases)
    for (size_t w = 0; w < 4; ++w)
      EXPECT_NEAR(eval(p, w, c.u, 0.5f, 0.0f).x, c.want[w], 1e-6) << "u " << c.u << " wrap " << w;
  // Huge coordinates stay finite and in range (the coordinate is reduced before indexing).
  for (size_t w = 0; w < 4; ++w) {
    float4 c = eval(p, w, 1e9f, -3e8f, 0.0f);
    EXPECT_TRUE(std::isfinite(c.x) && c.x >= 0.0f && c.x <= 0.4f) << w;
  }
}

// 8-bit sRGB images are decoded to linear with the exact IEC 61966-2-1 curve; "linear" keeps
// the stored values. The PNG is written by the renderer's own preview writer (linear -> sRGB).
TEST(Texture, SrgbDecode) {
  aw::Image img;
  img.width = 8;
  img.height = 1;
  const float values[8] = {0.0f, 0.001f, 0.003f, 0.05f, 0.2f, 0.5f, 0.8f, 1.0f};
  for (float v : values)
    for (int c = 0; c < 3; ++c) img.rgb.push_back(v);
  const std::string path = testing::TempDir() + "/srgb_ramp_" + std::to_string(getpid()) + ".png";
  aw::write_png_preview(path, img, 1.0f);
  TextureDesc lin, srgb;
  lin.colorspace = TextureDesc::ColorSpace::Linear;
  srgb.colorspace = TextureDesc::ColorSpace::Srgb;
  std::string err;
  ASSERT_TRUE(aw::load_texture_file(path, &lin, &err)) << err;
  ASSERT_TRUE(aw::load_texture_file(path, &srgb, &err)) << err;
  ASSERT_EQ(srgb.width, 8);
  EXPECT_TRUE(srgb.eight_bit);
  aw::PackedTextures p = pack({srgb});
  for (int x = 0; x < 8; ++x) {
    const double byte = std::round(double(lin.texels[size_t(x) * 4]) * 255.0);
    const double c = byte / 255.0;
    const double want = c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
    EXPECT_NEAR(srgb.texels[size_t(x) * 4], want, 1e-7) << "texel " << x;
    // Within a quantisation step of what was written.
    EXPECT_NEAR(want, values[x], std::max(0.5 / 255.0 / 12.92, 0.5 / 255.0 * 2.4 * std::pow(values[x], 1.0 / 2.4 * 1.4)))
        << "texel " << x;
    // Packed as a half, read back at the texel centre.
    const float got = eval(p, 0, (float(x) + 0.5f) / 8.0f, 0.5f, 0.0f).x;
    EXPECT_NEAR(got, want, std::max(want * 1e-3, 1e-7)) << "texel " << x;
  }
  // Byte 128 (the textbook value).
  EXPECT_NEAR(std::pow((128.0 / 255.0 + 0.055) / 1.055, 2.4), 0.2158605, 1e-6);
}

// The checker under a box footprint equals the mean of the point checker over the box
// (numerical integration on a 400 x 400 grid), and a footprint of two cells is grey.
TEST(Texture, CheckerIsBoxFiltered) {
  TextureDesc t = procedural(TextureDesc::Type::Checker, glm::vec2(8.0f, 8.0f));
  t.color1 = glm::vec3(1.0f);
  t.color2 = glm::vec3(0.0f);
  aw::PackedTextures p = pack({t});
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> uni(0.0f, 1.0f);
  for (int k = 0; k < 40; ++k) {
    const float u = uni(rng), v = uni(rng), f = 0.02f + 0.3f * uni(rng);  // f in UV units; 8 cells per unit
    double sum = 0.0;
    const int n = 400;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        sum += eval(p, 0, u + f * ((i + 0.5f) / n - 0.5f), v + f * ((j + 0.5f) / n - 0.5f), 0.0f).x;
    EXPECT_NEAR(eval(p, 0, u, v, f).x, sum / (double(n) * n), 4e-3) << "u " << u << " v " << v << " f " << f;
  }
  EXPECT_NEAR(eval(p, 0, 0.3f, 0.7f, 0.25f).x, 0.5f, 1e-6);  // two cells wide
  EXPECT_EQ(eval(p, 0, 0.01f, 0.01f, 0.0f).x, 1.0f);          // color1 at UV (0, 0)
  EXPECT_EQ(eval(p, 0, 0.13f, 0.01f, 0.0f).x, 0.0f);
}

// A 64 x 64 image of alternating 0/1 texels: level 1 and above are 0.5 everywhere. A footprint
// of one texel reads level 0, of two texels level 1, between them a blend (trilinear).
TEST(Texture, MipLevelFollowsTheFootprint) {
  TextureDesc t = image(64, 64, 1, false, TextureDesc::ColorSpace::Linear, TextureDesc::Wrap::Repeat,
                        [](int x, int y, int) { return float((x + y) & 1); });
  aw::PackedTextures p = pack({t});
  EXPECT_EQ(p.textures[0].levels, 7u);
  EXPECT_EQ(tex_image_level(&p.textures[0], 1.0f / 64.0f), 0.0f);
  EXPECT_NEAR(tex_image_level(&p.textures[0], 2.0f / 64.0f), 1.0f, 1e-6);
  EXPECT_NEAR(tex_image_level(&p.textures[0], 8.0f / 64.0f), 3.0f, 1e-6);
  EXPECT_EQ(tex_image_level(&p.textures[0], 1000.0f), 6.0f);
  const float u = 2.5f / 64.0f, v = 1.0f - 3.5f / 64.0f;  // the centre of texel (2, 3): value 1
  EXPECT_EQ(eval(p, 0, u, v, 0.0f).x, 1.0f);
  EXPECT_EQ(eval(p, 0, u, v, 1.0f / 64.0f).x, 1.0f);
  EXPECT_NEAR(eval(p, 0, u, v, 2.0f / 64.0f).x, 0.5f, 1e-6);
  const float a = std::log2(1.5f);  // footprint 1.5 texels: level 0.585
  EXPECT_NEAR(eval(p, 0, u, v, 1.5f / 64.0f).x, (1.0f - a) * 1.0f + a * 0.5f, 1e-5);
}

// ---- rendering ---------------------------------------------------------------------------

double mean_channel(const aw::RenderResult& r, int c) {
  double s = 0.0;
  for (size_t p = 0; p < r.count.size(); ++p) s += r.sum[p * 3 + size_t(c)] / r.count[p];
  return s / double(r.count.size());
}

aw::RenderOptions quiet() {
  aw::RenderOptions o;
  o.progress = false;
  return o;
}

// Camera straight down (from 100 m, 1.1 degrees: nearly parallel rays) through a horizontal
// quad 2 cm above the floor whose cutout opacity is an 8 x 8 checker of
// 0 and 1, onto a white Lambert floor, under a hard sun straight down; the quad's opaque cells
// are black. Camera rays pass through half the quad, and so do the sun's shadow rays, along
// the same (vertical) lines: the visible floor is exactly the lit floor, 0.5 of the image at
// radiance rho E / pi. With the holes ignored by shadow rays the image would be black; with
// the cells ignored by camera rays it would show unlit floor.
TEST(Texture, CutoutHolesLetCameraAndShadowRaysThrough) {
  const std::string scene = aw_test::write_temp_scene("cutout", R"({
    "render": { "width": 64, "height": 64, "spp": 16, "max_depth": 1 },
    "camera": { "position": [0, 100, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 1.1 },
    "lights": [ { "type": "sun", "direction": [0, -1, 0], "angle": 0, "color": [1, 1, 1], "intensity": 3.14159265 } ],
    "textures": { "holes": { "type": "checker", "scale": [8, 8], "color1": [1, 1, 1], "color2": [0, 0, 0] } },
    "materials": {
      "floor": { "diffuse": { "color": [0.5, 0.5, 0.5] }, "reflection": { "weight": 0 } },
      "screen": { "diffuse": { "color": [0, 0, 0] }, "reflection": { "weight": 0 },
                  "cutout_opacity": { "texture": "holes" } }
    },
    "objects": [
      { "shape": "quad", "corner": [-5, 0, 5], "edge_u": [10, 0, 0], "edge_v": [0, 0, -10], "material": "floor" },
      { "shape": "quad", "corner": [-1, 0.02, 1], "edge_u": [2, 0, 0], "edge_v": [0, 0, -2], "material": "screen" }
    ]
  })");
  aw::Scene s = aw::load_scene(scene);
  // The view (1.1 degrees at 100 m: 1.92 m across) lies inside the 2 m quad, symmetric about
  // its centre, so it holds holes and cells in equal parts (the trimmed edge cells are of
  // opposite parity). A camera ray through a hole meets the floor at most 0.96 * 0.02 / 100 m
  // (0.08% of a cell) from where the vertical shadow ray leaves it.
  for (bool scalar : {false, true}) {
    aw::RenderResult r = scalar ? aw::render_scalar(s, quiet()) : aw::render_wavefront(s, quiet());
    const double mean = mean_channel(r, 0);
    std::printf("%s: mean %.5f, expected %.5f\n", scalar ? "scalar" : "wavefront", mean, 0.5 * 0.5);
    // The pixels on cell edges are estimated by 16 jittered samples each: measured within
    // 2.1e-4 (0.08%) of 0.25 on both renderers; the tolerance is 0.4%.
    EXPECT_NEAR(mean, 0.25, 1e-3) << (scalar ? "scalar" : "wavefront");
    EXPECT_EQ(r.stats.bad_samples, 0u);
  }
}

// A Lambert plane bumped by a height that rises linearly along u (an EXR ramp, h = k u with
// bump.scale s) under a hard sun straight down: the bumped normal is tilted by
// atan(s k / |dP/du|) (Blinn 1978), so the radiance is rho E cos(tilt) / pi. With
// diffuse.disable_bump the diffuse lobe shades with the flat normal again (rho E / pi), while
// reflection.disable_bump on the same diffuse-only material changes nothing.
TEST(Texture, BumpTiltsTheNormalByTheAnalyticAngle) {
  // h(u) = u at every texel centre, so the bilinear ramp is exactly u in between (clamp).
  const int w = 64;
  aw::Image ramp;
  ramp.width = w;
  ramp.height = 1;
  for (int x = 0; x < w; ++x)
    for (int c = 0; c < 3; ++c) ramp.rgb.push_back((float(x) + 0.5f) / float(w));
  const std::string exr = testing::TempDir() + "/bump_ramp_" + std::to_string(getpid()) + ".exr";
  aw::write_exr(exr, ramp);
  const double L = 4.0, tilt = 30.0 * M_PI / 180.0;
  const double scale = std::tan(tilt) * L;  // s k / L = tan(tilt) with k = 1
  auto scene = [&](const std::string& disable) {
    char buf[2048];
    std::snprintf(buf, sizeof buf, R"({
      "render": { "width": 32, "height": 32, "spp": 4, "max_depth": 1 },
      "camera": { "position": [0, 100, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 0.5 },
      "lights": [ { "type": "sun", "direction": [0, -1, 0], "angle": 0, "color": [1, 1, 1], "intensity": 3.14159265 } ],
      "textures": { "ramp": { "file": "%s", "wrap": "clamp" } },
      "materials": { "m": { "diffuse": { "color": [0.5, 0.5, 0.5] %s }, "reflection": { "weight": 0 %s },
                            "bump": { "input": "ramp", "scale": %.9g } } },
      "objects": [ { "shape": "quad", "corner": [-2, 0, 2], "edge_u": [4, 0, 0], "edge_v": [0, 0, -4], "material": "m" } ]
    })",
                  exr.c_str(), disable == "diffuse" ? R"(, "disable_bump": true)" : "",
                  disable == "reflection" ? R"(, "disable_bump": true)" : "", scale);
    return aw::load_scene(aw_test::write_temp_scene("bump", buf));
  };
  const double flat = 0.5, bumped = 0.5 * std::cos(tilt);
  for (bool scalar : {false, true}) {
    auto render = [&](const aw::Scene& s) { return scalar ? aw::render_scalar(s, quiet()) : aw::render_wavefront(s, quiet()); };
    const char* who = scalar ? "scalar" : "wavefront";
    EXPECT_NEAR(mean_channel(render(scene("")), 1), bumped, 2e-4) << who;
    EXPECT_NEAR(mean_channel(render(scene("diffuse")), 1), flat, 2e-4) << who << ", diffuse.disable_bump";
    EXPECT_NEAR(mean_channel(render(scene("reflection")), 1), bumped, 2e-4) << who << ", reflection.disable_bump";
  }
}

// A glTF quad on y = 0 over [-2, 2]^2 (normals +y) with the given UV sets (4 corners each,
// glTF convention), written next to the test's scenes; `uv1` empty: one set.
std::string write_quad_gltf(const std::string& name, const std::vector<float>& uv0, const std::vector<float>& uv1) {
  std::vector<float> f = {-2, 0, 2, 2, 0, 2, 2, 0, -2, -2, 0, -2, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0};
  f.insert(f.end(), uv0.begin(), uv0.end());
  f.insert(f.end(), uv1.begin(), uv1.end());
  const uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
  std::vector<uint8_t> bin(f.size() * 4 + sizeof(idx));
  std::memcpy(bin.data(), f.data(), f.size() * 4);
  std::memcpy(bin.data() + f.size() * 4, idx, sizeof(idx));
  std::string views, accessors, attributes = R"("POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2)";
  auto view = [&](size_t offset, size_t bytes) {
    views += std::string(views.empty() ? "" : ",") + R"({"buffer": 0, "byteOffset": )" + std::to_string(offset) +
             R"(, "byteLength": )" + std::to_string(bytes) + "}";
  };
  view(0, 48);
  view(48, 48);
  view(96, 32);
  std::string acc = R"({"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-2, 0, -2], "max": [2, 0, 2]},
                       {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
                       {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"})";
  size_t at = 128;
  if (!uv1.empty()) {
    view(at, 32);
    acc += R"(, {"bufferView": 3, "componentType": 5126, "count": 4, "type": "VEC2"})";
    attributes += R"(, "TEXCOORD_1": 3)";
    at += 32;
  }
  view(at, sizeof(idx));
  acc += R"(, {"bufferView": )" + std::to_string(uv1.empty() ? 3 : 4) + R"(, "componentType": 5125, "count": 6, "type": "SCALAR"})";
  const std::string json = R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "scene": 0, "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {)" + attributes + R"(}, "indices": )" + std::to_string(uv1.empty() ? 3 : 4) + R"(}]}],
    "buffers": [{"byteLength": )" + std::to_string(bin.size()) + R"(, "uri": "data:application/octet-stream;base64,)" +
                           aw_test::base64(bin) + R"("}],
    "bufferViews": [)" + views + R"(], "accessors": [)" + acc + "]}";
  const std::string path = testing::TempDir() + "/" + name + "_" + std::to_string(getpid()) + ".gltf";
  std::ofstream(path) << json;
  return path;
}

// The second UV set (glTF TEXCOORD_1): a checker colour, a checker cutout and a noise bump all
// bound with uv_set 1 on a quad whose two sets differ (set 1 scaled, sheared and shifted) give
// the same image, bit for bit in the scalar path, as the quad whose only set is that set 1
// read as set 0; set 0 on the first quad gives another image; likewise anisotropy.uv_set for
// the "uv" frame; and the wavefront matches the scalar path per pixel with the set-1 bindings
// (the device's uv2 path).
TEST(Texture, SecondUvSet) {
  const std::vector<float> uv0 = {0, 1, 1, 1, 1, 0, 0, 0};
  // Set 1 turned a quarter turn against set 0 (u runs along the quad's other edge), scaled and sheared.
  const std::vector<float> uv1 = {0.3f, 0.2f, 0.3f, 3.2f, 2.8f, 3.4f, 2.8f, 0.5f};
  const std::string two = write_quad_gltf("uv_two_sets", uv0, uv1), one = write_quad_gltf("uv_one_set", uv1, {});
  auto scene = [&](const std::string& file, int set) {
    const std::string s = std::to_string(set);
    return aw::load_scene(aw_test::write_temp_scene("uv_set", R"({
      "render": { "width": 48, "height": 48, "spp": 4, "max_depth": 3 },
      "camera": { "position": [0, 5, 3], "look_at": [0, 0, 0], "fov": 50 },
      "environment": { "type": "constant", "color": [0.3, 0.3, 0.3] },
      "lights": [ { "type": "sun", "direction": [-0.3, -1, -0.2], "angle": 2, "intensity": 3 } ],
      "textures": { "checks": { "type": "checker", "scale": [4, 4], "color1": [0.9, 0.6, 0.2], "color2": [0.1, 0.3, 0.7] },
                    "holes": { "type": "checker", "scale": [3, 3], "color1": [1, 1, 1], "color2": [0, 0, 0] },
                    "bumps": { "type": "noise", "scale": [6, 6], "octaves": 3 } },
      "materials": { "m": { "diffuse": { "color": { "texture": "checks", "uv_set": )" + s + R"( } },
                            "reflection": { "weight": 0.3, "glossiness": 0.6 },
                            "cutout_opacity": { "texture": "holes", "uv_set": )" + s + R"( },
                            "bump": { "input": { "texture": "bumps", "uv_set": )" + s + R"( }, "scale": 0.05 } },
                     "floor": { "diffuse": { "color": [0.5, 0.5, 0.5] } } },
      "objects": [ { "shape": "mesh", "file": ")" + file + R"(", "material": "m", "transform": { "translate": [0, 0.5, 0] } },
                   { "shape": "quad", "corner": [-5, 0, 5], "edge_u": [10, 0, 0], "edge_v": [0, 0, -10], "material": "floor" } ]
    })"));
  };
  const aw::Scene a1 = scene(two, 1), b0 = scene(one, 0), a0 = scene(two, 0);
  const aw::RenderResult r_a1 = aw::render_scalar(a1, quiet()), r_b0 = aw::render_scalar(b0, quiet()),
                         r_a0 = aw::render_scalar(a0, quiet());
  size_t differ = 0;
  for (size_t i = 0; i < r_a1.sum.size(); ++i) differ += r_a1.sum[i] != r_b0.sum[i];
  EXPECT_EQ(differ, 0u) << "uv_set 1 on the two-set quad vs set 0 of the one-set quad";
  const aw::ImageDiff d = aw::compare_images(r_a1.image(a1), r_a0.image(a0), 1e-3, 1e-4);
  std::printf("uv_set 1 vs uv_set 0 on the same quad: %.1f%% of pixels within 1e-3\n", d.frac_pixels_within * 100);
  EXPECT_LT(d.frac_pixels_within, 0.8);  // the quad covers about half the image
  // anisotropy.uv_set: the "uv" frame follows the set (scalar path; the frame code is shared).
  auto aniso = [&](const std::string& file, int set) {
    return aw::load_scene(aw_test::write_temp_scene("uv_set_aniso", R"({
      "render": { "width": 32, "height": 32, "spp": 4, "max_depth": 2 },
      "camera": { "position": [0, 5, 3], "look_at": [0, 0, 0], "fov": 50 },
      "lights": [ { "type": "quad", "corner": [-1, 4, -1], "edge_u": [2, 0, 0], "edge_v": [0, 0, 2], "intensity": 10 } ],
      "materials": { "m": { "diffuse": { "color": [0.9, 0.9, 0.9] }, "metal": true,
                            "reflection": { "weight": 1, "glossiness": 0.6 },
                            "anisotropy": { "amount": 0.9, "orientation": "uv", "uv_set": )" + std::to_string(set) + R"( } } },
      "objects": [ { "shape": "mesh", "file": ")" + file + R"(", "material": "m" } ]
    })"));
  };
  const aw::Scene s_a1 = aniso(two, 1), s_b0 = aniso(one, 0), s_a0 = aniso(two, 0);
  const aw::RenderResult q_a1 = aw::render_scalar(s_a1, quiet()), q_b0 = aw::render_scalar(s_b0, quiet()),
                         q_a0 = aw::render_scalar(s_a0, quiet());
  size_t adiff = 0;
  for (size_t i = 0; i < q_a1.sum.size(); ++i) adiff += q_a1.sum[i] != q_b0.sum[i];
  EXPECT_EQ(adiff, 0u) << "anisotropy.uv_set 1 on the two-set quad vs set 0 of the one-set quad";
  const aw::ImageDiff da = aw::compare_images(q_a1.image(s_a1), q_a0.image(s_a0), 1e-3, 1e-4);
  std::printf("anisotropy.uv_set 1 vs 0: %.1f%% of pixels within 1e-3 (means %.4f, %.4f)\n", da.frac_pixels_within * 100,
              da.mean_a, da.mean_b);
  EXPECT_LT(da.frac_pixels_within, 0.8);

  const aw::RenderResult w = aw::render_wavefront(a1, quiet());
  const aw::ImageDiff dw = aw::compare_images(w.image(a1), r_a1.image(a1), 1e-3, 1e-4);
  std::printf("wavefront vs scalar, uv_set 1: %.2f%% of pixels within 1e-3\n", dw.frac_pixels_within * 100);
  EXPECT_GE(dw.frac_pixels_within, 0.99);
  EXPECT_EQ(w.stats.bad_samples, 0u);
}

// The textured test scene (checker floor, a cutout screen, a bumped glossy sphere, noise),
// per pixel: the wavefront against the scalar path, and the specialised build against the
// generic one.
TEST(Texture, TexturedSceneKernelMatchesScalar) {
  aw_test::expect_kernel_matches_scalar("scenes/textures/texture_test.json", {"render.width=64", "render.height=48", "render.spp=8"});
}

// Bad texture input: each names the file, the key and what is wrong.
TEST(Texture, LoaderErrors) {
  auto fails_with = [](const std::string& json, const std::string& want) {
    const std::string path = aw_test::write_temp_scene("bad_texture", json);
    try {
      aw::load_scene(path);
      ADD_FAILURE() << "loaded: " << json;
    } catch (const aw::SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(want), std::string::npos) << e.what();
    }
  };
  const std::string tex = R"("textures": { "checks": { "type": "checker" } })";
  fails_with("{" + tex + R"(, "materials": { "m": { "diffuse": { "color": { "texture": "chekcs" } } } } })",
             "no texture named \"chekcs\" in the textures section (did you mean \"checks\"?)");
  fails_with("{" + tex + R"(, "materials": { "m": { "refraction": { "ior": { "texture": "checks" } } } } })",
             "refraction.ior cannot be read from a texture");
  fails_with("{" + tex + R"(, "lights": [ { "type": "point", "color": { "texture": "checks" } } ] })",
             "only material inputs take a texture");
  fails_with(R"({ "textures": { "t": { "file": "no_such_file.png" } } })", "cannot open the file");
  fails_with(R"({ "textures": { "t": { "type": "checker", "file": "x.png" } } })", "textures.t.file");
  fails_with(R"({ "textures": { "t": { "type": "checker", "scale": [0, 1] } } })", "scale must be finite and non-zero");
  fails_with("{" + tex + R"(, "materials": { "m": { "diffuse": { "color": { "texture": "checks", "channel": "luminance" } } } } })",
             "unknown value \"luminance\"");
  const std::string not_image = aw_test::write_temp_scene("not_an_image", "this is text");
  fails_with(R"({ "textures": { "t": { "file": ")" + not_image + R"(" } } })", "not a PNG, JPEG or EXR image");
  // A 752-byte EXR whose damaged header claims a window of 2.4 GB of texels (found by
  // fuzz_image): refused before the texels are allocated.
  fails_with(R"({ "textures": { "t": { "file": ")" + aw_test::source_path("tests/fuzz/seeds/exr_window_huge.exr") +
                 R"(" } } })",
             "bytes can hold at any EXR compression (a damaged header)");
}

}  // namespace

namespace {

// Issue 16's extremes for textures: a 1 x 1 image, UV scales of 1e-6 and 1e6, bump scales 0 and
// +-1e6, an opacity map that removes everything, on a quad and an analytic sphere seen close
// and at a grazing angle: both renderers, no sample discarded (the guard is a safety net, not
// the fix: docs/numerics.md).
TEST(Texture, ExtremesRenderFinite) {
  aw::Image one;
  one.width = one.height = 1;
  one.rgb = {0.7f, 0.2f, 0.9f};
  const std::string exr = testing::TempDir() + "/one_texel_" + std::to_string(getpid()) + ".exr";
  aw::write_exr(exr, one);
  for (const char* bump : {"0", "1e6", "-1e6"}) {
    for (const char* scale : {"1e-6", "1e6"}) {
      char buf[4096];
      std::snprintf(buf, sizeof buf, R"({
        "render": { "width": 24, "height": 16, "spp": 4, "max_depth": 4 },
        "camera": { "position": [0, 0.3, 2], "look_at": [0, 0.25, 0], "fov": 50 },
        "environment": { "type": "constant", "color": [0.3, 0.3, 0.3] },
        "lights": [ { "type": "sphere", "center": [0, 2, 1], "radius": 0.2, "intensity": 20 } ],
        "textures": {
          "one": { "file": "%s" },
          "noise": { "type": "noise", "scale": %s, "octaves": 16 },
          "gone": { "type": "checker", "color1": [0, 0, 0], "color2": [0, 0, 0] }
        },
        "materials": {
          "a": { "diffuse": { "color": { "texture": "one" } }, "reflection": { "glossiness": { "texture": "noise" } },
                 "anisotropy": { "amount": 0.9, "rotation": { "texture": "noise" } }, "bump": { "input": "noise", "scale": %s } },
          "b": { "diffuse": { "color": { "texture": "noise" } }, "bump": { "input": "one", "scale": %s } },
          "hole": { "cutout_opacity": { "texture": "gone" } }
        },
        "objects": [
          { "shape": "quad", "corner": [-5, 0, 5], "edge_u": [10, 0, 0], "edge_v": [0, 0, -10], "material": "a" },
          { "shape": "sphere", "center": [0.4, 0.25, 0], "radius": 0.25, "material": "b" },
          { "shape": "sphere", "center": [-0.4, 0.25, 0], "radius": 0.25, "material": "a" },
          { "shape": "quad", "corner": [-1, 0, 1], "edge_u": [2, 0, 0], "edge_v": [0, 1, 0], "material": "hole" }
        ]
      })",
                    exr.c_str(), scale, bump, bump);
      aw::Scene s = aw::load_scene(aw_test::write_temp_scene("texture_extreme", buf));
      for (bool scalar : {false, true}) {
        aw::RenderResult r = scalar ? aw::render_scalar(s, quiet()) : aw::render_wavefront(s, quiet());
        EXPECT_EQ(r.stats.bad_samples, 0u) << "bump " << bump << ", scale " << scale << (scalar ? ", scalar" : ", wavefront");
        for (float x : r.sum) ASSERT_TRUE(std::isfinite(x)) << "bump " << bump << ", scale " << scale;
      }
    }
  }
}

}  // namespace

namespace {

// Writes a w x h 8-bit grey PNG (colour type 0), texel (x, y) = value(x, y) with row 0 at the
// top, compressed row by row through zlib (level 1), so no image-sized buffer is needed.
template <class F>
void write_grey_png(const std::string& path, uint32_t w, uint32_t h, F value) {
  std::ofstream f(path, std::ios::binary);
  auto put32 = [](std::string* s, uint32_t v) {
    for (int k = 3; k >= 0; --k) s->push_back(char((v >> (8 * k)) & 0xff));
  };
  auto chunk = [&](const char* type, const std::string& data) {
    std::string c;
    put32(&c, uint32_t(data.size()));
    c += type;
    c += data;
    uLong crc = crc32(0, reinterpret_cast<const Bytef*>(c.data() + 4), uInt(c.size() - 4));
    put32(&c, uint32_t(crc));
    f.write(c.data(), std::streamsize(c.size()));
  };
  f.write("\x89PNG\r\n\x1a\n", 8);
  std::string ihdr;
  put32(&ihdr, w);
  put32(&ihdr, h);
  ihdr += std::string("\x08\x00\x00\x00\x00", 5);  // 8 bits, grey, deflate, no filter, no interlace
  chunk("IHDR", ihdr);
  z_stream z{};
  ASSERT_EQ(deflateInit(&z, 1), Z_OK);
  std::vector<unsigned char> row(size_t(w) + 1), out(1 << 20);
  std::string idat;
  auto pump = [&](int flush) {
    do {
      z.next_out = out.data();
      z.avail_out = uInt(out.size());
      deflate(&z, flush);
      idat.append(reinterpret_cast<const char*>(out.data()), out.size() - z.avail_out);
      if (idat.size() >= (1u << 24)) {
        chunk("IDAT", idat);
        idat.clear();
      }
    } while (z.avail_out == 0);
  };
  for (uint32_t y = 0; y < h; ++y) {
    row[0] = 0;  // filter type None
    for (uint32_t x = 0; x < w; ++x) row[x + 1] = value(x, y);
    z.next_in = row.data();
    z.avail_in = uInt(row.size());
    pump(Z_NO_FLUSH);
  }
  pump(Z_FINISH);
  deflateEnd(&z);
  if (!idat.empty()) chunk("IDAT", idat);
  chunk("IEND", "");
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The largest image a texture may have (docs/scene-format.md: 16384 x 16384 texels), an 8-bit
// grey PNG read as linear (8-bit texels on the device, 256 MiB at level 0, 15 mip levels), whose
// far corner differs from the rest: the last 2 x 2 texels (largest x and y: the largest texel
// indices and byte offsets there are) are 255, a band of 5 x 3 texels around them 200, the rest
// 64. The PNG's rows run from the top, V = 1, so the last row is at V = 0, and texel (i, j) of
// the quad below (corner at the origin, edge_u 16384 along +x, edge_v 16384 along -z: one texel
// per unit) covers x in [i, i + 1], z in [j - 16384, j + 1 - 16384]. A camera 4 units above,
// looking straight down with a 53.13-degree field of view (tan = 1/2), sees x in [16377.875,
// 16383.875] and z in [-4.125, -0.125], a quarter texel per pixel: the ray cone (0.25-0.29
// texels wide) reads level 0. A Lambert quad under a constant environment of radiance 1 and
// nothing else has radiance equal to its albedo (every sample exactly: the bounce ray always
// escapes), so a pixel whose bilinear stencils touch only texels of one value is exactly that
// value (bilinear filtering with clamp: the pure regions run between the texel centres of a
// value's texels). Both renderers, per pixel, no sample discarded.
TEST(Texture, LargestImageReadsItsFarCornerAtLevelZero) {
  const uint32_t n = 16384;
  auto texel = [n](uint32_t x, uint32_t y) -> unsigned char {
    if (x >= n - 2 && y >= n - 2) return 255;
    if (x >= n - 5 && y >= n - 3) return 200;
    return 64;
  };
  const std::string png = testing::TempDir() + "/largest_" + std::to_string(getpid()) + ".png";
  auto t0 = std::chrono::steady_clock::now();
  write_grey_png(png, n, n, texel);
  const double write_s = seconds_since(t0);
  const std::string path = aw_test::write_temp_scene("texture_largest", R"({
    "render": { "width": 24, "height": 16, "spp": 4, "seed": 2, "max_depth": 2 },
    "camera": { "position": [16380.875, 4, -2.125], "look_at": [16380.875, 0, -2.125], "up": [0, 0, -1],
                "fov": 53.130102354155978 },
    "environment": { "type": "constant", "color": [1, 1, 1] },
    "textures": { "big": { "file": ")" + png + R"(", "colorspace": "linear", "wrap": "clamp" } },
    "materials": { "m": { "diffuse": { "color": { "texture": "big" } }, "reflection": { "weight": 0 } } },
    "objects": [ { "shape": "quad", "corner": [0, 0, 0], "edge_u": [16384, 0, 0], "edge_v": [0, 0, -16384], "material": "m" } ]
  })");
  t0 = std::chrono::steady_clock::now();
  const aw::Scene s = aw::load_scene(path);
  const double load_s = seconds_since(t0);
  std::remove(png.c_str());
  ASSERT_EQ(s.textures.size(), 1u);
  ASSERT_EQ(s.textures[0].width, int(n));
  ASSERT_EQ(s.textures[0].height, int(n));
  aw::RenderOptions o = quiet();
  o.generic_kernels = true;
  t0 = std::chrono::steady_clock::now();
  const aw::RenderResult w = aw::render_wavefront(s, o);
  const double wave_s = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  const aw::RenderResult sc = aw::render_scalar(s, o);
  const double scalar_s = seconds_since(t0);
  std::printf("16384 x 16384 PNG: written in %.2f s, loaded in %.2f s; wavefront %.2f s, scalar %.2f s\n", write_s, load_s, wave_s,
              scalar_s);
  EXPECT_EQ(w.stats.bad_samples, 0u);
  EXPECT_EQ(sc.stats.bad_samples, 0u);
  const double a = 64.0 / 255.0, b = 200.0 / 255.0, c = 1.0;
  int pure[3] = {0, 0, 0}, mixed = 0;
  double worst_pure = 0.0, worst_mixed = 0.0, worst_pair_pure = 0.0, worst_pair_mixed = 0.0;
  for (int py = 0; py < w.height; ++py) {
    for (int px = 0; px < w.width; ++px) {
      const size_t p = size_t(py) * size_t(w.width) + size_t(px);
      const double x0 = 16377.875 + 0.25 * px, x1 = x0 + 0.25, z0 = -4.125 + 0.25 * py, z1 = z0 + 0.25;
      // Pure regions, with a margin of 0.01 texel for the hit points' rounding (ulp(16384) = 0.002).
      const double m = 0.01;
      int kind = -1;
      if (x1 <= 16378.5 - m || z1 <= -3.5 + m) kind = 0;                                           // A
      else if (x0 >= 16379.5 + m && x1 <= 16381.5 - m && z0 >= -2.5 + m) kind = 1;                 // B
      else if (x0 >= 16382.5 + m && z0 >= -1.5 + m) kind = 2;                                      // C
      const double want[3] = {a, b, c};
      for (const aw::RenderResult* r : {&w, &sc}) {
        for (int ch = 0; ch < 3; ++ch) {
          const double v = double(r->sum[p * 3 + size_t(ch)]) / double(r->count[p]);
          ASSERT_TRUE(std::isfinite(v));
          if (kind >= 0) worst_pure = std::max(worst_pure, std::fabs(v / want[kind] - 1.0));
          else worst_mixed = std::max(worst_mixed, std::max(a - v, v - c) / c);
        }
      }
      for (int ch = 0; ch < 3; ++ch) {
        const double u = w.sum[p * 3 + size_t(ch)] / w.count[p], v = sc.sum[p * 3 + size_t(ch)] / sc.count[p];
        double& worst_pair = kind >= 0 ? worst_pair_pure : worst_pair_mixed;
        worst_pair = std::max(worst_pair, std::fabs(u - v) / std::max(u, v));
      }
      if (kind >= 0) ++pure[kind];
      else ++mixed;
    }
  }
  std::printf("pixels: %d of the rest (64), %d of the band (200), %d of the corner (255), %d mixed; largest relative deviation of a "
              "pure pixel %.3g, a mixed pixel's excursion outside [64, 255]/255 %.3g; wavefront vs scalar %.3g (pure pixels), "
              "%.3g (mixed)\n",
              pure[0], pure[1], pure[2], mixed, worst_pure, worst_mixed, worst_pair_pure, worst_pair_mixed);
  EXPECT_EQ(pure[0], 76);
  EXPECT_EQ(pure[1], 63);
  EXPECT_EQ(pure[2], 25);
  EXPECT_LE(worst_pure, 1e-5);
  EXPECT_LE(worst_mixed, 1e-6);
  EXPECT_LE(worst_pair_pure, 1e-6);
  // Where a pixel's samples straddle two values, the renderers' hit points (Embree's and the
  // kernels' barycentrics) differ by an ulp or two of 16384 (1/512 texel), and the bilinear
  // slope is at most (255 - 64)/255 per texel: up to 3e-3 per sample, a quarter of that in a
  // 4-sample pixel on average. Measured: 1.5e-3 relative.
  EXPECT_LE(worst_pair_mixed, 5e-3);
}

}  // namespace
