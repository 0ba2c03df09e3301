#include "host/render/scene_pack.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "host/render/alias_table.h"
#include "host/render/environment_pack.h"
#include "host/render/light_tree.h"
#include "host/render/texture_pack.h"
#include "host/scene/sky.h"
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

LightGpu pack_light(const LightDesc& d, float scene_radius, float* power) {
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
    case LightDesc::Type::Sun: {
      // kernels/lights/lights.h, "the sun": colour x intensity is the irradiance E on a surface
      // facing it; a disc of half-angle a has radiance E / (pi sin^2 a). 1 - cos a is kept as
      // 2 sin^2(a / 2), exact for the sun's 0.27 degrees where 1 - cos a would cancel.
      l.type = AW_LIGHT_SUN;
      put3(l.n, -glm::normalize(d.direction));
      const double half = 0.5 * double(d.angle) * M_PI / 180.0;
      l.radius = float(std::cos(half));
      l.area = float(2.0 * std::sin(0.5 * half) * std::sin(0.5 * half));
      if (l.area > 0.0f) {
        const double s2 = std::sin(half) * std::sin(half);
        put3(l.radiance, glm::vec3(glm::dvec3(radiance) / (M_PI * s2)));
      }
      // Power through the scene's bounding disc (Pharr, Jakob & Humphreys, PBR 4th ed., the
      // distant light's Phi = pi r^2 E): comparable with the area lights' for selection.
      *power = pi * scene_radius * scene_radius * luminance(radiance);
      break;
    }
  }
  // A zero-area light emits nothing and must never be sampled (its pdf would be infinite).
  if (d.type != LightDesc::Type::Point && d.type != LightDesc::Type::Sun && !(l.area > 0.0f)) *power = 0.0f;
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

MaterialGpu pack_material(const MaterialDesc& d, const RenderSettings& rs, float exposure_k) {
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
  if (d.anisotropy.uv_set == 1) g.flags |= AW_MAT_ANISO_UV_SET1;
  if (o.specular_highlights_only) g.flags |= AW_MAT_HIGHLIGHTS_ONLY;
  if (o.skip_weak_internal_reflections) g.flags |= AW_MAT_SKIP_WEAK_INTERNAL;
  g.refl_depth = uint32_t(o.trace_depth_override ? o.reflection_depth : rs.reflection_depth);
  g.refr_depth = uint32_t(o.trace_depth_override ? o.refraction_depth : rs.refraction_depth);
  // Ambient occlusion (kernels/integrator/ambient_occlusion.h); samples 0 keeps it off.
  const AoDesc& ao = d.ao;
  if (ao.enable && ao.samples > 0) {
    g.ao_samples = uint32_t(ao.samples);
    put3(g.ao_shadow_color, ao.shadow_color);
    put3(g.ao_ambient_color, ao.ambient_color);
    g.ao_max_distance = ao.max_distance;
    g.ao_spread = ao.spread;
    g.ao_falloff = ao.falloff;
    if (ao.combine == AoCombine::Multiply) g.ao_flags |= AW_AO_MULTIPLY;
    if (ao.invert_normal) g.ao_flags |= AW_AO_INVERT;
    if (ao.apply_to_incandescence) g.ao_flags |= AW_AO_INCANDESCENCE;
    // exposure_compensation: the ambient term is divided by the camera's exposure scale, so
    // that after exposure it shows at its colour whatever the exposure (docs/material.md §4).
    g.ao_add_scale = ao.exposure_compensation && exposure_k > 0.0f ? 1.0f / exposure_k : 1.0f;
  }

  g.cutout_binding = AW_NONE;
  g.bump_binding = AW_NONE;
  return g;
}

}  // namespace

