// load_scene: JSON text -> validated, defaulted, triangulated Scene (docs/scene-format.md).
#include "host/scene/scene.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <sstream>

#include "host/film/image_io.h"
#include "host/scene/gltf_mesh.h"
#include "host/scene/obj_materials.h"
#include "host/scene/loader_parts.h"
#include "kernels/common/compat.h"
#include "kernels/integrator/aov.h"
#include "kernels/types/material.h"

namespace aw {
namespace scene_detail {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kMaxInt = std::numeric_limits<int>::max();

// Small helper: run `fn(node)` when `key` is present in `obj`.
template <class Fn>
void if_present(const Node& obj, const char* key, Fn fn) {
  Node c = child(obj, key);
  if (c.j) fn(c);
}

glm::vec3 read_colour_nonnegative(const LoadContext& ctx, const Node& n) {
  const glm::dvec3 c = read_colour(ctx, n);
  if (c.x < 0 || c.y < 0 || c.z < 0) {
    ctx.fail(n.path, "colour components must be >= 0, got " + describe(*n.j));
  }
  return glm::vec3(c);
}

glm::vec3 to_f(const glm::dvec3& v) { return glm::vec3(v); }

std::string mib(uint64_t bytes) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.1f MiB", double(bytes) / (1024.0 * 1024.0));
  return buf;
}


// ---- render ----------------------------------------------------------------------------------

void parse_render(const LoadContext& ctx, const Node& n, RenderSettings* r) {
  expect_object(ctx, n,
                {"width", "height", "spp", "seed", "max_depth", "reflection_depth",
                 "refraction_depth", "gi", "cutoff", "lobe_splitting", "clamp", "rr_depth", "sampler",
                 "light_selection", "instancing", "aovs"});
  // 65536 per side is far beyond any film we write and keeps width * height in range.
  if_present(n, "width", [&](const Node& c) { r->width = read_int_in(ctx, c, 1, 65536); });
  if_present(n, "height", [&](const Node& c) { r->height = read_int_in(ctx, c, 1, 65536); });
  // Pixel indices are 32-bit on the device (and a film of 2^31 pixels would take 32 GiB):
  // caught here, naming the keys, rather than wrapping around in the renderer (found by the
  // bad-input corpus: 65536 x 65536 rendered an empty film and failed in clEnqueueReadBuffer).
  if (int64_t(r->width) * int64_t(r->height) > int64_t(kMaxInt)) {
    ctx.fail(has(n, "height") ? join_key(n.path, "height") : join_key(n.path, "width"),
             "width x height = " + std::to_string(int64_t(r->width) * int64_t(r->height)) +
                 " pixels; at most 2^31 - 1 (" + std::to_string(kMaxInt) + ") are supported");
  }
  if_present(n, "spp", [&](const Node& c) { r->spp = read_int_in(ctx, c, 1, kMaxInt); });
  if_present(n, "seed", [&](const Node& c) {
    const int64_t v = read_integer(ctx, c);
    if (v < 0 || v > static_cast<int64_t>(std::numeric_limits<uint32_t>::max())) {
      ctx.fail(c.path, "must be a non-negative integer below 2^32, got " + describe(*c.j));
    }
    r->seed = static_cast<uint32_t>(v);
  });
  if_present(n, "max_depth",
             [&](const Node& c) { r->max_depth = read_int_in(ctx, c, 0, kMaxInt); });
  if_present(n, "reflection_depth",
             [&](const Node& c) { r->reflection_depth = read_int_in(ctx, c, 0, kMaxInt); });
  if_present(n, "refraction_depth",
             [&](const Node& c) { r->refraction_depth = read_int_in(ctx, c, 0, kMaxInt); });
  if_present(n, "gi", [&](const Node& c) { r->gi = read_bool(ctx, c); });
  if_present(n, "cutoff", [&](const Node& c) {
    r->cutoff = static_cast<float>(read_number_in(ctx, c, Range{0, 1}));
  });
  if_present(n, "lobe_splitting", [&](const Node& c) { r->lobe_splitting = read_bool(ctx, c); });
  if_present(n, "clamp", [&](const Node& c) {
    r->clamp = static_cast<float>(read_number_in(ctx, c, Range{0, kInf}));
  });
  if_present(n, "rr_depth", [&](const Node& c) { r->rr_depth = read_int_in(ctx, c, 0, kMaxInt); });
  if_present(n, "instancing", [&](const Node& c) { r->instancing = read_bool(ctx, c); });
  if_present(n, "light_selection", [&](const Node& c) {
    r->light_selection = read_enum<RenderSettings::LightSelection>(
        ctx, c, {{"auto", RenderSettings::LightSelection::Auto},
                  {"power", RenderSettings::LightSelection::Power},
                  {"tree", RenderSettings::LightSelection::Tree}});
  });
  if_present(n, "aovs", [&](const Node& c) {
    // A list of names, or one string of names separated by commas (as --aovs gives them).
    std::vector<std::pair<std::string, std::string>> names;  // (name, its path)
    if (c.j->is_array()) {
      for (size_t i = 0; i < c.j->size(); ++i) {
        const Node e = element(c, i);
        names.emplace_back(read_string(ctx, e), e.path);
      }
    } else {
      std::string all = read_string(ctx, c), item;
      std::stringstream ss(all);
      while (std::getline(ss, item, ',')) names.emplace_back(item, c.path);
    }
    r->aovs = 0;
    for (const auto& [name, at] : names) {
      const uint32_t bits = aov_bits_for_name(name);
      if (!bits) ctx.fail(at, "\"" + name + "\" is not an AOV; known: " + aov_known_names());
      r->aovs |= bits;
    }
  });
  if_present(n, "sampler", [&](const Node& c) {
    r->sampler = read_enum<RenderSettings::Sampler>(
        ctx, c, {{"sobol", RenderSettings::Sampler::Sobol},
                  {"zsobol", RenderSettings::Sampler::ZSobol},
                  {"independent", RenderSettings::Sampler::Independent}});
  });
}

// ---- camera ----------------------------------------------------------------------------------

void parse_exposure(const LoadContext& ctx, const Node& n, ExposureDesc* e) {
  // All keys are accepted in both modes (and stored) so that -D camera.exposure.mode=stops
  // works on a scene written for photographic exposure.
  expect_object(ctx, n,
                {"mode", "stops", "iso", "shutter", "f_number", "whitepoint", "vignetting"});
  if_present(n, "mode", [&](const Node& c) {
    e->mode = read_enum<ExposureDesc::Mode>(
        ctx, c,
        {{"stops", ExposureDesc::Mode::Stops}, {"photographic", ExposureDesc::Mode::Photographic}});
  });
  if_present(n, "stops",
             [&](const Node& c) { e->stops = static_cast<float>(read_number(ctx, c)); });
  const Range positive{0, kInf, true};
  if_present(n, "iso",
             [&](const Node& c) { e->iso = static_cast<float>(read_number_in(ctx, c, positive)); });
  if_present(n, "shutter", [&](const Node& c) {
    e->shutter = static_cast<float>(read_number_in(ctx, c, positive));
  });
  if_present(n, "f_number", [&](const Node& c) {
    e->f_number = static_cast<float>(read_number_in(ctx, c, positive));
  });
  if_present(n, "whitepoint", [&](const Node& c) {
    const glm::dvec3 w = read_colour(ctx, c);
    // The white point divides the image; a zero or negative channel has no meaning.
    if (!(w.x > 0 && w.y > 0 && w.z > 0)) {
      ctx.fail(c.path, "white point components must be > 0, got " + describe(*c.j));
    }
    e->whitepoint = to_f(w);
  });
  if_present(n, "vignetting", [&](const Node& c) {
    e->vignetting = static_cast<float>(read_number_in(ctx, c, Range{0, kInf}));
  });
}

void parse_camera(const LoadContext& ctx, const Node& n, CameraDesc* cam) {
  expect_object(ctx, n, {"position", "look_at", "up", "fov", "exposure"});
  glm::dvec3 position(cam->position), look_at(cam->look_at), up(cam->up);
  if_present(n, "position", [&](const Node& c) { position = read_vec3(ctx, c); });
  if_present(n, "look_at", [&](const Node& c) { look_at = read_vec3(ctx, c); });
  if_present(n, "up", [&](const Node& c) { up = read_vec3(ctx, c); });
  if_present(n, "fov", [&](const Node& c) {
    cam->fov = static_cast<float>(read_number_in(ctx, c, Range{0, 180, true, true}));
  });
  if_present(n, "exposure", [&](const Node& c) { parse_exposure(ctx, c, &cam->exposure); });

  // A camera without a viewing direction or with "up" along it has no orientation; reject
  // it here rather than render NaNs.
  const glm::dvec3 dir = look_at - position;
  if (!(glm::length(dir) > 0)) {
    ctx.fail(join_key(n.path, "look_at"), "must differ from camera.position");
  }
  const double sin_angle = glm::length(glm::cross(dir, up)) / (glm::length(dir) * glm::length(up));
  if (!(sin_angle > 1e-6)) {
    ctx.fail(join_key(n.path, "up"), "must be non-zero and not parallel to the viewing direction");
  }
  cam->position = to_f(position);
  cam->look_at = to_f(look_at);
  cam->up = to_f(up);
}

// ---- environment -----------------------------------------------------------------------------

std::string resolve_relative(const std::string& scene_path, const std::string& file) {
  namespace fs = std::filesystem;
  const fs::path p(file);
  if (p.is_absolute()) return p.lexically_normal().string();
  return (fs::path(scene_path).parent_path() / p).lexically_normal().string();
}

// Reads the lat-long EXR of an environment map into env->map_rgb. Non-finite texels are an
// error naming the texel (they would make the map's distribution, and every pixel that sees
// it, NaN); negative ones (which some HDR tools and lossy EXR compressions write around black)
// are set to 0 with a warning, since light cannot be negative.
void load_environment_map(LoadContext& ctx, const Node& file_node, EnvironmentDesc* env) {
  Image img;
  try {
    img = read_exr(env->file);
  } catch (const OutputError& e) {
    ctx.fail(file_node.path, std::string("cannot read the environment map: ") + e.what());
  }
  if (img.width <= 0 || img.height <= 0) ctx.fail(file_node.path, "environment map \"" + env->file + "\" is empty");
  size_t negative = 0;
  for (size_t i = 0; i < img.rgb.size(); ++i) {
    float& v = img.rgb[i];
    if (!std::isfinite(v)) {
      const size_t px = i / 3;
      ctx.fail(file_node.path, "environment map \"" + env->file + "\": pixel (" + std::to_string(px % size_t(img.width)) +
                                   ", " + std::to_string(px / size_t(img.width)) + ") is not finite");
    }
    if (v < 0.0f) {
      v = 0.0f;
      ++negative;
    }
  }
  if (negative > 0)
    ctx.warn(file_node.path, "environment map \"" + env->file + "\": " + std::to_string(negative) +
                                 " negative channel values set to 0");
  env->map_width = img.width;
  env->map_height = img.height;
  env->map_rgb = std::move(img.rgb);
}

void parse_environment(LoadContext& ctx, const Node& n, EnvironmentDesc* env) {
  expect_object_any_keys(ctx, n);
  // The type decides which keys are valid, so read it before checking the key set.
  if_present(n, "type", [&](const Node& c) {
    env->type = read_enum<EnvironmentDesc::Type>(ctx, c,
                                                 {{"constant", EnvironmentDesc::Type::Constant},
                                                  {"map", EnvironmentDesc::Type::Map},
                                                  {"sky", EnvironmentDesc::Type::Sky}});
  });
  switch (env->type) {
    case EnvironmentDesc::Type::Constant:
      expect_object(ctx, n, {"type", "color", "intensity"});
      break;
    case EnvironmentDesc::Type::Map:
      expect_object(ctx, n, {"type", "file", "intensity", "rotation", "sampling"});
      break;
    case EnvironmentDesc::Type::Sky:
      expect_object(ctx, n, {"type", "turbidity", "ground_albedo", "intensity", "resolution", "sampling"});
      break;
  }
  if_present(n, "color", [&](const Node& c) { env->color = read_colour_nonnegative(ctx, c); });
  if_present(n, "intensity", [&](const Node& c) {
    env->intensity = static_cast<float>(read_number_in(ctx, c, Range{0, kInf}));
  });
  if_present(n, "rotation", [&](const Node& c) { env->rotation = static_cast<float>(read_number(ctx, c)); });
  // Preetham et al. fitted their model for turbidity 2 to 10 (and show 1.7 as the clearest
  // sky); outside that the formulas give negative luminances.
  if_present(n, "turbidity", [&](const Node& c) {
    env->turbidity = static_cast<float>(read_number_in(ctx, c, Range{1.7, 10}));
  });
  if_present(n, "ground_albedo", [&](const Node& c) {
    const glm::dvec3 a = read_colour(ctx, c);
    if (!(a.x >= 0 && a.y >= 0 && a.z >= 0 && a.x <= 1 && a.y <= 1 && a.z <= 1))
      ctx.fail(c.path, "ground albedo components must be in [0, 1], got " + describe(*c.j));
    env->ground_albedo = to_f(a);
  });
  if_present(n, "resolution", [&](const Node& c) { env->resolution = read_int_in(ctx, c, 16, 16384); });
  if_present(n, "sampling", [&](const Node& c) {
    env->uniform_sampling = read_enum<bool>(ctx, c, {{"importance", false}, {"uniform", true}});
  });
  if (env->type == EnvironmentDesc::Type::Map) {
    const Node file_node = require(ctx, n, "file");
    const std::string file = read_string(ctx, file_node);
    if (file.empty()) ctx.fail(file_node.path, "must not be empty");
    env->file = resolve_relative(ctx.file(), file);
    load_environment_map(ctx, file_node, env);
  }
}

// ---- textures --------------------------------------------------------------------------------

// A [u, v] pair, or one number for both.
glm::vec2 read_uv_pair(const LoadContext& ctx, const Node& n) {
  if (n.j->is_number()) return glm::vec2(float(read_number(ctx, n)));
  if (!n.j->is_array() || n.j->size() != 2) ctx.fail(n.path, "expected [u, v] or one number, got " + describe(*n.j));
  return glm::vec2(float(read_number(ctx, element(n, 0))), float(read_number(ctx, element(n, 1))));
}

// One entry of "textures" (docs/scene-format.md#textures). Image files are read here, with
// their size checked against the memory limit before they are decoded.
TextureDesc parse_texture(LoadContext& ctx, const Node& n, const std::string& name, const LoadLimits& limits) {
  TextureDesc t;
  t.name = name;
  expect_object_any_keys(ctx, n);
  if_present(n, "type", [&](const Node& c) {
    t.type = read_enum<TextureDesc::Type>(
        ctx, c, {{"image", TextureDesc::Type::Image}, {"checker", TextureDesc::Type::Checker}, {"noise", TextureDesc::Type::Noise}});
  });
  const std::vector<std::string> placement = {"type", "scale", "offset", "rotation"};
  auto keys = [&](std::initializer_list<const char*> extra) {
    std::vector<std::string> all = placement;
    for (const char* k : extra) all.push_back(k);
    return all;
  };
  switch (t.type) {
    case TextureDesc::Type::Image: expect_object(ctx, n, keys({"file", "colorspace", "wrap"})); break;
    case TextureDesc::Type::Checker: expect_object(ctx, n, keys({"color1", "color2"})); break;
    case TextureDesc::Type::Noise: expect_object(ctx, n, keys({"color1", "color2", "octaves"})); break;
  }
  if_present(n, "scale", [&](const Node& c) {
    t.scale = read_uv_pair(ctx, c);
    if (!(std::isfinite(t.scale.x) && std::isfinite(t.scale.y)) || t.scale.x == 0.0f || t.scale.y == 0.0f)
      ctx.fail(c.path, "texture \"" + name + "\": scale must be finite and non-zero, got " + describe(*c.j));
  });
  if_present(n, "offset", [&](const Node& c) { t.offset = read_uv_pair(ctx, c); });
  if_present(n, "rotation", [&](const Node& c) { t.rotation = float(read_number(ctx, c)); });
  if_present(n, "color1", [&](const Node& c) { t.color1 = read_colour_nonnegative(ctx, c); });
  if_present(n, "color2", [&](const Node& c) { t.color2 = read_colour_nonnegative(ctx, c); });
  if_present(n, "octaves", [&](const Node& c) { t.octaves = read_int_in(ctx, c, 1, 16); });
  if_present(n, "wrap", [&](const Node& c) {
    t.wrap = read_enum<TextureDesc::Wrap>(ctx, c,
                                          {{"repeat", TextureDesc::Wrap::Repeat},
                                           {"clamp", TextureDesc::Wrap::Clamp},
                                           {"mirror", TextureDesc::Wrap::Mirror},
                                           {"black", TextureDesc::Wrap::Black}});
  });
  if (t.type != TextureDesc::Type::Image) return t;

  const Node file_node = require(ctx, n, "file");
  const std::string file = read_string(ctx, file_node);
  if (file.empty()) ctx.fail(file_node.path, "must not be empty");
  t.source = resolve_relative(ctx.file(), file);
  std::string ext = std::filesystem::path(file).extension().string();
  for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  // Colour space: as given, else by the file's kind (8-bit formats hold sRGB colour, EXR linear).
  t.colorspace = ext == ".exr" ? TextureDesc::ColorSpace::Linear : TextureDesc::ColorSpace::Srgb;
  if_present(n, "colorspace", [&](const Node& c) {
    t.colorspace = read_enum<TextureDesc::ColorSpace>(
        ctx, c, {{"srgb", TextureDesc::ColorSpace::Srgb}, {"linear", TextureDesc::ColorSpace::Linear}});
  });
  std::error_code ec;
  const uintmax_t file_bytes = std::filesystem::file_size(t.source, ec);
  if (!ec && limits.max_bytes > 0 && file_bytes > limits.max_bytes)
    ctx.fail(file_node.path, "texture \"" + name + "\": \"" + t.source + "\" is " + mib(file_bytes) +
                                 ", more than the " + mib(limits.max_bytes) + " allowed (" + limits.source + ")");
  std::string error;
  if (!load_texture_file(t.source, &t, &error))
    ctx.fail(file_node.path, "texture \"" + name + "\": cannot load \"" + t.source + "\": " + error);
  return t;
}

// ---- lights ----------------------------------------------------------------------------------

// Returns false for a degenerate area light (a quad whose edges span no area, a disk or sphere
// of radius 0), which is dropped with a warning: exporters write such lights (a lamp scaled
// to nothing, a placeholder), and one emits no power, so the image is the same without it.
// (Degenerate triangles are kept, silently: the watertight test never hits them, so they cost
// memory and nothing else; docs/scene-format.md.)
bool parse_light(LoadContext& ctx, const Node& n, LightDesc* l) {
  expect_object_any_keys(ctx, n);
  const Node type_node = require(ctx, n, "type");
  const std::string type = read_string(ctx, type_node);
  l->type = read_enum<LightDesc::Type>(ctx, type_node,
                                       {{"point", LightDesc::Type::Point},
                                        {"quad", LightDesc::Type::Quad},
                                        {"disk", LightDesc::Type::Disk},
                                        {"sphere", LightDesc::Type::Sphere},
                                        {"sun", LightDesc::Type::Sun}});
  switch (l->type) {
    case LightDesc::Type::Point:
      expect_object(ctx, n, {"type", "position", "color", "intensity"});
      break;
    case LightDesc::Type::Quad:
      expect_object(
          ctx, n,
          {"type", "corner", "edge_u", "edge_v", "color", "intensity", "two_sided", "visible"});
      break;
    case LightDesc::Type::Disk:
      expect_object(
          ctx, n,
          {"type", "center", "normal", "radius", "color", "intensity", "two_sided", "visible"});
      break;
    case LightDesc::Type::Sphere:
      expect_object(ctx, n, {"type", "center", "radius", "color", "intensity", "visible"});
      break;
    case LightDesc::Type::Sun:
      expect_object(ctx, n, {"type", "direction", "angle", "color", "intensity", "visible"});
      break;
  }
  if_present(n, "direction", [&](const Node& c) {
    const glm::dvec3 v = read_vec3(ctx, c);
    if (!(glm::length(v) > 0)) ctx.fail(c.path, "must not be the zero vector");
    l->direction = to_f(glm::normalize(v));
  });
  // The angular diameter: 0 is a hard (delta) sun, 180 a whole hemisphere of sky.
  if_present(n, "angle", [&](const Node& c) { l->angle = static_cast<float>(read_number_in(ctx, c, Range{0, 180})); });
  if_present(n, "color", [&](const Node& c) { l->color = read_colour_nonnegative(ctx, c); });
  if_present(n, "intensity", [&](const Node& c) {
    l->intensity = static_cast<float>(read_number_in(ctx, c, Range{0, kInf}));
  });
  if_present(n, "position", [&](const Node& c) { l->position = to_f(read_vec3(ctx, c)); });
  if_present(n, "center", [&](const Node& c) { l->center = to_f(read_vec3(ctx, c)); });
  if_present(n, "radius", [&](const Node& c) {
    l->radius = static_cast<float>(read_number_in(ctx, c, Range{0, kInf}));
  });
  if_present(n, "normal", [&](const Node& c) {
    const glm::dvec3 v = read_vec3(ctx, c);
    if (!(glm::length(v) > 0)) ctx.fail(c.path, "must not be the zero vector");
    l->normal = to_f(glm::normalize(v));
  });
  if_present(n, "corner", [&](const Node& c) { l->corner = to_f(read_vec3(ctx, c)); });
  if_present(n, "edge_u", [&](const Node& c) { l->edge_u = to_f(read_vec3(ctx, c)); });
  if_present(n, "edge_v", [&](const Node& c) { l->edge_v = to_f(read_vec3(ctx, c)); });
  if_present(n, "two_sided", [&](const Node& c) { l->two_sided = read_bool(ctx, c); });
  if_present(n, "visible", [&](const Node& c) { l->visible = read_bool(ctx, c); });
  if (l->type == LightDesc::Type::Quad &&
      !(glm::length(glm::cross(glm::dvec3(l->edge_u), glm::dvec3(l->edge_v))) > 0)) {
    ctx.warn(has(n, "edge_v") ? join_key(n.path, "edge_v") : n.path,
             "quad light with zero area (edge_u and edge_v are zero or parallel): it emits nothing and is dropped");
    return false;
  }
  if ((l->type == LightDesc::Type::Disk || l->type == LightDesc::Type::Sphere) && !(l->radius > 0.0f)) {
    ctx.warn(join_key(n.path, "radius"), std::string(l->type == LightDesc::Type::Disk ? "disk" : "sphere") +
                                             " light of radius 0: it emits nothing and is dropped");
    return false;
  }
  return true;
}

// ---- objects ---------------------------------------------------------------------------------

glm::dmat4 parse_transform(const LoadContext& ctx, const Node& n) {
  expect_object(ctx, n, {"translate", "rotate", "scale", "matrix"});
  glm::dmat4 m(1.0);
  if (Node mat = child(n, "matrix"); mat.j) {
    for (const char* k : {"translate", "rotate", "scale"}) {
      if (has(n, k)) {
        ctx.fail(
            join_key(n.path, k),
            "cannot be combined with \"matrix\" (use either matrix or translate/rotate/scale)");
      }
    }
    if (!mat.j->is_array()) {
      ctx.fail(mat.path,
               "expected an array of 16 numbers (a row-major 4x4 matrix), got " + describe(*mat.j));
    }
    if (mat.j->size() != 16) {
      ctx.fail(mat.path, "expected 16 numbers (a row-major 4x4 matrix), got " +
                             std::to_string(mat.j->size()));
    }
    double a[16];
    for (size_t i = 0; i < 16; ++i) a[i] = read_number(ctx, element(mat, i));
    // Projective matrices would bend the meaning of "position"; the last row must be
    // [0, 0, 0, 1] (a tolerance forgives exporters' round-off).
    if (std::fabs(a[12]) > 1e-9 || std::fabs(a[13]) > 1e-9 || std::fabs(a[14]) > 1e-9 ||
        std::fabs(a[15] - 1.0) > 1e-9) {
      ctx.fail(mat.path,
               "the last row must be [0, 0, 0, 1] (only affine transforms are supported)");
    }
    for (int row = 0; row < 3; ++row) {
      for (int col = 0; col < 4; ++col) m[col][row] = a[4 * row + col];  // glm: column-major
    }
  } else {
    glm::dvec3 translate(0.0), rotate(0.0), scale(1.0);
    if_present(n, "translate", [&](const Node& c) { translate = read_vec3(ctx, c); });
    if_present(n, "rotate", [&](const Node& c) { rotate = read_vec3(ctx, c); });
    if_present(n, "scale", [&](const Node& c) {
      if (c.j->is_number()) {
        scale = glm::dvec3(read_number(ctx, c));
      } else if (c.j->is_array() && c.j->size() == 3) {
        scale = read_vec3(ctx, c);
      } else {
        ctx.fail(c.path, "expected a number or an array of 3 numbers, got " + describe(*c.j));
      }
    });
    glm::dmat4 t(1.0), s(1.0);
    t[3] = glm::dvec4(translate, 1.0);
    s[0][0] = scale.x;
    s[1][1] = scale.y;
    s[2][2] = scale.z;
    m = t * rotation_xyz_degrees(rotate) * s;  // scale, then rotate, then translate
  }
  bool finite = true;
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) finite = finite && std::isfinite(m[c][r]);
  }
  if (!finite || !std::isfinite(glm::determinant(glm::dmat3(m)))) {
    ctx.fail(n.path, "the transform overflows (its values are too large to represent)");
  }
  if (is_singular(m)) {
    ctx.fail(n.path, "the transform is singular (it flattens the object; check scale and matrix)");
  }
  return m;
}

