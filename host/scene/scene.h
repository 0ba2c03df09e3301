// The loaded, validated scene: what the rest of the renderer consumes.
//
// host/scene turns a JSON file (docs/scene-format.md) into this
// structure. Everything here is already validated and defaulted; geometry is triangulated and
// transformed to world space. Nothing downstream re-reads the JSON.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "host/scene/material_desc.h"

namespace aw {

// A scene that could not be loaded. what() is the complete, user-facing message, already in
// the form "FILE:LINE:COL: json.path: message" (or "FILE: message" when there is no position).
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct RenderSettings {
  int width = 640;
  int height = 480;
  int spp = 64;
  uint32_t seed = 0;
  int max_depth = 8;
  int reflection_depth = 8;
  int refraction_depth = 8;
  bool gi = true;
  float cutoff = 0.001f;
  bool lobe_splitting = true;
  float clamp = 0.0f;  // 0 = off
  int rr_depth = 4;    // archwave extension: first bounce at which Russian roulette may end a path
  // Where the random numbers come from (kernels/common/rng.h): Owen-scrambled Sobol' points
  // per pixel, the same ordered along a randomised Morton curve (blue noise), or independent
  // (white-noise) hashes, kept for comparison.
  enum class Sampler { Sobol, ZSobol, Independent };
  Sampler sampler = Sampler::Sobol;
  // How next-event estimation chooses lights (kernels/lights/light_tree.h): by power alone (the
  // alias table), by the light tree, or auto: the tree from kLightTreeMinLights finite lights on.
  enum class LightSelection { Auto, Power, Tree };
  LightSelection light_selection = LightSelection::Auto;
  // Meshes placed several times are stored once (a two-level BVH); false stores every
  // placement as a mesh of its own (docs/scene-format.md#instancing).
  bool instancing = true;
  // Arbitrary output variables written beside the beauty (docs/production.md#aovs): a bit per
  // AW_AOV_* of kernels/integrator/aov.h, from the names in render.aovs / --aovs.
  uint32_t aovs = 0;
};

struct ExposureDesc {
  enum class Mode { Stops, Photographic };
  Mode mode = Mode::Stops;
  float stops = 0.0f;
  // Photographic (mental ray compatible): k = (1/shutter) * iso / (f_number^2 * 100).
  float iso = 100.0f;
  float shutter = 100.0f;  // 1/seconds
  float f_number = 16.0f;
  glm::vec3 whitepoint{1.0f};
  float vignetting = 0.0f;
};

struct CameraDesc {
  glm::vec3 position{0.0f, 1.0f, 4.0f};
  glm::vec3 look_at{0.0f, 1.0f, 0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float fov = 40.0f;  // vertical, degrees
  ExposureDesc exposure;
};

struct EnvironmentDesc {
  enum class Type { Constant, Map, Sky };
  Type type = Type::Constant;
  glm::vec3 color{0.0f};  // constant
  float intensity = 1.0f;  // every type: multiplies the radiance
  // map: a lat-long EXR (kernels/lights/environment.h has the mapping), read by the loader.
  std::string file;        // as resolved against the scene file
  float rotation = 0.0f;   // degrees about +Y (map)
  bool uniform_sampling = false;  // environment.sampling "uniform": for comparison with importance sampling
  int map_width = 0, map_height = 0;
  std::vector<float> map_rgb;  // linear RGB, row 0 at the top (+Y)
  // sky: Preetham, Shirley & Smits 1999 (host/scene/sky.h), lit by the first sun light.
  float turbidity = 3.0f;
  glm::vec3 ground_albedo{0.2f};
  int resolution = 1024;  // width of the baked lat-long sky; its height is half of it
};

struct LightDesc {
  enum class Type { Point, Quad, Disk, Sphere, Sun };
  Type type = Type::Point;
  glm::vec3 color{1.0f};
  float intensity = 1.0f;
  // point: position. sphere: center + radius. disk: center + normal + radius.
  // quad: corner + edge_u + edge_v (emits towards edge_u x edge_v unless two_sided).
  glm::vec3 position{0.0f};
  glm::vec3 center{0.0f};
  glm::vec3 normal{0.0f, -1.0f, 0.0f};
  float radius = 0.5f;
  glm::vec3 corner{0.0f};
  glm::vec3 edge_u{1.0f, 0.0f, 0.0f};
  glm::vec3 edge_v{0.0f, 0.0f, 1.0f};
  bool two_sided = false;
  bool visible = true;
  // sun: direction the light travels (unit), angular diameter in degrees (0: hard shadows).
  glm::vec3 direction{0.0f, -1.0f, 0.0f};
  float angle = 0.53f;
};

// One triangulated object in world space. Built-in shapes are tessellated with smooth normals
// and UVs; OBJ meshes keep their normals/UVs when they have them (empty vectors otherwise).
struct TriangleMesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  // per vertex, same size as positions, or empty
  std::vector<glm::vec2> uvs;      // per vertex, same size as positions, or empty
  // The second UV set (glTF TEXCOORD_1; texture lookups with uv_set 1 read it), or empty:
  // lookups of set 1 then read set 0.
  std::vector<glm::vec2> uvs2;
  // Per vertex, same size as positions, or empty: xyz a unit tangent along increasing u,
  // orthogonal to the normal; w = ±1, the handedness (sign of (n × t)·dP/dv). Built-in shapes
  // carry their analytic tangents; OBJ meshes none: they are generated when a material
  // needs them (host/scene/tangents.h).
  std::vector<glm::vec4> tangents;
  std::vector<glm::uvec3> indices;
  uint32_t material = 0;  // index into Scene::materials
  std::string name;       // "objects[3] (mesh meshes/bunny.obj)" for messages and stats
  bool light_sampling = false;  // objects[].light_sampling: its triangles are lights (incandescent material)
};

// An analytic sphere (objects[].shape "sphere" under a similarity transform, without
// "segments" or light_sampling: docs/scene-format.md#sphere): one primitive in world space.
// Its frame places the UV parametrisation as the tessellated sphere's: u = 0 along axis_x, v
// from -axis_y (0) to +axis_y (1).
struct SphereDesc {
  glm::vec3 center{0.0f};
  float radius = 1.0f;
  glm::vec3 axis_x{1.0f, 0.0f, 0.0f};
  glm::vec3 axis_y{0.0f, 1.0f, 0.0f};
  uint32_t material = 0;
  std::string name;
};

// A mesh shared by several placements (instancing, docs/scene-format.md#instancing): its
// parts (one per material, as a mesh object's) in the mesh file's own space, stored once.
struct MeshPrototype {
  std::string name;  // "meshes.tree" or "objects[3] (mesh meshes/chair.obj)", for messages and stats
  std::vector<TriangleMesh> parts;
  size_t triangle_count() const {
    size_t n = 0;
    for (const auto& m : parts) n += m.indices.size();
    return n;
  }
};

// One placement of a prototype: its object-to-world transform (affine, invertible).
struct MeshInstance {
  uint32_t prototype = 0;
  glm::dmat4 transform{1.0};
  std::string name;
};

struct Scene {
  std::string path;  // the scene file as given
  RenderSettings render;
  CameraDesc camera;
  EnvironmentDesc environment;
  std::vector<LightDesc> lights;
  std::vector<std::string> material_names;  // same order as materials
  std::vector<MaterialDesc> materials;
  std::vector<TextureDesc> textures;  // the "textures" section (and those glTF files bring)
  std::vector<TriangleMesh> meshes;  // world space, each stored once
  std::vector<SphereDesc> spheres;
  // Instancing: meshes stored once in their own space, placed by instances.
  std::vector<MeshPrototype> prototypes;
  std::vector<MeshInstance> instances;
  std::vector<std::string> warnings;  // already printed once by load_scene; kept for tests