PackedScene pack_scene(const Scene& scene, std::vector<std::string>* warnings) {
  PackedScene ps;
  // Geometry: one global vertex and triangle list: the world meshes, then each prototype's
  // parts in their own space (instancing, host/bvh/flat_bvh.h).
  auto add_mesh = [&](const TriangleMesh& m) {
    uint32_t base = uint32_t(ps.verts.size());
    bool has_n = m.normals.size() == m.positions.size();
    bool has_uv = m.uvs.size() == m.positions.size();
    bool has_uv2 = m.uvs2.size() == m.positions.size();  // else set 1 reads set 0
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
      v.uv2[0] = has_uv2 ? m.uvs2[i].x : v.uv[0];
      v.uv2[1] = has_uv2 ? m.uvs2[i].y : v.uv[1];
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
  };
  for (const TriangleMesh& m : scene.meshes) add_mesh(m);
  const size_t world_verts = ps.soup.positions.size();
  for (const MeshPrototype& p : scene.prototypes) {
    SoupPrototype sp;
    sp.first_tri = uint32_t(ps.soup.indices.size());
    for (const TriangleMesh& m : p.parts) add_mesh(m);
    sp.tri_count = uint32_t(ps.soup.indices.size() - sp.first_tri);
    ps.soup.prototypes.push_back(sp);
  }
  // Instances: both transforms as float 3 x 4 rows (kernels/types/bvh.h), the inverse taken in
  // double; the root of the prototype's tree is the BVH's to set.
  for (const MeshInstance& mi : scene.instances) {
    InstanceGpu in;
    std::memset(&in, 0, sizeof(in));
    const glm::dmat4 inv = glm::inverse(mi.transform);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) {
        in.o2w[4 * r + c] = float(mi.transform[c][r]);  // glm is column-major
        in.w2o[4 * r + c] = float(inv[c][r]);
      }
    in.prototype = mi.prototype;
    in.flags = glm::determinant(glm::dmat3(mi.transform)) < 0.0 ? AW_INSTANCE_MIRROR : 0u;
    ps.soup.instances.push_back(in);
  }

  // Analytic spheres (kernels/types/bvh.h): after the triangles, one vertex each (centre and
  // radius, the frame's axes in n and t) and a TriangleInfo marked AW_SPHERE_MARK, so that
  // their primitive ids follow the triangles' in the BVH, in Embree and in tri_info alike.
  for (const SphereDesc& sd : scene.spheres) {
    VertexData v;
    std::memset(&v, 0, sizeof(v));
    put3(v.p, sd.center);
    v.p[3] = sd.radius;
    put3(v.n, sd.axis_x);
    put3(v.t, sd.axis_y);
    TriangleInfo ti;
    ti.v[0] = ti.v[2] = uint32_t(ps.verts.size());
    ti.v[1] = AW_SPHERE_MARK;
    ti.material = sd.material;
    ps.verts.push_back(v);
    ps.tri_info.push_back(ti);
    ps.soup.spheres.push_back(glm::vec4(sd.center, sd.radius));
  }

  TextureRanges ranges(scene);
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    ps.materials.push_back(pack_material(scene.materials[i], scene.render, exposure_scale(scene.camera.exposure)));
    pack_material_textures(scene, scene.materials[i], ranges, &ps.materials.back(), &ps.tex_bindings);
  }
  if (!ps.tex_bindings.empty()) {
    PackedTextures pt = pack_textures(scene);
    ps.textures = std::move(pt.textures);
    ps.texels = std::move(pt.texels);
  }

  // Lights, with selection probabilities proportional to emitted power. Lights at infinity
  // come first (kernels/types/scene.h): the environment map, then the suns in scene order.
  // Their power is taken through the scene's bounding disc, radius R (half the diagonal of
  // the geometry's bounds; 1 without geometry).
  float scene_radius = 1.0f;
  if (world_verts > 0 || !ps.soup.spheres.empty() || !ps.soup.instances.empty()) {
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (size_t i = 0; i < world_verts; ++i) {
      lo = glm::min(lo, ps.soup.positions[i]);
      hi = glm::max(hi, ps.soup.positions[i]);
    }
    const auto protos = prototype_bounds(ps.soup);
    for (size_t k = 0; k < ps.soup.instances.size(); ++k) {
      glm::vec3 ilo, ihi;
      instance_bounds(ps.soup, k, protos, &ilo, &ihi);
      lo = glm::min(lo, ilo);
      hi = glm::max(hi, ihi);
    }
    for (const glm::vec4& q : ps.soup.spheres) {
      lo = glm::min(lo, glm::vec3(q) - q.w);
      hi = glm::max(hi, glm::vec3(q) + q.w);
    }
    scene_radius = std::max(0.5f * glm::length(hi - lo), 1e-6f);
  }
  std::vector<double> power;  // exact copies of the floats pack_light computes
  const EnvironmentDesc& env = scene.environment;
  const LightDesc* first_sun = nullptr;
  for (const LightDesc& d : scene.lights)
    if (d.type == LightDesc::Type::Sun && !first_sun) first_sun = &d;
  if (env.type != EnvironmentDesc::Type::Constant) {
    PackedEnvironment pe;
    if (env.type == EnvironmentDesc::Type::Map) {
      pe = pack_environment(env.map_rgb, env.map_width, env.map_height, env.intensity, env.uniform_sampling);
      ps.env_width = env.map_width;
      ps.env_height = env.map_height;
    } else {
      // The sky is baked into a lat-long map in world space (no rotation: the first sun light
      // places it), and from there sampled like any map.
      const int w = env.resolution, h = std::max(1, env.resolution / 2);
      SkyModel sky = make_preetham_sky(-glm::normalize(first_sun->direction), env.turbidity, env.ground_albedo);
      pe = pack_environment(bake_sky_latlong(sky, w, h), w, h, env.intensity, env.uniform_sampling);
      ps.env_width = w;
      ps.env_height = h;
    }
    ps.env = std::move(pe.buffer);
    LightGpu l;
    std::memset(&l, 0, sizeof(l));
    l.type = AW_LIGHT_ENV;
    ps.lights.push_back(l);
    const double p = M_PI * double(scene_radius) * double(scene_radius) * pe.luminance_integral;
    power.push_back(std::isfinite(p) && p > 0.0 ? p : 0.0);
  }
  for (int pass = 0; pass < 2; ++pass) {
    for (const LightDesc& d : scene.lights) {
      if ((d.type == LightDesc::Type::Sun) != (pass == 0)) continue;
      LightDesc dd = d;
      // Under the sky, the sun's colour is the sky model's: the light's colour times the
      // direct sunlight's transmittance through the atmosphere at its elevation (normalised to
      // luminance 1, so that intensity stays the illuminance of a surface facing the sun).
      if (env.type == EnvironmentDesc::Type::Sky && d.type == LightDesc::Type::Sun) {
        const float zenith = std::acos(std::clamp(-glm::normalize(d.direction).y, -1.0f, 1.0f));
        dd.color = d.color * sun_transmittance_rgb(env.turbidity, zenith);
      }
      float p = 0.0f;
      ps.lights.push_back(pack_light(dd, scene_radius, &p));
      power.push_back(std::isfinite(p) && p > 0.0f ? p : 0.0f);
    }
    if (pass == 0) ps.num_infinite = uint32_t(ps.lights.size());
  }
  // Mesh lights (objects[].light_sampling): each triangle of a light-sampled object is a light
  // of its material's incandescence, emitting from both sides as incandescence does.
  {
    size_t tri = 0;
    for (const TriangleMesh& m : scene.meshes) {
      const MaterialDesc& md = scene.materials[m.material];
      const glm::vec3 le = md.incandescent.color * md.incandescent.scale;
      for (size_t k = 0; k < m.indices.size(); ++k, ++tri) {
        if (!m.light_sampling) continue;
        const TriangleInfo& ti = ps.tri_info[tri];
        const glm::vec3 p0 = ps.soup.positions[ti.v[0]], p1 = ps.soup.positions[ti.v[1]], p2 = ps.soup.positions[ti.v[2]];
        const glm::vec3 c = glm::cross(p1 - p0, p2 - p0);
        const float area = 0.5f * glm::length(c);
        // A degenerate triangle emits nothing and could not be sampled (its pdf would be
        // infinite): it stays plain geometry, as everywhere else (docs/scene-format.md).
        if (!(area > 0.0f) || !std::isfinite(area)) continue;
        LightGpu l;
        std::memset(&l, 0, sizeof(l));
        l.type = AW_LIGHT_TRIANGLE;
        l.flags = AW_LIGHT_TWO_SIDED | AW_LIGHT_VISIBLE;
        put3(l.p, p0);
        put3(l.u, p1 - p0);
        put3(l.v, p2 - p0);
        put3(l.n, c / (2.0f * area));
        put3(l.radiance, le);
        l.area = area;
        if (ps.tri_light.empty()) ps.tri_light.assign(ps.tri_info.size(), 0xffffffffu);  // AW_NONE
        ps.tri_light[tri] = uint32_t(ps.lights.size());
        ps.lights.push_back(l);
        const double p = 2.0 * M_PI * double(luminance(le)) * double(area);
        power.push_back(std::isfinite(p) && p > 0.0 ? p : 0.0);
      }
    }
  }
  // Selection (kernels/integrator/light_select.h): one alias table over every light, or, for
  // many lights, the light tree over the finite ones beside an alias table over the lights at
  // infinity. Within each group by power; between the groups by count, as pbrt-v4's
  // BVHLightSampler does: each light at infinity's share, and the finite lights' together,
  // 1 / (n_inf + 1). A power through the scene's bounding disc is no measure against a lamp's:
  // a sun over a 100 m ground plane would take 99.6% of the samples from three lamps beside it
  // (measured: 3% error at 65k samples in tests/render/test_many_lights.cpp).
  const uint32_t n_inf = ps.num_infinite, n_fin = uint32_t(ps.lights.size()) - ps.num_infinite;
  const RenderSettings::LightSelection sel = scene.render.light_selection;
  const bool tree = n_fin > 0 && (sel == RenderSettings::LightSelection::Tree ||
                                  (sel == RenderSettings::LightSelection::Auto && n_fin >= kLightTreeMinLights));
  double p_inf = 0.0, p_fin = 0.0;
  for (uint32_t i = 0; i < n_inf; ++i) p_inf += power[i];
  for (size_t i = n_inf; i < power.size(); ++i) p_fin += power[i];
  // The finite lights' share.
  const double fin_share = !(p_inf > 0.0) ? 1.0 : !(p_fin > 0.0) ? 0.0 : 1.0 / (double(n_inf) + 1.0);
  if (!tree) {
    std::vector<double> weight(power.size());
    for (size_t i = 0; i < power.size(); ++i)
      weight[i] = i < n_inf ? (p_inf > 0.0 ? (1.0 - fin_share) * power[i] / p_inf : 0.0)
                            : (p_fin > 0.0 ? fin_share * power[i] / p_fin : 0.0);
    // (Without lights at infinity the weights are the powers themselves: the table is built
    // from them as it always was, bit for bit.)
    AliasTable alias = build_alias_table(n_inf == 0 ? power : weight);  // light_pick's O(1) selection
    for (size_t i = 0; i < ps.lights.size(); ++i) {
      ps.lights[i].select_pdf = float(weight[i]);
      ps.lights[i].alias_q = alias.q[i];
      ps.lights[i].alias = alias.alias[i];
    }
  } else {
    ps.tree_prob = float(fin_share);
    if (n_inf > 0) {
      std::vector<double> inf_power(power.begin(), power.begin() + n_inf);
      AliasTable alias = build_alias_table(inf_power);
      for (uint32_t i = 0; i < n_inf; ++i) {
        ps.lights[i].select_pdf = float(p_inf > 0.0 ? (1.0 - double(ps.tree_prob)) * power[i] / p_inf : 0.0);
        ps.lights[i].alias_q = alias.q[i];
        ps.lights[i].alias = alias.alias[i];
      }
    }
    ps.light_tree = build_light_tree(ps.lights, n_inf, std::vector<double>(power.begin() + n_inf, power.end()));
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
  // The whole frame and every sample until the renderer narrows them (render.cpp, plan_film).
  rp.win_w = rp.width;
  rp.win_h = rp.height;
  rp.aov_mask = rs.aovs;
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
  // The constant environment (a map or a sky is a light instead).
  if (env.type == EnvironmentDesc::Type::Constant) put3(rp.env_radiance, env.color * env.intensity);
  // Every light is passed, also those that cannot be sampled: they are still hit and still
  // occlude (a zero-radiance light is a black object). If all have zero power the pick lands
  // on a light with select_pdf 0, whose sample then contributes nothing.
  rp.num_lights = uint32_t(ps.lights.size());
  rp.num_materials = uint32_t(ps.materials.size());
  rp.num_infinite = ps.num_infinite;
  rp.num_tree_nodes = uint32_t(ps.light_tree.size());
  rp.tree_prob = ps.tree_prob;
  rp.has_mesh_lights = ps.tri_light.empty() ? 0u : 1u;
  rp.env_width = uint32_t(ps.env_width);
  rp.env_height = uint32_t(ps.env_height);
  const double rotation = env.type == EnvironmentDesc::Type::Map ? double(env.rotation) * M_PI / 180.0 : 0.0;
  rp.env_rot_cos = float(std::cos(rotation));
  rp.env_rot_sin = float(std::sin(rotation));
  // Each material's own features, from the table as it goes to the device (the lane programs'
  // feature guard reads them: kernels/material/architectural.h, material_uses_missing_feature).
  for (MaterialGpu& m : ps.materials) m.features = material_features(&m);
  // The scene's features, decided once (host/render/features.cpp), and what follows from them.
  ps.features = decide_features(ps, rs);
  rp.split_spp = ps.features.on[FeatureSet::SPLIT] ? uint32_t(rs.spp) : 0u;
  // ao.samples split like a lobe's; 0 without AO, where it would change nothing (and would
  // tie the scene's identity, scene_identity, to spp).
  rp.ao_split_spp = rs.lobe_splitting && ps.features.on[FeatureSet::AO] ? uint32_t(rs.spp) : 0u;
  return ps;
}