// The materials a glTF file brought, per file as resolved: the scene's index of each of the
// file's materials, then of its default material (for primitives that name none), so a file
// referenced by several objects adds its materials once.
using GltfMaterials = std::map<std::string, std::vector<uint32_t>>;

// Adds a glTF file's materials and textures to the scene (names "FILE#material"); returns the
// scene's material index of each, the default material last.
std::vector<uint32_t> add_gltf_materials(const std::string& file, GltfImport& g,
                                         std::map<std::string, uint32_t>& material_index, Scene& scene) {
  const uint32_t texture_base = uint32_t(scene.textures.size());
  for (TextureDesc& t : g.textures) {
    t.name = file + "#" + t.name;
    scene.textures.push_back(std::move(t));
  }
  std::vector<uint32_t> ids;
  auto add = [&](std::string name, MaterialDesc m) {
    // A name already taken (two glTF materials of one name, or the scene's own) gets a suffix.
    for (int k = 2; material_index.count(name); ++k) name = name.substr(0, name.rfind(" (")) + " (" + std::to_string(k) + ")";
    material_index[name] = uint32_t(scene.materials.size());
    ids.push_back(uint32_t(scene.materials.size()));
    scene.material_names.push_back(name);
    scene.materials.push_back(std::move(m));
  };
  for (size_t i = 0; i < g.materials.size(); ++i) {
    MaterialDesc m = g.materials[i];
    for (auto& [key, ref] : g.bindings[i]) {
      TextureRef r = ref;
      r.texture += texture_base;
      m.textures[key] = r;
    }
    add(file + "#" + g.material_names[i], std::move(m));
  }
  add(file + "#default", MaterialDesc{});
  return ids;
}

