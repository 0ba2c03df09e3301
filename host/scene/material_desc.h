// Every parameter of the Architectural material (docs/material.md §1), with its default.
// Field names follow the scene-file keys. The loader fills this from JSON; the renderer packs
// what the kernels need into kernels/types/material.h.
#pragma once

#include <string>

#include <glm/glm.hpp>

#include "host/scene/texture_desc.h"

namespace aw {

enum class Brdf { Beckmann, Ggx, AshikhminShirley, AshikhminShirleyLegacy };
enum class FresnelMedium { Dielectric, Conductor };
enum class AoCombine { Add, Multiply };
enum class AnisoOrientation { Tangent, Uv };

struct FresnelDesc {
  bool use_ior = true;
  bool lock_to_refraction_ior = true;
  float ior = 1.5f;
  FresnelMedium medium = FresnelMedium::Dielectric;
  float k = 0.0f;
  float facing = 0.2f;
  float perpendicular = 1.0f;
  float curve = 5.0f;
};

struct ReflectionDesc {
  float weight = 0.6f;  // reflection2 defaults to 0
  glm::vec3 color{1.0f};
  Brdf brdf = Brdf::Ggx;
  float glossiness = 1.0f;
  int samples = 8;
  bool disable_bump = false;
  FresnelDesc fresnel;
};

struct FogDesc {
  bool enable = false;
  float distance = 0.0f;
  bool use_end_color = false;
  glm::vec3 end_color{0.0f};
};

struct RefractionDesc {
  float weight = 0.0f;
  glm::vec3 color{1.0f};
  float glossiness = 1.0f;
  int samples = 8;
  float ior = 1.4f;
  bool disable_bump = false;
  bool thin_walled = false;
  bool caustics = false;
  bool allow_global_volume = true;
  FogDesc fog;
};

struct AoDesc {
  bool enable = false;
  AoCombine combine = AoCombine::Add;
  bool apply_to_incandescence = false;
  bool exposure_compensation = false;
  int samples = 16;
  float max_distance = 10.0f;
  float spread = 0.8f;
  float falloff = 1.0f;
  bool invert_normal = false;
  glm::vec3 shadow_color{0.2f};
  glm::vec3 ambient_color{1.0f};
};

struct CutoffDesc {
  bool enable = false;
  float threshold = 0.01f;
};

struct OptimizationsDesc {
  bool trace_depth_override = false;
  int reflection_depth = 5;
  int refraction_depth = 5;
  bool specular_highlights_only = false;
  bool skip_weak_internal_reflections = true;
  CutoffDesc reflection_cutoff;
  CutoffDesc refraction_cutoff;
};

struct MaterialDesc {
  struct {
    glm::vec3 color{0.5f};
    float weight = 1.0f;
    float roughness = 0.0f;
    bool disable_bump = false;
  } diffuse;
  struct {
    bool enable = false;
    glm::vec3 color{0.7f, 0.6f, 0.5f};
    float weight = 0.5f;
  } translucency;
  ReflectionDesc reflection;
  ReflectionDesc reflection2 = [] {
    ReflectionDesc r;
    r.weight = 0.0f;
    return r;
  }();
  bool metal = false;
  float highlight_vs_reflection = 1.0f;
  struct {
    float amount = 0.0f;
    float rotation = 0.0f;
    AnisoOrientation orientation = AnisoOrientation::Tangent;
    int uv_set = 0;
  } anisotropy;
  RefractionDesc refraction;
  AoDesc ao;
  OptimizationsDesc optimizations;
  float cutout_opacity = 1.0f;
  struct {
    glm::vec3 color{0.0f};
    float scale = 1.0f;
  } incandescent;
  bool propagate_alpha = false;
  struct {
    std::string input;  // texture name; empty = none
    float scale = 1.0f;
    bool add_to_material_bump = false;
  } bump;
  // Inputs read from textures instead of their constants, by key ("diffuse.color", ...,
  // "bump.input"); host/scene/texture_inputs.h lists the keys that may be bound.
  TextureBindings textures;
};

}  // namespace aw