  // Triangles stored: the world meshes' and each prototype's once.
  size_t triangle_count() const {
    size_t n = 0;
    for (const auto& m : meshes) n += m.indices.size();
    for (const auto& p : prototypes) n += p.triangle_count();
    return n;
  }
  // Triangles as rendered: each instance counts its prototype's.
  size_t rendered_triangle_count() const {
    size_t n = 0;
    for (const auto& m : meshes) n += m.indices.size();
    for (const auto& i : instances) n += prototypes[i.prototype].triangle_count();
    return n;
  }
};

// How much memory a scene may grow to (docs/scene-format.md, "Memory"). The loader estimates
// what rendering it will take, kRenderBytesPerTriangle per triangle, and checks object by
// object, a built-in shape before it is tessellated, so that a scene too large for the machine
// is refused with the sizes instead of being killed by the out-of-memory killer.
struct LoadLimits {
  uint64_t max_bytes = 0;  // 0: no limit
  std::string source;      // where the limit comes from, for the message ("--max-memory", ...)
};
// Peak bytes per triangle of a wavefront render on PoCL, measured: 64 default spheres (1.05 M
// triangles) peaked at 666 MB RSS, 460 B per triangle after the path pool and film; the BVH
// build, the flattened BVH, the packed arrays and PoCL's copies of the device buffers. With a
// margin.
constexpr uint64_t kRenderBytesPerTriangle = 500;

// The memory the machine can give now (MemAvailable of /proc/meminfo), 0 when unknown.
uint64_t available_memory_bytes();

// Loads and validates a scene. `overrides` are the command line's -D entries, each
// "dotted.key.path=value" (value parsed as JSON, falling back to a plain string); they are
// applied before validation so they are checked like the file's own keys.
// Throws SceneError on any problem. Warnings (clamped values) go to stderr and Scene::warnings.
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {},
                 const LoadLimits& limits = {});

// Linear exposure scale: 2^stops, or the photographic constant.
float exposure_scale(const ExposureDesc& e);

// The whole exposure, in place on an RGB image (3 floats per pixel, top row first) of the
// camera's render: k = exposure_scale, and in photographic mode the white balance (whitepoint)
// and the vignetting (docs/scene-format.md, camera.exposure).
void apply_exposure(const CameraDesc& cam, int width, int height, float* rgb);

// The exposure as numbers, so that an image can be exposed without its scene (archwave
// merge): factor(x, y) multiplies frame pixel (x, y)'s channel c by k * wb[c] * vignetting.
struct ExposureMap {
  double k = 1.0;
  double wb[3] = {1.0, 1.0, 1.0};
  double vignetting = 0.0;    // the cos^4 law's exponent; 0 = none
  double tan_half_fov = 1.0;  // the camera's, for the vignetting's angle
  // "k wb0 wb1 wb2 vignetting tan_half_fov", each with 17 significant digits (exact).
  std::string to_string() const;
  // The inverse of to_string; false for anything else.
  static bool parse(const std::string& s, ExposureMap* out);
  // Exposes an RGB window (3 floats per pixel) at (x0, y0) of size w x h of a frame_w x
  // frame_h frame, in place.
  void apply(int frame_w, int frame_h, int x0, int y0, int w, int h, float* rgb) const;
};
ExposureMap exposure_map(const CameraDesc& cam);

}  // namespace aw