// How parse_object reads a mesh that instancing shares (docs/scene-format.md#instancing).
struct MeshOptions {
  // A "meshes" entry: the shape is a mesh without saying so; keys file, material, transform;
  // named `definition` in messages.
  std::string definition;
  // The parts in the mesh file's own space: the transform is the instances' (read by the caller).
  bool object_space = false;
  // The material for every part instead of the node's own "material" (an instance's).
  const Node* material = nullptr;
};

std::vector<TriangleMesh> parse_object(LoadContext& ctx, const Node& n, size_t index,
                                       std::map<std::string, uint32_t>& material_index, Scene& scene,
                                       GltfMaterials& gltf_materials, const MeshOptions& opts = {}) {
  const std::vector<std::string>& material_names = scene.material_names;
  expect_object_any_keys(ctx, n);
  enum class Shape { Mesh, Sphere, Quad, Disk, Box };
  const bool definition = !opts.definition.empty();
  const Node shape_node = definition ? Node{nullptr, ""} : require(ctx, n, "shape");
  const Shape shape = definition ? Shape::Mesh
                                 : read_enum<Shape>(ctx, shape_node,
                                                    {{"mesh", Shape::Mesh},
                                                     {"sphere", Shape::Sphere},
                                                     {"quad", Shape::Quad},
                                                     {"disk", Shape::Disk},
                                                     {"box", Shape::Box}});
  const std::vector<std::string> common = definition ? std::vector<std::string>{"material", "transform"}
                                                     : std::vector<std::string>{"shape", "material", "transform",
                                                                                "light_sampling"};
  auto keys = [&](std::initializer_list<const char*> extra) {
    std::vector<std::string> all = common;
    for (const char* k : extra) all.push_back(k);
    return all;
  };
  const std::string shape_name = definition ? "mesh" : shape_node.j->get<std::string>();
  std::string name = definition ? opts.definition + " (mesh" : "objects[" + std::to_string(index) + "] (" + shape_name;
  const bool has_material = opts.material || has(n, "material");
  const Node material_node = opts.material ? *opts.material : has_material ? child(n, "material") : Node{nullptr, ""};

  DMesh mesh;
  bool analytic_sphere = false;  // a sphere that may stay one primitive (decided below)
  glm::dvec3 sphere_center(0.0);
  double sphere_radius = 1.0;
  GltfImport gltf;          // a glTF file, or an OBJ with its .mtl: its primitives instead of `mesh`
  std::string gltf_file;    // as resolved
  // Where geometry problems are reported: the "file" key for meshes (the data came from
  // there), the object itself for built-in shapes.
  std::string geometry_path = n.path;
  switch (shape) {
    case Shape::Mesh: {
      expect_object(ctx, n, keys({"file"}));
      const Node file_node = require(ctx, n, "file");
      const std::string file = read_string(ctx, file_node);
      if (file.empty()) ctx.fail(file_node.path, "must not be empty");
      name += " " + file;
      geometry_path = file_node.path;
      const std::string resolved = resolve_relative(ctx.file(), file);
      std::string ext = std::filesystem::path(file).extension().string();
      for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
      std::string error;
      if (ext == ".gltf" || ext == ".glb") {
        std::vector<std::string> gltf_warnings;
        if (!load_gltf(resolved, &gltf, &error, &gltf_warnings))
          ctx.fail(file_node.path, "cannot load glTF \"" + resolved + "\": " + error);
        for (const std::string& w : gltf_warnings) ctx.warn(file_node.path, "glTF \"" + resolved + "\": " + w);
        if (gltf.primitives.empty()) ctx.fail(file_node.path, "glTF \"" + resolved + "\" has no triangles");
        gltf_file = resolved;
        break;
      }
      // An OBJ without a "material" key takes its .mtl materials (docs/obj-mtl.md), through
      // the same path as a glTF file's.
      if (!has_material) {
        std::vector<std::string> obj_warnings;
        if (!load_obj_with_materials(resolved, &gltf, &error, &obj_warnings))
          ctx.fail(file_node.path, "cannot load mesh \"" + resolved + "\": " + error);
        for (const std::string& w : obj_warnings) ctx.warn(file_node.path, "mesh \"" + resolved + "\": " + w);
        if (gltf.primitives.empty()) ctx.fail(file_node.path, "mesh \"" + resolved + "\" has no triangles");
        gltf_file = resolved;
        break;
      }
      std::vector<std::string> obj_warnings;
      if (!load_obj(resolved, &mesh, &error, &obj_warnings)) {
        ctx.fail(file_node.path, "cannot load mesh \"" + resolved + "\": " + error);
      }
      for (const std::string& w : obj_warnings) {
        ctx.warn(file_node.path, "mesh \"" + resolved + "\": " + w);
      }
      if (mesh.indices.empty()) {
        ctx.fail(file_node.path, "mesh \"" + resolved + "\" has no triangles");
      }
      break;
    }
    case Shape::Sphere: {
      expect_object(ctx, n, keys({"center", "radius", "segments"}));
      glm::dvec3 center(0.0);
      double radius = 1.0;
      int su = kSphereSegmentsU, sv = kSphereSegmentsV;
      if_present(n, "center", [&](const Node& c) { center = read_vec3(ctx, c); });
      if_present(n, "radius", [&](const Node& c) {
        radius = read_number_in(ctx, c, Range{0, kInf, true});
      });
      if_present(n, "segments", [&](const Node& c) {
        if (!c.j->is_array() || c.j->size() != 2) {
          ctx.fail(c.path, "expected [around, rings] (2 integers), got " + describe(*c.j));
        }
        su = read_int_in(ctx, element(c, 0), 3, 4096);
        sv = read_int_in(ctx, element(c, 1), 2, 4096);
      });
      // Analytic unless "segments" asks for a tessellation (or, below, the transform or
      // light sampling need one).
      if (has(n, "segments")) mesh = make_sphere(center, radius, su, sv);
      else sphere_center = center, sphere_radius = radius, analytic_sphere = true;
      break;
    }
    case Shape::Quad: {
      expect_object(ctx, n, keys({"corner", "edge_u", "edge_v"}));
      glm::dvec3 corner(0.0), eu(1, 0, 0), ev(0, 0, 1);
      if_present(n, "corner", [&](const Node& c) { corner = read_vec3(ctx, c); });
      if_present(n, "edge_u", [&](const Node& c) { eu = read_vec3(ctx, c); });
      if_present(n, "edge_v", [&](const Node& c) { ev = read_vec3(ctx, c); });
      if (!(glm::length(glm::cross(eu, ev)) > 0)) {
        ctx.fail(has(n, "edge_v") ? join_key(n.path, "edge_v") : n.path,
                 "edge_u and edge_v must span a non-zero area (they are zero or parallel)");
      }
      mesh = make_quad(corner, eu, ev);
      break;
    }
    case Shape::Disk: {
      expect_object(ctx, n, keys({"center", "normal", "radius", "segments"}));
      glm::dvec3 center(0.0), normal(0, 1, 0);
      double radius = 1.0;
      int segments = kDiskSegments;
      if_present(n, "center", [&](const Node& c) { center = read_vec3(ctx, c); });
      if_present(n, "normal", [&](const Node& c) {
        normal = read_vec3(ctx, c);
        if (!(glm::length(normal) > 0)) ctx.fail(c.path, "must not be the zero vector");
      });
      if_present(n, "radius", [&](const Node& c) {
        radius = read_number_in(ctx, c, Range{0, kInf, true});
      });
      if_present(n, "segments", [&](const Node& c) { segments = read_int_in(ctx, c, 3, 65536); });
      mesh = make_disk(center, normal, radius, segments);
      break;
    }
    case Shape::Box: {
      expect_object(ctx, n, keys({"min", "max"}));
      glm::dvec3 lo(-0.5), hi(0.5);
      if_present(n, "min", [&](const Node& c) { lo = read_vec3(ctx, c); });
      if_present(n, "max", [&](const Node& c) { hi = read_vec3(ctx, c); });
      if (hi.x < lo.x || hi.y < lo.y || hi.z < lo.z) {
        ctx.fail(has(n, "max") ? join_key(n.path, "max") : n.path,
                 "box max must be >= min in every component");
      }
      mesh = make_box(lo, hi);
      break;
    }
  }
  name += ")";

  glm::dmat4 transform(1.0);
  if (!opts.object_space) if_present(n, "transform", [&](const Node& c) { transform = parse_transform(ctx, c); });
  bool light_sampling = false;
  if_present(n, "light_sampling", [&](const Node& c) { light_sampling = read_bool(ctx, c); });

  // A glTF file (or an OBJ read with its .mtl): one mesh per primitive, with the file's
  // materials unless "material" names one for all of them (docs/gltf.md, docs/obj-mtl.md).
  if (!gltf_file.empty()) {
    std::vector<uint32_t> ids;
    uint32_t forced = AW_NONE;
    if (has_material) {
      const Node mat_node = material_node;
      const std::string material = read_string(ctx, mat_node);
      const auto found = material_index.find(material);
      if (found == material_index.end()) {
        const std::string hint = closest(material, material_names);
        ctx.fail(mat_node.path, name + " uses unknown material \"" + material + "\"" +
                                    (hint.empty() ? std::string() : " (did you mean \"" + hint + "\"?)"));
      }
      forced = found->second;
    } else {
      auto it = gltf_materials.find(gltf_file);
      if (it == gltf_materials.end())
        it = gltf_materials.emplace(gltf_file, add_gltf_materials(gltf_file, gltf, material_index, scene)).first;
      ids = it->second;
    }
    std::vector<TriangleMesh> meshes;
    for (GltfPrimitive& prim : gltf.primitives) {
      TriangleMesh out;
      if (!finalize_mesh(prim.mesh, transform, &out))
        ctx.fail(geometry_path, name + ", " + prim.name + ": a vertex coordinate or normal is NaN or infinite after the transform");
      out.material = forced != AW_NONE ? forced
                     : prim.material >= 0 && size_t(prim.material) + 1 < ids.size() ? ids[size_t(prim.material)]
                                                                                     : ids.back();
      out.name = name + ", " + prim.name;
      out.light_sampling = light_sampling;
      meshes.push_back(std::move(out));
    }
    return meshes;
  }

  // The material is checked after the shape so that the message can name the object fully.
  const Node mat_node = has_material ? material_node : require(ctx, n, "material");
  const std::string material = read_string(ctx, mat_node);
  const auto found = material_index.find(material);
  if (found == material_index.end()) {
    std::string message = name + " uses unknown material \"" + material + "\"";
    if (material_names.empty()) {
      message += " (the scene defines no materials)";
    } else {
      const std::string suggestion = closest(material, material_names);
      if (!suggestion.empty()) {
        message += " (did you mean \"" + suggestion + "\"?)";
      } else {
        std::string list;
        for (const std::string& m : material_names) list += (list.empty() ? "" : ", ") + m;
        message += "; defined materials: " + list;
      }
    }
    ctx.fail(mat_node.path, message);
  }

  // A sphere stays analytic under a similarity (rotation, uniform scale, translation: it is
  // still a sphere) without light sampling (which samples triangles); otherwise it is
  // tessellated as before (docs/scene-format.md#sphere).
  if (analytic_sphere) {
    const glm::dmat3 L(transform);
    const double s2 = glm::dot(L[0], L[0]);
    bool similarity = glm::determinant(L) > 0.0;
    for (int a = 0; a < 3 && similarity; ++a)
      for (int b = 0; b < 3; ++b)
        if (std::fabs(glm::dot(L[a], L[b]) - (a == b ? s2 : 0.0)) > 1e-9 * s2) similarity = false;
    if (similarity && !light_sampling) {
      SphereDesc sd;
      const glm::dvec3 c = glm::dvec3(transform * glm::dvec4(sphere_center, 1.0));
      const double r = sphere_radius * std::sqrt(s2);
      sd.center = glm::vec3(c);
      sd.radius = float(r);
      sd.axis_x = glm::vec3(glm::normalize(L[0]));
      sd.axis_y = glm::vec3(glm::normalize(L[1]));
      if (!(std::isfinite(r) && r > 0.0 && std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z)) ||
          !(sd.radius > 0.0f) || !std::isfinite(sd.radius))
        ctx.fail(geometry_path, name + " has a centre or radius that is not a finite positive number after the transform");
      sd.material = found->second;
      sd.name = name;
      scene.spheres.push_back(sd);
      return {};
    }
    mesh = make_sphere(sphere_center, sphere_radius, kSphereSegmentsU, kSphereSegmentsV);
  }

  TriangleMesh out;
  if (!finalize_mesh(mesh, transform, &out)) {
    ctx.fail(geometry_path, name + " has a vertex coordinate or normal that is NaN or infinite");
  }
  out.material = found->second;
  out.name = name;
  out.light_sampling = light_sampling;
  return {std::move(out)};
}