namespace {

struct Fnv1a {
  uint64_t h = 1469598103934665603ull;
  void bytes(const void* p, size_t n) {
    const unsigned char* b = static_cast<const unsigned char*>(p);
    for (size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  }
  template <class T>
  void vec(const std::vector<T>& v) {
    const uint64_t n = v.size();
    bytes(&n, sizeof n);  // lengths too, so [a][bc] and [ab][c] differ
    if (!v.empty()) bytes(v.data(), v.size() * sizeof(T));
  }
};

}  // namespace

uint64_t scene_identity(const PackedScene& p) {
  Fnv1a f;
  f.vec(p.soup.positions);
  f.vec(p.soup.indices);
  f.vec(p.soup.spheres);
  for (const SoupPrototype& pr : p.soup.prototypes) {
    f.bytes(&pr.first_tri, sizeof pr.first_tri);
    f.bytes(&pr.tri_count, sizeof pr.tri_count);
  }
  f.vec(p.soup.instances);
  f.vec(p.tri_info);
  f.vec(p.verts);
  f.vec(p.materials);
  f.vec(p.lights);
  f.vec(p.env);
  f.vec(p.light_tree);
  f.vec(p.tri_light);
  f.vec(p.textures);
  f.vec(p.tex_bindings);
  f.vec(p.texels);
  RenderParams rp = p.params;
  rp.pool_size = 0;
  rp.batch_pixel = rp.batch_sample = rp.job_count = 0;
  rp.num_nodes = 0;  // the BVH's, set by the wavefront: not part of what is rendered
  rp.win_x0 = rp.win_y0 = rp.win_w = rp.win_h = 0;
  rp.sample_start = 0;
  rp.aov_mask = 0;  // which AOVs are kept changes no sample's value (begin_film checks it apart)
  // zsobol's layout depends on spp (rng.h); the other samplers' numbers do not, so a film of
  // theirs may be resumed to more samples.
  if (rp.sampler != AW_SAMPLER_ZSOBOL) rp.sampler_log2_spp = rp.sampler_bits = 0;
  f.bytes(&rp, sizeof rp);
  return f.h;
}

}  // namespace aw
