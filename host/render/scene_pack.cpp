#include "host/render/scene_pack.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "host/render/alias_table.h"
#include "host/scene/tangents.h"
#include "kernels/common/rng.h"
#include "kernels/common/sampling.h"
#include "kernels/material/architectural.h"

namespace aw {

namespace {

void put3(float* dst, glm::vec3 v) {
  dst[0] = v.x;
  dst[1] = v.y;
  dst[2] = v.z;
}

LightGpu pack_light(const LightDesc& d, float* power) {
  LightGpu l;
  std::memset(&l, 0, sizeof(l));
  glm::vec3 radiance = d.color * d.intensity;
  put3(l.radiance, radiance);
  l.flags = (d.two_sided ? AW_LIGHT_TWO_SIDED : 0u) | (d.visible ? AW_LIGHT_VISIBLE : 0u);
  const float pi = M_PI_F;
  // Emitted power (luminance), the light-selection weight: a point light emits 4 pi I, a
  // Lambertian area emitter pi L A per emitting side.
  switch (d.type) {
    case LightDesc::Type::Point:
      l.type = AW_LIGHT_POINT;
      put3(l.p, d.position);
      *power = 4.0f * pi * luminance(radiance);
      break;
    case LightDesc::Type::Quad: {
      l.type = AW_LIGHT_QUAD;
      put3(l.p, d.corner);
      put3(l.u, d.edge_u);
      put3(l.v, d.edge_v);
      glm::vec3 c = glm::cross(d.edge_u, d.edge_v);
      l.area = glm::length(c);
      put3(l.n, l.area > 0.0f ? c / l.area : glm::vec3(0, 0, 1));
      // Orthogonal edges: a rectangle, which light sampling samples by solid angle
      // (kernels/lights/lights.h); a general parallelogram is sampled by area.
      if (std::fabs(glm::dot(d.edge_u, d.edge_v)) <= 1e-6f * glm::length(d.edge_u) * glm::length(d.edge_v))
        l.flags |= AW_LIGHT_RECTANGLE;
      *power = pi * luminance(radiance) * l.area * (d.two_sided ? 2.0f : 1.0f);
      break;
    }
    case LightDesc::Type::Disk: {
      l.type = AW_LIGHT_DISK;
      put3(l.p, d.center);
      glm::vec3 n = glm::normalize(d.normal);
      float3 t, b;
      make_frame(n, &t, &b);
      put3(l.n, n);
      put3(l.u, t);
      put3(l.v, b);
      l.radius = d.radius;
      l.area = pi * d.radius * d.radius;
      *power = pi * luminance(radiance) * l.area * (d.two_sided ? 2.0f : 1.0f);
      break;
    }
    case LightDesc::Type::Sphere:
      l.type = AW_LIGHT_SPHERE;
      put3(l.p, d.center);
      l.radius = d.radius;
      l.area = 4.0f * pi * d.radius * d.radius;
      *power = pi * luminance(radiance) * l.area;
      break;
  }
  // A zero-area light emits nothing and must never be sampled (its pdf would be infinite).
  if (d.type != LightDesc::Type::Point && !(l.area > 0.0f)) *power = 0.0f;
  return l;
}

uint32_t pack_brdf(Brdf b) {
  switch (b) {
    case Brdf::Beckmann: return AW_BRDF_BECKMANN;
    case Brdf::Ggx: return AW_BRDF_GGX;
    case Brdf::AshikhminShirley: return AW_BRDF_ASHIKHMIN_SHIRLEY;
    case Brdf::AshikhminShirleyLegacy: return AW_BRDF_ASHIKHMIN_SHIRLEY_LEGACY;
  }
  return AW_BRDF_GGX;
}

ReflectionGpu pack_reflection(const ReflectionDesc& r, float refraction_ior) {
  ReflectionGpu g;
  std::memset(&g, 0, sizeof(g));
  put3(g.color, r.color);
  g.weight = r.weight;
  g.glossiness = r.glossiness;
  g.brdf = pack_brdf(r.brdf);
  // Fresnel mode: physical (dielectric or conductor) from an IOR, or the artist curve.
  if (!r.fresnel.use_ior) g.fresnel_mode = AW_FRESNEL_CURVE;
  else g.fresnel_mode = r.fresnel.medium == FresnelMedium::Conductor ? AW_FRESNEL_CONDUCTOR : AW_FRESNEL_DIELECTRIC;
  g.fresnel_ior = r.fresnel.lock_to_refraction_ior ? refraction_ior : r.fresnel.ior;
  g.fresnel_k = r.fresnel.k;
  g.facing = r.fresnel.facing;
  g.perpendicular = r.fresnel.perpendicular;
  g.curve = r.fresnel.curve;
  g.samples = uint32_t(r.samples);
  return g;
}

MaterialGpu pack_material(const MaterialDesc& d, const RenderSettings& rs, const std::string& name,
                          std::vector<std::string>* warnings) {
  MaterialGpu g;
  std::memset(&g, 0, sizeof(g));
  put3(g.diffuse_color, d.diffuse.color);
  g.diffuse_weight = d.diffuse.weight;
  g.diffuse_roughness = d.diffuse.roughness;
  if (d.translucency.enable) {
    put3(g.transl_color, d.translucency.color);
    g.transl_weight = d.translucency.weight;
    g.flags |= AW_MAT_TRANSLUCENCY;
  }
  g.refl[0] = pack_reflection(d.reflection, d.refraction.ior);
  g.refl[1] = pack_reflection(d.reflection2, d.refraction.ior);
  const OptimizationsDesc& o = d.optimizations;
  if (o.reflection_cutoff.enable) g.refl[0].cutoff = g.refl[1].cutoff = o.reflection_cutoff.threshold;
  put3(g.refr_color, d.refraction.color);
  g.refr_weight = d.refraction.weight;
  g.refr_glossiness = d.refraction.glossiness;
  g.refr_ior = d.refraction.ior;
  g.refr_samples = uint32_t(d.refraction.samples);
  if (o.refraction_cutoff.enable) g.refr_cutoff = o.refraction_cutoff.threshold;
  const FogDesc& fog = d.refraction.fog;
  if (fog.enable && fog.distance > 0.0f) {
    g.fog_distance = fog.distance;
    put3(g.fog_end_color, fog.end_color);
    if (fog.use_end_color) g.flags |= AW_MAT_FOG_END_COLOR;
  }
  put3(g.incandescent, d.incandescent.color * d.incandescent.scale);
  g.cutout_opacity = d.cutout_opacity;
  g.aniso_amount = d.anisotropy.amount;
  g.aniso_rotation = d.anisotropy.rotation;
  g.aniso_orientation = d.anisotropy.orientation == AnisoOrientation::Uv ? AW_ANISO_UV : AW_ANISO_TANGENT;
  g.highlight_vs_reflection = d.highlight_vs_reflection;
  if (d.metal) g.flags |= AW_MAT_METAL;
  if (d.refraction.thin_walled) g.flags |= AW_MAT_THIN_WALLED;
  if (o.specular_highlights_only) g.flags |= AW_MAT_HIGHLIGHTS_ONLY;
  if (o.skip_weak_internal_reflections) g.flags |= AW_MAT_SKIP_WEAK_INTERNAL;
  g.refl_depth = uint32_t(o.trace_depth_override ? o.reflection_depth : rs.reflection_depth);
  g.refr_depth = uint32_t(o.trace_depth_override ? o.refraction_depth : rs.refraction_depth);

  // What the kernels do not render yet is said, never silently dropped.
  auto note = [&](const std::string& what) {
    if (warnings) warnings->push_back("material '" + name + "': " + what);
  };
  if (d.ao.enable) note("ao is not rendered yet (ambient occlusion comes with the lights/AO issue)");
  if (!d.bump.input.empty()) note("bump is not rendered yet (textures come later)");
  return g;
}

}  // namespace

PackedScene pack_scene(const Scene& scene, std::vector<std::string>* warnings) {
  PackedScene ps;
  // Geometry: one global vertex and triangle list.
  for (const TriangleMesh& m : scene.meshes) {
    uint32_t base = uint32_t(ps.verts.size());
    bool has_n = m.normals.size() == m.positions.size();
    bool has_uv = m.uvs.size() == m.positions.size();
    // Mesh tangents for anisotropy.orientation = "tangent" (empty where nothing reads them).
    std::vector<glm::vec4> tangents;
    if (m.material < scene.materials.size()) tangents = tangents_for_material(m, scene.materials[m.material]);
    for (size_t i = 0; i < m.positions.size(); ++i) {
      VertexData v;
      std::memset(&v, 0, sizeof(v));
      put3(v.p, m.positions[i]);
      if (has_n) {
        put3(v.n, m.normals[i]);
        v.n[3] = 1.0f;  // marks "has a shading normal" (kernels/types/bvh.h)
      }
      if (has_uv) {
        v.uv[0] = m.uvs[i].x;
        v.uv[1] = m.uvs[i].y;
      }
      if (i < tangents.size()) {
        put3(v.t, glm::vec3(tangents[i]));
        v.t[3] = tangents[i].w;
      }
      ps.verts.push_back(v);
      ps.soup.positions.push_back(m.positions[i]);
    }
    for (const glm::uvec3& t : m.indices) {
      TriangleInfo ti;
      ti.v[0] = base + t.x;
      ti.v[1] = base + t.y;
      ti.v[2] = base + t.z;
      ti.material = m.material;
      ps.tri_info.push_back(ti);
      ps.soup.indices.push_back(glm::uvec3(ti.v[0], ti.v[1], ti.v[2]));
    }
  }

  for (size_t i = 0; i < scene.materials.size(); ++i) {
    const std::string& name = i < scene.material_names.size() ? scene.material_names[i] : std::to_string(i);
    ps.materials.push_back(pack_material(scene.materials[i], scene.render, name, warnings));
  }

  // Lights, with selection probabilities proportional to emitted power.
  std::vector<double> power;  // exact copies of the floats pack_light computes
  for (const LightDesc& d : scene.lights) {
    float p = 0.0f;
    ps.lights.push_back(pack_light(d, &p));
    power.push_back(std::isfinite(p) && p > 0.0f ? p : 0.0f);
  }
  double total = 0.0;
  for (double p : power) total += p;
  AliasTable alias = build_alias_table(power);  // light_pick's O(1) selection
  for (size_t i = 0; i < ps.lights.size(); ++i) {
    ps.lights[i].select_pdf = float(total > 0.0 ? power[i] / total : 0.0);
    ps.lights[i].alias_q = alias.q[i];
    ps.lights[i].alias = alias.alias[i];
  }

  // Camera: orthonormal basis from position, look_at and up.
  const CameraDesc& cam = scene.camera;
  glm::vec3 fwd = cam.look_at - cam.position;
  if (!(glm::length(fwd) > 0.0f)) throw SceneError(scene.path + ": camera: look_at equals position");
  fwd = glm::normalize(fwd);
  glm::vec3 right = glm::cross(fwd, cam.up);
  if (!(glm::length(right) > 1e-6f))
    throw SceneError(scene.path + ": camera: up is parallel to the viewing direction");
  right = glm::normalize(right);
  glm::vec3 up = glm::cross(right, fwd);
  RenderParams& rp = ps.params;
  std::memset(&rp, 0, sizeof(rp));
  put3(rp.cam_origin, cam.position);
  put3(rp.cam_forward, fwd);
  put3(rp.cam_right, right);
  put3(rp.cam_up, up);
  rp.tan_half_fov = std::tan(0.5f * cam.fov * M_PI_F / 180.0f);
  const RenderSettings& rs = scene.render;
  rp.aspect = float(rs.width) / float(rs.height);
  rp.width = uint32_t(rs.width);
  rp.height = uint32_t(rs.height);
  rp.seed = rs.seed;
  rp.max_depth = uint32_t(rs.max_depth);
  rp.gi = rs.gi ? 1u : 0u;
  rp.cutoff = rs.cutoff;
  rp.clamp = rs.clamp;
  rp.rr_depth = uint32_t(rs.rr_depth);
  rp.sampler = rs.sampler == RenderSettings::Sampler::Independent ? AW_SAMPLER_INDEPENDENT
               : rs.sampler == RenderSettings::Sampler::ZSobol    ? AW_SAMPLER_ZSOBOL
                                                                   : AW_SAMPLER_SOBOL;
  // zsobol's index layout (kernels/common/rng.h, sampler_for_image).
  const Sampler layout = sampler_for_image(rp.sampler, rp.seed, rp.width, rp.height, uint32_t(rs.spp));
  rp.sampler_log2_spp = layout.log2_spp;
  rp.sampler_bits = layout.bits;
  put3(rp.env_radiance, scene.environment.color * scene.environment.intensity);
  // Every light is passed, also those that cannot be sampled: they are still hit and still
  // occlude (a zero-radiance light is a black object). If all have zero power the pick lands
  // on a light with select_pdf 0, whose sample then contributes nothing.
  rp.num_lights = uint32_t(ps.lights.size());
  // The scene's features, decided once (host/render/features.cpp), and what follows from them.
  ps.features = decide_features(ps, rs);
  rp.split_spp = ps.features.on[FeatureSet::SPLIT] ? uint32_t(rs.spp) : 0u;
  return ps;
}

}  // namespace aw