std::string read_text_file(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw SceneError(path + ": cannot read scene file: is a directory");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in.is_open()) {
    throw SceneError(path + ": cannot open scene file: " + std::strerror(errno));
  }
  std::ostringstream s;
  s << in.rdbuf();
  if (in.bad()) throw SceneError(path + ": cannot read scene file");
  return s.str();
}

// Triangles a built-in shape will be tessellated into, read before it is (the shape's own
// parse validates the keys; here an unreadable value counts as the default); 0 for meshes,
// which are counted once read.
uint64_t builtin_triangles(const Node& n) {
  auto count = [&](const char* key, size_t i, int64_t def) -> int64_t {
    const Json* j = n.j->contains(key) ? &(*n.j)[key] : nullptr;
    if (j && j->is_array() && j->size() > i) j = &(*j)[i];
    return j && j->is_number_integer() && j->get<int64_t>() > 0 ? j->get<int64_t>() : def;
  };
  if (!n.j->is_object() || !n.j->contains("shape") || !(*n.j)["shape"].is_string()) return 0;
  const std::string shape = (*n.j)["shape"].get<std::string>();
  // An analytic sphere counts as one primitive (about as much memory as a triangle); with
  // "segments" or light sampling it is tessellated.
  if (shape == "sphere" && !n.j->contains("segments") && !n.j->contains("light_sampling")) return 1;
  if (shape == "sphere")
    return sphere_triangle_count(count("segments", 0, kSphereSegmentsU), count("segments", 1, kSphereSegmentsV));
  if (shape == "disk") return disk_triangle_count(count("segments", 0, kDiskSegments));
  if (shape == "box") return 12;
  if (shape == "quad") return 2;
  return 0;
}

