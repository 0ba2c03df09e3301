// The "materials" section: every key of docs/material.md §1, with its default from MaterialDesc.
#include <algorithm>
#include <cmath>
#include <limits>

#include "host/scene/loader_parts.h"
#include "host/scene/texture_inputs.h"

namespace aw {
namespace scene_detail {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Reads the values of one material. Values outside their documented range are clamped (the
// material spec asks for that, unlike render settings, where a bad value is an error) with
// exactly one warning per key that names the material and the key.
class MaterialParser {
 public:
  MaterialParser(LoadContext& ctx, std::string name) : ctx_(ctx), name_(std::move(name)) {}

  MaterialDesc parse(const Node& n) {
    MaterialDesc m;
    expect_object(ctx_, n,
                  {"diffuse", "translucency", "reflection", "reflection2", "metal",
                   "highlight_vs_reflection", "anisotropy", "refraction", "ao", "optimizations",
                   "cutout_opacity", "incandescent", "propagate_alpha", "bump"});

    if (Node g = child(n, "diffuse"); g.j) {
      expect_object(ctx_, g, {"color", "weight", "roughness", "disable_bump"});
      colour(g, "color", 0, 1, &m.diffuse.color);
      scalar(g, "weight", 0, 1, &m.diffuse.weight);
      scalar(g, "roughness", 0, 1, &m.diffuse.roughness);
      boolean(g, "disable_bump", &m.diffuse.disable_bump);
    }
    if (Node g = child(n, "translucency"); g.j) {
      expect_object(ctx_, g, {"enable", "color", "weight"});
      boolean(g, "enable", &m.translucency.enable);
      colour(g, "color", 0, 1, &m.translucency.color);
      scalar(g, "weight", 0, 1, &m.translucency.weight);
    }
    if (Node g = child(n, "reflection"); g.j) reflection(g, &m.reflection);
    if (Node g = child(n, "reflection2"); g.j) reflection(g, &m.reflection2);
    boolean(n, "metal", &m.metal);
    scalar(n, "highlight_vs_reflection", 0, kInf, &m.highlight_vs_reflection);

    if (Node g = child(n, "anisotropy"); g.j) {
      expect_object(ctx_, g, {"amount", "rotation", "orientation", "uv_set"});
      scalar(g, "amount", -1, 1, &m.anisotropy.amount);
      // Rotation is periodic (0..1 = 0..360 degrees, used as 2*pi*rotation), so any value is
      // meaningful and nothing is clamped.
      scalar(g, "rotation", -kInf, kInf, &m.anisotropy.rotation);
      if (Node e = child(g, "orientation"); e.j) {
        m.anisotropy.orientation = read_enum<AnisoOrientation>(
            ctx_, e, {{"tangent", AnisoOrientation::Tangent}, {"uv", AnisoOrientation::Uv}});
      }
      integer(g, "uv_set", 0, std::numeric_limits<int>::max(), &m.anisotropy.uv_set);
      // Meshes carry two UV sets (glTF's TEXCOORD_0 and TEXCOORD_1; a mesh with one reads it
      // as both): a higher set would silently orient the highlight by another, so it is an
      // error, not a warning.
      if (m.anisotropy.uv_set > 1) {
        ctx_.fail(join_key(g.path, "uv_set"), "material \"" + name_ + "\": anisotropy.uv_set = " +
                                                  std::to_string(m.anisotropy.uv_set) +
                                                  ": no such UV set; meshes carry two UV sets, 0 and 1");
      }
    }

    if (Node g = child(n, "refraction"); g.j) refraction(g, &m.refraction);

    if (Node g = child(n, "ao"); g.j) {
      expect_object(
          ctx_, g,
          {"enable", "combine", "apply_to_incandescence", "exposure_compensation", "samples",
           "max_distance", "spread", "falloff", "invert_normal", "shadow_color", "ambient_color"});
      boolean(g, "enable", &m.ao.enable);
      if (Node e = child(g, "combine"); e.j) {
        m.ao.combine = read_enum<AoCombine>(
            ctx_, e, {{"add", AoCombine::Add}, {"multiply", AoCombine::Multiply}});
      }
      boolean(g, "apply_to_incandescence", &m.ao.apply_to_incandescence);
      boolean(g, "exposure_compensation", &m.ao.exposure_compensation);
      integer(g, "samples", 1, std::numeric_limits<int>::max(), &m.ao.samples);
      scalar(g, "max_distance", 0, kInf, &m.ao.max_distance);
      scalar(g, "spread", 0, 1, &m.ao.spread);
      scalar(g, "falloff", 0, kInf, &m.ao.falloff);
      boolean(g, "invert_normal", &m.ao.invert_normal);
      // AO colours are multipliers of the lighting, not reflectances: no upper bound.
      colour(g, "shadow_color", 0, kInf, &m.ao.shadow_color);
      colour(g, "ambient_color", 0, kInf, &m.ao.ambient_color);
    }

    if (Node g = child(n, "optimizations"); g.j) {
      expect_object(ctx_, g,
                    {"trace_depth_override", "reflection_depth", "refraction_depth",
                     "specular_highlights_only", "skip_weak_internal_reflections",
                     "reflection_cutoff", "refraction_cutoff"});
      OptimizationsDesc& o = m.optimizations;
      boolean(g, "trace_depth_override", &o.trace_depth_override);
      integer(g, "reflection_depth", 0, std::numeric_limits<int>::max(), &o.reflection_depth);
      integer(g, "refraction_depth", 0, std::numeric_limits<int>::max(), &o.refraction_depth);
      boolean(g, "specular_highlights_only", &o.specular_highlights_only);
      boolean(g, "skip_weak_internal_reflections", &o.skip_weak_internal_reflections);
      cutoff(g, "reflection_cutoff", &o.reflection_cutoff);
      cutoff(g, "refraction_cutoff", &o.refraction_cutoff);
    }

    scalar(n, "cutout_opacity", 0, 1, &m.cutout_opacity);
    if (Node g = child(n, "incandescent"); g.j) {
      expect_object(ctx_, g, {"color", "scale"});
      // Emission: any non-negative radiance.
      colour(g, "color", 0, kInf, &m.incandescent.color);
      scalar(g, "scale", 0, kInf, &m.incandescent.scale);
    }
    boolean(n, "propagate_alpha", &m.propagate_alpha);

    if (Node g = child(n, "bump"); g.j) {
      expect_object(ctx_, g, {"input", "scale", "add_to_material_bump"});
      if (Node in = child(g, "input"); in.j && !in.j->is_null()) {
        // A bump input is always a texture (by name or {"texture": NAME}); "" means none. Its
        // value (luminance, or "channel") times bump.scale is the height in scene units.
        if (!(in.j->is_string() && in.j->get<std::string>().empty())) {
          if (in.j->is_string()) {
            Json ref = Json::object();
            ref["texture"] = in.j->get<std::string>();
            m.textures["bump.input"] = read_texture_ref(ctx_, Node{&ref, in.path}, false);
          } else if (is_texture_reference(*in.j)) {
            m.textures["bump.input"] = read_texture_ref(ctx_, in, false);
          } else {
            ctx_.fail(in.path, "expected a texture name or {\"texture\": NAME}, got " + describe(*in.j));
          }
          m.bump.input = "texture";
        }
      }
      // Negative scales invert the bump; any finite value is meaningful.
      scalar(g, "scale", -kInf, kInf, &m.bump.scale);
      boolean(g, "add_to_material_bump", &m.bump.add_to_material_bump);
    }
    for (auto& [key, ref] : textures_) m.textures[key] = ref;
    return m;
  }

 private:
  void reflection(const Node& g, ReflectionDesc* r) {
    expect_object(ctx_, g,
                  {"weight", "color", "brdf", "glossiness", "samples", "disable_bump", "fresnel"});
    scalar(g, "weight", 0, 1, &r->weight);
    colour(g, "color", 0, 1, &r->color);
    if (Node e = child(g, "brdf"); e.j) {
      r->brdf = read_enum<Brdf>(ctx_, e,
                                {{"beckmann", Brdf::Beckmann},
                                 {"ggx", Brdf::Ggx},
                                 {"ashikhmin_shirley", Brdf::AshikhminShirley},
                                 {"ashikhmin_shirley_legacy", Brdf::AshikhminShirleyLegacy}});
    }
    scalar(g, "glossiness", 0, 1, &r->glossiness);
    integer(g, "samples", 1, std::numeric_limits<int>::max(), &r->samples);
    boolean(g, "disable_bump", &r->disable_bump);
    if (Node f = child(g, "fresnel"); f.j) {
      expect_object(ctx_, f,
                    {"use_ior", "lock_to_refraction_ior", "ior", "medium", "k", "facing",
                     "perpendicular", "curve"});
      FresnelDesc& fr = r->fresnel;
      boolean(f, "use_ior", &fr.use_ior);
      boolean(f, "lock_to_refraction_ior", &fr.lock_to_refraction_ior);
      scalar(f, "ior", kMinIor, kInf, &fr.ior);
      if (Node e = child(f, "medium"); e.j) {
        fr.medium = read_enum<FresnelMedium>(
            ctx_, e,
            {{"dielectric", FresnelMedium::Dielectric}, {"conductor", FresnelMedium::Conductor}});
      }
      scalar(f, "k", 0, kInf, &fr.k);
      scalar(f, "facing", 0, 1, &fr.facing);
      scalar(f, "perpendicular", 0, 1, &fr.perpendicular);
      scalar(f, "curve", 0, kInf, &fr.curve);
    }
  }

  void refraction(const Node& g, RefractionDesc* r) {
    expect_object(ctx_, g,
                  {"weight", "color", "glossiness", "samples", "ior", "disable_bump", "thin_walled",
                   "caustics", "allow_global_volume", "fog"});
    scalar(g, "weight", 0, 1, &r->weight);
    colour(g, "color", 0, 1, &r->color);
    scalar(g, "glossiness", 0, 1, &r->glossiness);
    integer(g, "samples", 1, std::numeric_limits<int>::max(), &r->samples);
    scalar(g, "ior", kMinIor, kInf, &r->ior);
    boolean(g, "disable_bump", &r->disable_bump);
    boolean(g, "thin_walled", &r->thin_walled);
    // docs/material.md §7: these depend on scene-wide features that come later; they parse now and
    // say so when they would change the image.
    boolean(g, "caustics", &r->caustics);
    if (r->caustics) {
      ctx_.warn(join_key(g.path, "caustics"),
                "material \"" + name_ +
                    "\": refraction.caustics is not implemented yet (needs the photon pass); "
                    "rendering without caustics");
    }
    boolean(g, "allow_global_volume", &r->allow_global_volume);
    if (!r->allow_global_volume) {
      ctx_.warn(join_key(g.path, "allow_global_volume"),
                "material \"" + name_ +
                    "\": refraction.allow_global_volume is not implemented yet (needs a "
                    "scene-wide volume); the setting has no effect");
    }
    if (Node f = child(g, "fog"); f.j) {
      expect_object(ctx_, f, {"enable", "distance", "use_end_color", "end_color"});
      boolean(f, "enable", &r->fog.enable);
      scalar(f, "distance", 0, kInf, &r->fog.distance);
      boolean(f, "use_end_color", &r->fog.use_end_color);
      colour(f, "end_color", 0, 1, &r->fog.end_color);
    }
  }

  void cutoff(const Node& parent, const char* key, CutoffDesc* c) {
    Node g = child(parent, key);
    if (!g.j) return;
    expect_object(ctx_, g, {"enable", "threshold"});
    boolean(g, "enable", &c->enable);
    scalar(g, "threshold", 0, 1, &c->threshold);
  }

  // "materials.glass.refraction.ior" -> "refraction.ior": the key as docs/material.md names it.
  std::string material_key(const std::string& path) const {
    const std::string prefix = join_key(join_key("materials", name_), "");
    return path.compare(0, prefix.size(), prefix) == 0 ? path.substr(prefix.size()) : path;
  }

  static std::string range_text(double lo, double hi) {
    Range r{lo, hi};
    return r.describe();
  }

  void warn_clamped(const Node& n, const std::string& value, double lo, double hi,
                    const std::string& clamped) {
    ctx_.warn(n.path, "material \"" + name_ + "\": " + material_key(n.path) + " = " + value +
                          " is not " + range_text(lo, hi) + "; clamped to " + clamped);
  }

  // {"texture": ...} in place of a value: recorded in the material's bindings (a key that no
  // texture can drive is an error). Returns whether it was one.
  bool texture(const Node& n, bool is_colour) {
    if (!is_texture_reference(*n.j)) return false;
    const std::string key = material_key(n.path);
    if (!find_texture_input(key))
      ctx_.fail(n.path, "material \"" + name_ + "\": " + key +
                            " cannot be read from a texture (docs/scene-format.md#textures lists the inputs that can)");
    textures_[key] = read_texture_ref(ctx_, n, is_colour);
    return true;
  }

  void scalar(const Node& parent, const char* key, double lo, double hi, float* out) {
    Node n = child(parent, key);
    if (!n.j) return;
    if (texture(n, false)) return;
    const double v = read_scalar_input(ctx_, n);
    const double c = std::min(std::max(v, lo), hi);
    if (c != v) warn_clamped(n, describe(*n.j), lo, hi, format_number(c));
    *out = static_cast<float>(c);
  }

  void colour(const Node& parent, const char* key, double lo, double hi, glm::vec3* out) {
    Node n = child(parent, key);
    if (!n.j) return;
    if (texture(n, true)) return;
    const glm::dvec3 v = read_colour(ctx_, n);
    const glm::dvec3 c = glm::min(glm::max(v, glm::dvec3(lo)), glm::dvec3(hi));
    if (c != v) {
      warn_clamped(
          n, describe(*n.j), lo, hi,
          "[" + format_number(c.x) + ", " + format_number(c.y) + ", " + format_number(c.z) + "]");
    }
    *out = glm::vec3(c);
  }

  void integer(const Node& parent, const char* key, int64_t lo, int64_t hi, int* out) {
    Node n = child(parent, key);
    if (!n.j) return;
    const int64_t v = read_integer(ctx_, n);
    const int64_t c = std::min(std::max(v, lo), hi);
    if (c != v) {
      warn_clamped(n, describe(*n.j), static_cast<double>(lo),
                   hi >= std::numeric_limits<int>::max() ? kInf : static_cast<double>(hi),
                   std::to_string(c));
    }
    *out = static_cast<int>(c);
  }

  void boolean(const Node& parent, const char* key, bool* out) {
    Node n = child(parent, key);
    if (n.j) *out = read_bool(ctx_, n);
  }

  // An IOR must be positive; 0.01 is far below any real medium and keeps 1/ior finite.
  static constexpr double kMinIor = 0.01;

  LoadContext& ctx_;
  std::string name_;
  TextureBindings textures_;  // collected by scalar/colour, handed to the material at the end
};

}  // namespace

MaterialDesc parse_material(LoadContext& ctx, const Node& n, const std::string& name) {
  return MaterialParser(ctx, name).parse(n);
}

}  // namespace scene_detail
}  // namespace aw