// The memory check of LoadLimits: the film and path pool (`fixed`) and `triangles` (all so
// far, this object's included) against the limit, failing at `at`.
void check_memory(const LoadContext& ctx, const std::string& at, const LoadLimits& limits, uint64_t fixed,
                  uint64_t triangles) {
  const uint64_t need = fixed + triangles * kRenderBytesPerTriangle;
  if (limits.max_bytes == 0 || need <= limits.max_bytes) return;
  ctx.fail(at, "the scene reaches " + std::to_string(triangles) + " triangles here; with its film and path pool (" +
                   mib(fixed) + ") it takes about " + mib(need) + " to render (" +
                   std::to_string(kRenderBytesPerTriangle) + " B per triangle), more than the " + mib(limits.max_bytes) +
                   " allowed (" + limits.source + "); nothing was allocated for it. --max-memory SIZE sets the limit");
}

Scene load(const std::string& path, const std::vector<std::string>& overrides, const LoadLimits& limits) {
  const std::string text = read_text_file(path);
  LocatedJson doc;
  JsonSyntaxError syntax;
  if (!parse_located_json(text, &doc, &syntax)) {
    const TextPos pos = LineMap(&text).at(syntax.offset);
    throw SceneError(path + ":" + std::to_string(pos.line) + ":" + std::to_string(pos.col) + ": " +
                     syntax.message);
  }

  LoadContext ctx(path, &text, &doc);
  if (!doc.root.is_object()) {
    ctx.fail("", "the scene must be a JSON object, got " + describe(doc.root));
  }
  apply_overrides(ctx, doc.root, overrides);

  Scene scene;
  scene.path = path;
  const Node root{&doc.root, ""};
  expect_object(ctx, root,
                {"render", "camera", "environment", "lights", "textures", "materials", "meshes", "objects"});

  if_present(root, "render", [&](const Node& c) { parse_render(ctx, c, &scene.render); });
  if_present(root, "camera", [&](const Node& c) { parse_camera(ctx, c, &scene.camera); });
  if_present(root, "environment",
             [&](const Node& c) { parse_environment(ctx, c, &scene.environment); });
  if_present(root, "lights", [&](const Node& c) {
    expect_array(ctx, c);
    for (size_t i = 0; i < c.j->size(); ++i) {
      LightDesc l;
      if (parse_light(ctx, element(c, i), &l)) scene.lights.push_back(l);
    }
  });
  if (scene.environment.type == EnvironmentDesc::Type::Sky &&
      std::none_of(scene.lights.begin(), scene.lights.end(),
                   [](const LightDesc& l) { return l.type == LightDesc::Type::Sun; })) {
    ctx.fail("environment.type", "a \"sky\" environment is lit by the first sun light, and the scene has none "
                                 "(add {\"type\": \"sun\", \"direction\": [...]} to lights)");
  }
  std::map<std::string, uint32_t> texture_index;
  uint64_t texture_bytes = 0;  // decoded texels held on the host (4 floats each), for the memory check
  if_present(root, "textures", [&](const Node& c) {
    expect_object_any_keys(ctx, c);
    for (const auto& item : c.j->items()) {
      const Node tn = child(c, item.key());
      if (item.key().empty()) ctx.fail(tn.path, "texture names must not be empty");
      LoadLimits left = limits;
      if (left.max_bytes > 0) left.max_bytes = left.max_bytes > texture_bytes ? left.max_bytes - texture_bytes : 1;
      texture_index[item.key()] = static_cast<uint32_t>(scene.textures.size());
      scene.textures.push_back(parse_texture(ctx, tn, item.key(), left));
      texture_bytes += uint64_t(scene.textures.back().texels.size()) * sizeof(float);
      // Decoded, the texels (and the device's copy with its mip levels) must fit as well.
      if (limits.max_bytes > 0 && texture_bytes * 3 / 2 > limits.max_bytes)
        ctx.fail(tn.path, "the textures so far take " + mib(texture_bytes) + " decoded (plus their mip levels), more than the " +
                              mib(limits.max_bytes) + " allowed (" + limits.source + "); --max-memory SIZE sets the limit");
    }
  });
  ctx.set_textures(&texture_index);

  std::map<std::string, uint32_t> material_index;
  if_present(root, "materials", [&](const Node& c) {
    expect_object_any_keys(ctx, c);
    for (const auto& item : c.j->items()) {
      const Node m = child(c, item.key());
      if (item.key().empty()) ctx.fail(m.path, "material names must not be empty");
      material_index[item.key()] = static_cast<uint32_t>(scene.materials.size());
      scene.material_names.push_back(item.key());
      scene.materials.push_back(parse_material(ctx, m, item.key()));
    }
  });

  // Film (per pixel: the device's exact sums and count, 52 B, the host's copy of both with
  // their float sums, 64 B, and the image written: 128 B in all; kernels/integrator/film.h) and
  // the path pool (256 Ki states of about 230 B), before any geometry.
  uint64_t triangles = 0;
  uint64_t fixed_bytes = uint64_t(scene.render.width) * uint64_t(scene.render.height) * 128u + (uint64_t(64) << 20);
  // Textures: their decoded texels (and half again for the device's packed copy with its mip
  // levels), and with textured materials a material per path state (256 Ki states at most,
  // kernels/integrator/shading_material.h).
  fixed_bytes += texture_bytes * 3 / 2;
  if (std::any_of(scene.materials.begin(), scene.materials.end(), [](const MaterialDesc& m) { return !m.textures.empty(); }))
    fixed_bytes += uint64_t(262144) * sizeof(MaterialGpu);
  check_memory(ctx, "render", limits, fixed_bytes, 0);
  GltfMaterials gltf_materials;
  // Instancing (docs/scene-format.md#instancing). The "meshes" section names meshes that
  // "instance" objects place; mesh objects that differ only in their transform share one
  // prototype too. Prototypes are loaded on first use, in the file's own space.
  std::map<std::string, Node> mesh_defs;
  std::map<std::string, bool> mesh_def_used;
  if_present(root, "meshes", [&](const Node& c) {
    expect_object_any_keys(ctx, c);
    for (const auto& item : c.j->items()) {
      const Node d = child(c, item.key());
      if (item.key().empty()) ctx.fail(d.path, "mesh names must not be empty");
      expect_object(ctx, d, {"file", "material", "transform"});
      require(ctx, d, "file");
      mesh_defs.emplace(item.key(), d);
      mesh_def_used[item.key()] = false;
    }
  });
  std::map<std::string, size_t> share_count;  // mesh objects by everything but their transform
  auto share_key = [](const Json& j) -> std::string {
    if (!j.is_object() || !j.contains("shape") || j["shape"] != "mesh") return std::string();
    if (j.contains("light_sampling") && j["light_sampling"] == true) return std::string();  // lights stay apart
    nlohmann::json sorted = nlohmann::json::parse(j.dump());  // key order does not matter
    sorted.erase("transform");
    return sorted.dump();
  };
  if (const Node objs = child(root, "objects"); objs.j && objs.j->is_array())
    for (const Json& j : *objs.j)
      if (std::string k = share_key(j); !k.empty()) ++share_count[k];
  std::map<std::string, uint32_t> prototype_of;  // share key or "meshes" name + material
  std::vector<std::pair<glm::dvec3, glm::dvec3>> prototype_box;  // object-space bounds
  // Places prototype `key` (loading it with `load` the first time) with `transform`.
  auto place = [&](const std::string& key, const std::string& proto_name, const std::string& inst_name,
                   const glm::dmat4& transform, const std::string& at, const std::function<std::vector<TriangleMesh>()>& load) {
    auto it = prototype_of.find(key);
    if (it == prototype_of.end()) {
      MeshPrototype p;
      p.name = proto_name;
      p.parts = load();
      glm::dvec3 lo(kInf), hi(-kInf);
      for (const TriangleMesh& m : p.parts)
        for (const glm::vec3& q : m.positions) {
          lo = glm::min(lo, glm::dvec3(q));
          hi = glm::max(hi, glm::dvec3(q));
        }
      triangles += p.triangle_count();
      it = prototype_of.emplace(key, uint32_t(scene.prototypes.size())).first;
      scene.prototypes.push_back(std::move(p));
      prototype_box.emplace_back(lo, hi);
    }
    // The placed mesh must stay finite (the loader's check on every flattened vertex).
    const auto& [lo, hi] = prototype_box[it->second];
    for (int k = 0; k < 8; ++k) {
      const glm::dvec3 q(transform * glm::dvec4((k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z, 1.0));
      const glm::vec3 f(q);
      if (!std::isfinite(f.x) || !std::isfinite(f.y) || !std::isfinite(f.z))
        ctx.fail(at, inst_name + " places its mesh outside the range of single precision (a coordinate is infinite after the transform)");
    }
    MeshInstance mi;
    mi.prototype = it->second;
    mi.transform = transform;
    mi.name = inst_name;
    scene.instances.push_back(std::move(mi));
    triangles += 1;  // an instance's memory: about one triangle's (InstanceGpu and its BVH share)
  };
  if_present(root, "objects", [&](const Node& c) {
    expect_array(ctx, c);
    for (size_t i = 0; i < c.j->size(); ++i) {
      const Node obj = element(c, i);
      check_memory(ctx, obj.path, limits, fixed_bytes, triangles + builtin_triangles(obj));
      // An explicit instance of a "meshes" entry.
      if (obj.j->is_object() && obj.j->contains("shape") && (*obj.j)["shape"] == "instance") {
        expect_object(ctx, obj, {"shape", "mesh", "transform", "material"});
        const Node mesh_node = require(ctx, obj, "mesh");
        const std::string mesh = read_string(ctx, mesh_node);
        const auto def = mesh_defs.find(mesh);
        if (def == mesh_defs.end()) {
          std::vector<std::string> names;
          for (const auto& d : mesh_defs) names.push_back(d.first);
          const std::string hint = closest(mesh, names);
          ctx.fail(mesh_node.path, "objects[" + std::to_string(i) + "] (instance) places unknown mesh \"" + mesh + "\"" +
                                       (names.empty() ? std::string(" (the scene has no \"meshes\" section)")
                                        : hint.empty() ? std::string()
                                                       : " (did you mean \"" + hint + "\"?)"));
        }
        mesh_def_used[mesh] = true;
        glm::dmat4 transform(1.0), def_transform(1.0);
        if_present(obj, "transform", [&](const Node& t) { transform = parse_transform(ctx, t); });
        if_present(def->second, "transform", [&](const Node& t) { def_transform = parse_transform(ctx, t); });
        const Node mat = child(obj, "material");
        const std::string mat_name = mat.j ? read_string(ctx, mat) : std::string();
        const std::string label = "meshes." + mesh + (mat.j ? " with material \"" + mat_name + "\"" : std::string());
        place("meshes\n" + mesh + "\n" + mat_name, label,
              "objects[" + std::to_string(i) + "] (instance of " + label + ")", transform * def_transform,
              has(obj, "transform") ? join_key(obj.path, "transform") : obj.path,
              [&] {
                MeshOptions o;
                o.definition = "meshes." + mesh;
                o.object_space = true;
                o.material = mat.j ? &mat : nullptr;
                return parse_object(ctx, def->second, i, material_index, scene, gltf_materials, o);
              });
        check_memory(ctx, obj.path, limits, fixed_bytes, triangles);
        continue;
      }
      // A mesh object that others repeat with another transform: shared.
      if (const std::string key = share_key(*obj.j); !key.empty() && share_count[key] >= 2) {
        glm::dmat4 transform(1.0);
        if_present(obj, "transform", [&](const Node& t) { transform = parse_transform(ctx, t); });
        const std::string file = (*obj.j).contains("file") && (*obj.j)["file"].is_string() ? (*obj.j)["file"].get<std::string>() : "";
        const std::string oname = "objects[" + std::to_string(i) + "] (mesh " + file + ")";
        place(key, oname, oname, transform, has(obj, "transform") ? join_key(obj.path, "transform") : obj.path, [&] {
          MeshOptions o;
          o.object_space = true;
          return parse_object(ctx, obj, i, material_index, scene, gltf_materials, o);
        });
        check_memory(ctx, obj.path, limits, fixed_bytes, triangles);
        continue;
      }
      const size_t first = scene.meshes.size(), first_sphere = scene.spheres.size();
      for (TriangleMesh& m : parse_object(ctx, obj, i, material_index, scene, gltf_materials)) {
        triangles += m.indices.size();
        scene.meshes.push_back(std::move(m));
      }
      triangles += scene.spheres.size() - first_sphere;  // a primitive each
      check_memory(ctx, obj.path, limits, fixed_bytes, triangles);
      if (scene.meshes.size() == first) continue;  // an analytic sphere
      // Light sampling: of the object's emitting parts (a glTF file's primitives whose material
      // emits nothing stay plain geometry); an object with none is an error.
      size_t emitting = 0;
      const bool asked = scene.meshes[first].light_sampling;
      for (size_t k = first; k < scene.meshes.size(); ++k) {
        TriangleMesh& m = scene.meshes[k];
        if (!m.light_sampling) continue;
        const MaterialDesc& md = scene.materials[m.material];
        const glm::vec3 inc = md.incandescent.color * md.incandescent.scale;
        // Light sampling picks triangles by their (constant) power and evaluates the emission
        // where the sample lands; a textured emission would need both to follow the texture.
        if (md.textures.count("incandescent.color"))
          ctx.fail(join_key(obj.path, "light_sampling"),
                   m.name + ": light sampling of a textured incandescent colour is not supported (material \"" +
                       scene.material_names[m.material] + "\"); remove light_sampling, and BSDF sampling finds it");
        if (inc.x > 0.0f || inc.y > 0.0f || inc.z > 0.0f) ++emitting;
        else if (scene.meshes.size() - first > 1) m.light_sampling = false;
      }
      const TriangleMesh& m = scene.meshes[first];
      if (asked && emitting == 0)
        ctx.fail(join_key(obj.path, "light_sampling"),
                 m.name + ": light sampling needs an incandescent material, and \"" + scene.material_names[m.material] +
                     "\" emits nothing");
    }
  });

  // A material that reads UV set 1 on a mesh with one set reads set 0 there: said once per mesh.
  {
    auto reads_set1 = [&](uint32_t material) {
      const MaterialDesc& md = scene.materials[material];
      if (md.anisotropy.uv_set == 1) return true;
      for (const auto& kv : md.textures)
        if (kv.second.uv_set == 1) return true;
      return false;
    };
    auto check = [&](const TriangleMesh& m) {
      if (m.uvs2.empty() && m.material < scene.materials.size() && reads_set1(m.material))
        ctx.warn("objects", m.name + ": material \"" + scene.material_names[m.material] +
                                "\" reads UV set 1, which this mesh does not have; it reads set 0 there");
    };
    for (const TriangleMesh& m : scene.meshes) check(m);
    for (const SphereDesc& sd : scene.spheres)
      if (reads_set1(sd.material))
        ctx.warn("objects", sd.name + ": material \"" + scene.material_names[sd.material] +
                                "\" reads UV set 1; a sphere has one UV set, which it reads there");
    for (const MeshPrototype& p : scene.prototypes)
      for (const TriangleMesh& m : p.parts) check(m);
  }
  // render.instancing false: every placement becomes a world mesh of its own (memory for
  // speed: one level of BVH; and the flattened equivalent the tests compare instancing with).
  if (!scene.render.instancing) {
    for (const MeshInstance& mi : scene.instances)
      for (const TriangleMesh& part : scene.prototypes[mi.prototype].parts) {
        TriangleMesh m = place_mesh(part, mi.transform);
        m.name = mi.name + (scene.prototypes[mi.prototype].parts.size() > 1 ? ", " + part.name : std::string());
        scene.meshes.push_back(std::move(m));
      }
    scene.instances.clear();
    scene.prototypes.clear();
  }
  for (const auto& [mesh, used] : mesh_def_used)
    if (!used) ctx.warn(mesh_defs.at(mesh).path, "mesh \"" + mesh + "\" is defined but no instance places it");

  scene.warnings = ctx.take_warnings();
  return scene;
}

}  // namespace
}  // namespace scene_detail

uint64_t available_memory_bytes() {
  std::ifstream f("/proc/meminfo");
  std::string key;
  uint64_t kb = 0;
  std::string unit;
  while (f >> key >> kb >> unit)
    if (key == "MemAvailable:") return kb * 1024;
  return 0;
}

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides, const LoadLimits& limits) {
  // SceneError is the only exception the rest of the renderer has to handle; anything a
  // library throws despite our checks becomes one too, still naming the file.
  try {
    return scene_detail::load(path, overrides, limits);
  } catch (const SceneError&) {
    throw;
  } catch (const std::exception& e) {
    throw SceneError(path + ": internal error while loading the scene: " + e.what());
  }
}

ExposureMap exposure_map(const CameraDesc& cam) {
  const ExposureDesc& e = cam.exposure;
  ExposureMap m;
  m.k = exposure_scale(e);
  if (e.mode == ExposureDesc::Mode::Photographic) {
    // White balance: the white point's colour becomes grey of the same luminance (a von Kries
    // scaling in the Rec.709 primaries), so balancing does not change the exposure.
    const glm::dvec3 wp(e.whitepoint);
    const double lum = 0.2126 * wp.x + 0.7152 * wp.y + 0.0722 * wp.z;
    m.wb[0] = lum / wp.x;
    m.wb[1] = lum / wp.y;
    m.wb[2] = lum / wp.z;
    m.vignetting = e.vignetting;
  }
  m.tan_half_fov = std::tan(0.5 * double(cam.fov) * M_PI / 180.0);
  return m;
}

std::string ExposureMap::to_string() const {
  char buf[256];
  std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g %.17g %.17g %.17g", k, wb[0], wb[1], wb[2], vignetting, tan_half_fov);
  return buf;
}

bool ExposureMap::parse(const std::string& s, ExposureMap* out) {
  ExposureMap m;
  char tail = 0;
  if (std::sscanf(s.c_str(), "%lf %lf %lf %lf %lf %lf %c", &m.k, &m.wb[0], &m.wb[1], &m.wb[2], &m.vignetting, &m.tan_half_fov,
                  &tail) != 6)
    return false;
  for (double v : {m.k, m.wb[0], m.wb[1], m.wb[2], m.vignetting, m.tan_half_fov})
    if (!std::isfinite(v) || v < 0.0) return false;
  *out = m;
  return true;
}

void ExposureMap::apply(int frame_w, int frame_h, int x0, int y0, int w, int h, float* rgb) const {
  const double aspect = double(frame_w) / double(frame_h);
  const double t = tan_half_fov;
  for (int y = y0; y < y0 + h; ++y) {
    for (int x = x0; x < x0 + w; ++x) {
      double f = k;
      if (vignetting > 0.0) {
        // Natural vignetting: the cos^4 law of a lens's off-axis illuminance (Kerr, "Derivation
        // of the cosine fourth law for falloff of illuminance across a camera image", 2007),
        // raised to `vignetting` (0: none, 1: the law itself), at the pixel centre's ray.
        const double u = (2.0 * (x + 0.5) / frame_w - 1.0) * t * aspect, v = (1.0 - 2.0 * (y + 0.5) / frame_h) * t;
        const double c2 = 1.0 / (1.0 + u * u + v * v);  // cos^2 of the angle to the axis
        f *= std::pow(c2 * c2, vignetting);
      }
      float* p = rgb + 3 * (size_t(y - y0) * size_t(w) + size_t(x - x0));
      for (int c = 0; c < 3; ++c) p[c] = float(double(p[c]) * f * wb[c]);
    }
  }
}

void apply_exposure(const CameraDesc& cam, int width, int height, float* rgb) {
  exposure_map(cam).apply(width, height, 0, 0, width, height, rgb);
}

float exposure_scale(const ExposureDesc& e) {
  if (e.mode == ExposureDesc::Mode::Stops) return static_cast<float>(std::exp2(double(e.stops)));
  // mental ray's photographic exposure: k = (1/shutter) * iso / (f_number^2 * 100), with
  // shutter given as 1/seconds.
  const double f = e.f_number;
  return static_cast<float>((1.0 / e.shutter) * e.iso / (f * f * 100.0));
}

}  // namespace aw
