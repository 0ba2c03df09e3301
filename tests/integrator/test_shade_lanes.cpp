// The shading stages' shared steps on lanes (kernels/integrator/shade_common.h and the path
// state's lane access, path_state.h): 16 paths per work-item, on a path state of many slots
// in blocks of 16 with lanes that are not the stage's, equal the host's one-path C++ bit for
// bit, every field of every slot (docs/testing.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "kernels/integrator/classify_hit.h"
#include "kernels/integrator/shade_common.h"
#include "kernels/integrator/shade_surface.h"
#include "tests/lobes/lobe_harness.h"

namespace {

float bits_of(uint32_t u) {
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}

glm::vec3 unit(std::mt19937& rng) {
  std::normal_distribution<float> g(0.0f, 1.0f);
  glm::vec3 v(g(rng), g(rng), g(rng));
  return glm::normalize(v);
}

// The host's copy of a probe's path state (field-major over n slots), shaded one path at a time.
struct HostState {
  uint32_t n;
  std::vector<float> sf;
  std::vector<uint32_t> su;
  HostState(const std::vector<float>& in, uint32_t slots)
      : n(slots), sf(in.begin(), in.begin() + AW_SF_COUNT * slots), su(AW_SU_COUNT * slots) {
    std::memcpy(su.data(), in.data() + AW_SF_COUNT * slots, su.size() * 4);
  }
  PathRef path(uint32_t slot) {
    PathRef ps;
    std::memset(&ps, 0, sizeof ps);
    ps.sf = sf.data();
    ps.su = su.data();
    ps.pool = n;
    ps.slot = slot;
    return ps;
  }
};

// Every word of every slot after the stage, and each live slot's next queue (live: the
// input field after the state), the device's 16 lanes against the host: the differences,
// the first ten reported.
// `skip`: fields not compared (what one side writes that the other leaves out), numbered as
// in the probe's buffer (float fields, then AW_SF_COUNT + the uint fields).
size_t count_differences(const HostState& h, const std::vector<float>& in, const std::vector<float>& dev,
                         const std::vector<uint32_t>& q, const std::string& what,
                         const std::vector<uint32_t>& skip = {}) {
  const uint32_t n = h.n, nf = AW_SF_COUNT, nstate = AW_SF_COUNT + AW_SU_COUNT;
  size_t differ = 0;
  for (uint32_t f = 0; f < nstate; ++f)
    for (uint32_t i = 0; i < n; ++i) {
      if (std::find(skip.begin(), skip.end(), f) != skip.end()) continue;
      const void* host = f < nf ? static_cast<const void*>(&h.sf[f * n + i]) : static_cast<const void*>(&h.su[(f - nf) * n + i]);
      if (std::memcmp(host, &dev[f * n + i], 4) != 0 && differ++ < 10) {
        float v;
        std::memcpy(&v, host, 4);
        ADD_FAILURE() << what << (f < nf ? "float" : "uint") << " field " << (f < nf ? f : f - nf) << " of slot " << i
                      << ": host " << v << ", 16 lanes " << dev[f * n + i];
      }
    }
  for (uint32_t i = 0; i < n; ++i) {
    uint32_t d;
    std::memcpy(&d, &dev[nstate * n + i], 4);
    if (in[nstate * n + i] != 0.0f && d != q[i] && differ++ < 10)
      ADD_FAILURE() << what << "queue of slot " << i << ": host " << q[i] << ", 16 lanes " << d;
  }
  return differ;
}

// Next-event estimation's shadow ray and the path's continuation (Russian roulette, the cut-off,
// the ray cone, the extension ray): a state of 4096 slots, one in five not in the stage (its
// words must come back untouched), lobe samples of every kind (none, diffuse, specular,
// transmission; weights that end the path; densities 0 and infinite), lights at finite and
// infinite distances, cut-offs and bounces on both sides of rr_depth.
TEST(ShadeLanes, ShadowRayAndContinuationEqualTheHostBitForBit) {
  const uint32_t n = 4096, nf = AW_SF_COUNT, nu = AW_SU_COUNT, nstate = nf + nu, nin = 26;
  std::mt19937 rng(51206);
  std::uniform_real_distribution<float> uni(0.0f, 1.0f);
  std::vector<float> in((nstate + nin) * n);
  for (uint32_t f = 0; f < nf; ++f)
    for (uint32_t i = 0; i < n; ++i) in[f * n + i] = uni(rng);
  for (uint32_t i = 0; i < n; ++i) {
    in[AW_SF_eta_scale * n + i] = i % 7 == 0 ? 2.25f : 1.0f;
    in[AW_SF_sp_err * n + i] = 1e-5f * uni(rng);
  }
  const uint32_t flag_kinds[] = {0u, AW_LOBE_DIFFUSE_REFLECTION, AW_LOBE_SPECULAR | AW_LOBE_REFLECTION,
                                 AW_LOBE_TRANSMISSION | AW_LOBE_GLOSSY, AW_LOBE_SPECULAR | AW_LOBE_TRANSMISSION};
  for (uint32_t i = 0; i < n; ++i) {
    uint32_t u[AW_SU_COUNT];
    for (uint32_t k = 0; k < nu; ++k) u[k] = rng();
    u[AW_SU_pixel] = rng() % 100000u;
    u[AW_SU_sample] = rng() % 1024u;
    u[AW_SU_bounce] = rng() % 8u;
    u[AW_SU_flags] = rng() & 63u;
    for (uint32_t k = 0; k < nu; ++k) in[(nf + k) * n + i] = bits_of(u[k]);
    glm::vec3 p = 4.0f * glm::vec3(uni(rng), uni(rng), uni(rng)) - 2.0f, ng = unit(rng), wi = unit(rng), lwi = unit(rng);
    float w = i % 11 == 0 ? 0.0f : 1.5f * uni(rng);
    float pdf = i % 13 == 0 ? 0.0f : i % 17 == 0 ? INFINITY : 3.0f * uni(rng);
    float dist = i % 3 == 0 ? FLT_MAX : 0.1f + 5.0f * uni(rng);
    float cutoff = i % 4 == 0 ? 0.0f : 0.5f * uni(rng);
    float vals[26] = {i % 5 == 0 ? 0.0f : 1.0f, p.x, p.y, p.z, ng.x, ng.y, ng.z, wi.x, wi.y, wi.z,
                      w, w * uni(rng), w * uni(rng), pdf, bits_of(flag_kinds[rng() % 5u]),
                      i % 7 == 0 ? 1.0f / 2.25f : 1.0f, cutoff, lwi.x, lwi.y, lwi.z, dist,
                      bits_of(rng() % 9u), uni(rng), uni(rng), uni(rng), i % 2 ? 1.0f : 0.0f};
    for (uint32_t k = 0; k < nin; ++k) in[(nstate + k) * n + i] = vals[k];
  }
  RenderParams rp;
  std::memset(&rp, 0, sizeof rp);
  rp.sampler = AW_SAMPLER_SOBOL;
  rp.seed = 7u;
  rp.rr_depth = 3u;
  std::vector<float> dev = aw::lobe_test::run_device_probe("tests/probe_lanes.cl", "probe_shade_lanes", in,
                                                           nstate + 1, n, {{&rp, sizeof rp}});
  // The host: the same state, one path at a time.
  HostState h(in, n);
  std::vector<uint32_t> q(n, 0u);
  size_t live = 0, rays = 0, shadows = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const float* v = &in[nstate * n];
    auto at = [&](uint32_t k) { return v[k * n + i]; };
    auto ubits = [&](uint32_t k) {
      uint32_t u;
      std::memcpy(&u, &v[k * n + i], 4);
      return u;
    };
    if (at(0) == 0.0f) continue;
    ++live;
    PathRef ps = h.path(i);
    glm::vec3 p(at(1), at(2), at(3)), ng(at(4), at(5), at(6));
    LobeSample s;
    s.wi = glm::vec3(at(7), at(8), at(9));
    s.weight = glm::vec3(at(10), at(11), at(12));
    s.pdf = at(13);
    s.flags = ubits(14);
    s.eta_scale = at(15);
    LightSample ls;
    ls.wi = glm::vec3(at(17), at(18), at(19));
    ls.dist = at(20);
    ls.le = glm::vec3(0.0f);
    ls.pdf = 0.0f;
    ls.is_delta = 0;
    if (at(25) != 0.0f) {
      shade_emit_shadow(ps, p, ng, ls, ubits(21), glm::vec3(at(22), at(23), at(24)));
      ++shadows;
    }
    q[i] = shade_continue(ps, &rp, p, ng, s, at(16));
    rays += q[i] == AW_Q_RAY;
  }
  size_t differ = count_differences(h, in, dev, q, "");
  EXPECT_EQ(differ, 0u);
  // The cases the test means to cover all occur.
  EXPECT_GT(rays, live / 4);
  EXPECT_LT(rays, live * 3 / 4);
  EXPECT_GT(shadows, live / 3);
}

}  // namespace

namespace {

LightGpu shade_test_light(uint32_t type, glm::vec3 p, glm::vec3 u, glm::vec3 v, float radius, uint32_t flags) {
  LightGpu l;
  std::memset(&l, 0, sizeof l);
  l.type = type;
  l.flags = flags;
  store_f3(l.p, p);
  store_f3(l.u, u);
  store_f3(l.v, v);
  glm::vec3 c = glm::cross(u, v);
  l.radius = radius;
  l.area = type == AW_LIGHT_SPHERE ? 4.0f * float(M_PI) * radius * radius : glm::length(c);
  if (glm::length(c) > 0.0f) store_f3(l.n, glm::normalize(c));
  store_f3(l.radiance, glm::vec3(4.0f, 3.0f, 2.0f));
  return l;
}

// The whole diffuse shading stage (shade_surface for the diffuse lobe: its material read per
// lane, Lambert and EON, next-event estimation with MIS, the shadow ray, Russian roulette, the
// extension ray) on a path state of 4096 slots in blocks of 16, against the host one path at
// a time: every word of every slot, and the next queue. Materials differ per lane (smooth and
// rough, some with disable_bump on the diffuse lobe), so do the lights picked (a rectangle
// close enough to be sampled by solid angle, a point light, a sphere); with GI and without.
TEST(ShadeLanes, DiffuseStageEqualsTheHostBitForBit) {
  const uint32_t n = 4096, nf = AW_SF_COUNT, nu = AW_SU_COUNT, nstate = nf + nu;
  std::mt19937 rng(51208);
  std::uniform_real_distribution<float> uni(0.0f, 1.0f);
  std::vector<MaterialGpu> mats(6);
  for (size_t k = 0; k < mats.size(); ++k) {
    MaterialGpu& m = mats[k];
    std::memset(&m, 0, sizeof m);
    store_f3(m.diffuse_color, glm::vec3(uni(rng), uni(rng), uni(rng)));
    m.diffuse_weight = 0.5f + 0.5f * uni(rng);
    m.diffuse_roughness = k % 2 ? uni(rng) : 0.0f;
    m.bump_binding = k == 3 ? 0u : AW_NONE;
    m.no_bump_lobes = k == 3 ? (1u << AW_LID_DIFFUSE) : 0u;
  }
  std::vector<LightGpu> lights = {
      shade_test_light(AW_LIGHT_QUAD, {-0.5f, 1.0f, -0.5f}, {1.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}, 0.0f,
                       AW_LIGHT_RECTANGLE | AW_LIGHT_TWO_SIDED),
      shade_test_light(AW_LIGHT_POINT, {0.3f, 1.5f, 0.2f}, {0, 0, 0}, {0, 0, 0}, 0.0f, 0u),
      shade_test_light(AW_LIGHT_SPHERE, {-0.6f, 0.8f, 0.4f}, {0, 0, 0}, {0, 0, 0}, 0.2f, 0u)};
  for (size_t k = 0; k < lights.size(); ++k) {
    lights[k].select_pdf = 1.0f / 3.0f;
    lights[k].alias_q = 1.0f;
    lights[k].alias = uint32_t(k);
  }
  std::vector<float> in((nstate + 1) * n);
  for (uint32_t i = 0; i < n; ++i) {
    glm::vec3 ng = glm::normalize(glm::vec3(0.3f * (uni(rng) - 0.5f), 1.0f, 0.3f * (uni(rng) - 0.5f)));
    glm::vec3 ns = glm::normalize(ng + 0.2f * glm::vec3(uni(rng) - 0.5f, 0.0f, uni(rng) - 0.5f));
    glm::vec3 nb = glm::normalize(ng + 0.1f * glm::vec3(uni(rng) - 0.5f, 0.0f, uni(rng) - 0.5f));
    glm::vec3 d = glm::normalize(glm::vec3(uni(rng) - 0.5f, -1.0f, uni(rng) - 0.5f));
    glm::vec3 p(2.0f * uni(rng) - 1.0f, 0.6f * uni(rng), 2.0f * uni(rng) - 1.0f);
    float f[AW_SF_COUNT];
    for (uint32_t k = 0; k < nf; ++k) f[k] = uni(rng);
    f[AW_SF_ray_dx] = d.x, f[AW_SF_ray_dy] = d.y, f[AW_SF_ray_dz] = d.z;
    f[AW_SF_sp_px] = p.x, f[AW_SF_sp_py] = p.y, f[AW_SF_sp_pz] = p.z;
    f[AW_SF_sp_nx] = ns.x, f[AW_SF_sp_ny] = ns.y, f[AW_SF_sp_nz] = ns.z;
    f[AW_SF_sp_gx] = ng.x, f[AW_SF_sp_gy] = ng.y, f[AW_SF_sp_gz] = ng.z;
    f[AW_SF_sp_bx] = nb.x, f[AW_SF_sp_by] = nb.y, f[AW_SF_sp_bz] = nb.z;
    f[AW_SF_sp_err] = 1e-6f;
    f[AW_SF_eta_scale] = 1.0f;
    for (uint32_t k = 0; k < nf; ++k) in[k * n + i] = f[k];
    uint32_t u[AW_SU_COUNT];
    for (uint32_t k = 0; k < nu; ++k) u[k] = rng();
    u[AW_SU_pixel] = rng() % 100000u;
    u[AW_SU_sample] = rng() % 512u;
    u[AW_SU_bounce] = rng() % 6u;
    u[AW_SU_flags] = (rng() & (AW_PATH_SPECULAR | AW_PATH_HAS_SHADOW)) | (i % 3 ? AW_PATH_FRONT : 0u);
    u[AW_SU_material] = rng() % uint32_t(mats.size());
    for (uint32_t k = 0; k < nu; ++k) std::memcpy(&in[(nf + k) * n + i], &u[k], 4);
    in[nstate * n + i] = i % 7 == 3 ? 0.0f : 1.0f;
  }
  // The whole table (more than AW_SMALL_TABLE: each field gathered per lane), and
  // its first four with the lanes' indices folded onto them (a broadcast and a select per field).
  const std::vector<float> in_all = in;
  const std::vector<MaterialGpu> mats_all = mats;
  for (uint32_t nm : {uint32_t(mats_all.size()), AW_SMALL_TABLE})
  for (uint32_t gi : {1u, 0u}) {
    mats.assign(mats_all.begin(), mats_all.begin() + nm);
    in = in_all;
    for (uint32_t i = 0; i < n; ++i) {
      uint32_t m;
      std::memcpy(&m, &in[(nf + AW_SU_material) * n + i], 4);
      m %= nm;
      std::memcpy(&in[(nf + AW_SU_material) * n + i], &m, 4);
    }
    RenderParams rp;
    std::memset(&rp, 0, sizeof rp);
    rp.sampler = AW_SAMPLER_SOBOL;
    rp.seed = 11u;
    rp.rr_depth = 2u;
    rp.cutoff = 0.05f;
    rp.gi = gi;
    rp.num_lights = uint32_t(lights.size());
    rp.num_materials = nm;
    std::vector<float> dev = aw::lobe_test::run_device_probe(
        "tests/probe_lanes.cl", "probe_shade_surface_lanes", in, nstate + 1, n,
        {{mats.data(), mats.size() * sizeof(MaterialGpu)}, {lights.data(), lights.size() * sizeof(LightGpu)},
         {&rp, sizeof rp}});
    HostState h(in, n);
    SceneRef sc;
    std::memset(&sc, 0, sizeof sc);
    sc.materials = mats.data();
    sc.lights = lights.data();
    std::vector<uint32_t> q(n, 0u);
    size_t live = 0, rays = 0, shadows = 0;
    for (uint32_t i = 0; i < n; ++i) {
      if (in[nstate * n + i] == 0.0f) continue;
      ++live;
      q[i] = shade_surface(h.path(i), sc, &rp, AW_LID_DIFFUSE);
      rays += q[i] == AW_Q_RAY;
      shadows += (h.su[AW_SU_flags * n + i] & AW_PATH_HAS_SHADOW) != 0u;
    }
    size_t differ = count_differences(h, in, dev, q, std::to_string(nm) + " materials, gi " + std::to_string(gi) + ": ");
    EXPECT_EQ(differ, 0u) << nm << " materials, gi " << gi;
    EXPECT_GT(rays, live / 4) << nm << " materials, gi " << gi;
    EXPECT_GT(shadows, live / 4) << nm << " materials, gi " << gi;
  }
}


// The whole classification stage (classify_hit: a light hit with MIS, an escape to the
// constant environment and a soft sun, a triangle or analytic sphere hit and its shading
// point, the feature guard, incandescence of a light-sampled triangle and of a plain one
// under AO, the end of the path at max_depth, the lobe's choice among diffuse, translucency,
// both reflection lobes and refraction, with the reflections' Fresnel at the microfacet normal
// their samples draw (GGX and mirrors; dielectric, conductor, thin-walled and curve Fresnel),
// AO's queue) on a path state of 4096 slots in blocks of 16, against the host one
// path at a time: every word of every slot but those of the texture step, and the next queue.
// Lanes of a block hit different primitives, materials and lights. (The host's generic build
// has textures: its texture step writes the footprint, cone_w and sp_t*, and the material of
// every surface hit, also of a path that then ends. A program on lanes is built only for
// scenes without textures, and so are the one-path kernels beside it, which skip that step.)
TEST(ClassifyLanes, ClassificationEqualsTheHostBitForBit) {
  const uint32_t n = 4096, nf = AW_SF_COUNT, nu = AW_SU_COUNT, nstate = nf + nu;
  std::mt19937 rng(90411);
  std::uniform_real_distribution<float> uni(0.0f, 1.0f);
  // Materials: 0 white, 1 diffuse + translucency + refraction, 2 clear refraction (skip weak
  // internal reflections, refraction depth 1), 3 incandescent (the light-sampled triangle's),
  // 4 incandescent under AO (multiply, applied to incandescence), 5 black; and the reflection
  // lobes' sampled split (material_sampled_fresnel: isotropic GGX and mirrors on lanes):
  // 6 rough GGX over diffuse (dielectric Fresnel) with a second, rougher lobe (artist curve of
  // exponent 1), 7 a mirror (glossiness 1) with a conductor's Fresnel, metal, 8 glass (mirror
  // reflection locked to a refraction of IOR 1.5, skip weak internal reflections), 9 a
  // thin-walled pane (thin dielectric Fresnel), 10 a flat artist curve (exponent 0) over a
  // second, GGX lobe.
  // (The curve's exponents are 1 and 0 because pow's result is then exact on every side;
  // the host's pow and a device's may differ by an ulp elsewhere. That a device's pow rounds
  // alike on lanes and on one path is LaneMath.PowRoundsAsOnAScalar.)
  std::vector<MaterialGpu> mats(11);
  for (size_t k = 0; k < mats.size(); ++k) {
    MaterialGpu& m = mats[k];
    std::memset(&m, 0, sizeof m);
    store_f3(m.diffuse_color, glm::vec3(0.2f + 0.6f * uni(rng), 0.2f + 0.6f * uni(rng), 0.2f + 0.6f * uni(rng)));
    m.diffuse_weight = k == 5 ? 0.0f : 1.0f;
    m.refl_depth = m.refr_depth = 3u;
    m.cutout_opacity = 1.0f;
    m.tex_count = 0u;
    m.cutout_binding = m.bump_binding = AW_NONE;
  }
  mats[1].refr_weight = 0.5f;
  store_f3(mats[1].refr_color, glm::vec3(0.9f, 0.8f, 0.7f));
  mats[1].flags |= AW_MAT_TRANSLUCENCY;
  mats[1].transl_weight = 0.6f;
  store_f3(mats[1].transl_color, glm::vec3(0.5f, 0.6f, 0.7f));
  mats[2].refr_weight = 1.0f;
  mats[2].refr_ior = 1.5f;
  store_f3(mats[2].refr_color, glm::vec3(1.0f, 1.0f, 1.0f));
  mats[2].flags |= AW_MAT_SKIP_WEAK_INTERNAL;
  mats[2].refr_depth = 1u;
  store_f3(mats[3].incandescent, glm::vec3(2.0f, 1.5f, 1.0f));
  store_f3(mats[4].incandescent, glm::vec3(0.5f, 0.5f, 0.5f));
  mats[4].ao_samples = 4u;
  mats[4].ao_flags = AW_AO_MULTIPLY | AW_AO_INCANDESCENCE;
  auto reflection = [&](MaterialGpu& m, int i, float weight, float glossiness, uint32_t fresnel, float ior) {
    ReflectionGpu& r = m.refl[i];
    store_f3(r.color, glm::vec3(0.9f, 0.85f, 0.8f));
    r.weight = weight;
    r.glossiness = glossiness;
    r.brdf = AW_BRDF_GGX;
    r.fresnel_mode = fresnel;
    r.fresnel_ior = ior;
  };
  reflection(mats[6], 0, 1.0f, 0.6f, AW_FRESNEL_DIELECTRIC, 1.5f);
  reflection(mats[6], 1, 0.7f, 0.2f, AW_FRESNEL_CURVE, 0.0f);
  mats[6].refl[1].facing = 0.1f, mats[6].refl[1].perpendicular = 0.9f, mats[6].refl[1].curve = 1.0f;
  reflection(mats[7], 0, 1.0f, 1.0f, AW_FRESNEL_CONDUCTOR, 0.3f);
  mats[7].refl[0].fresnel_k = 3.0f;
  mats[7].flags |= AW_MAT_METAL;
  reflection(mats[8], 0, 1.0f, 1.0f, AW_FRESNEL_DIELECTRIC, 1.5f);
  mats[8].diffuse_weight = 0.0f;
  mats[8].refr_weight = 1.0f;
  mats[8].refr_ior = 1.5f;
  store_f3(mats[8].refr_color, glm::vec3(1.0f, 1.0f, 1.0f));
  mats[8].flags |= AW_MAT_SKIP_WEAK_INTERNAL;
  reflection(mats[9], 0, 1.0f, 0.9f, AW_FRESNEL_DIELECTRIC, 1.5f);
  mats[9].refr_weight = 0.8f;
  mats[9].refr_ior = 1.5f;
  store_f3(mats[9].refr_color, glm::vec3(0.9f, 0.95f, 1.0f));
  mats[9].flags |= AW_MAT_THIN_WALLED;
  reflection(mats[10], 0, 0.5f, 0.3f, AW_FRESNEL_CURVE, 0.0f);
  mats[10].refl[0].facing = mats[10].refl[0].perpendicular = 0.4f;
  reflection(mats[10], 1, 1.0f, 0.5f, AW_FRESNEL_DIELECTRIC, 1.33f);
  // Geometry: a floor of two triangles (with and without vertex normals), a wall whose vertex
  // normals lean away (the silhouette guards), a degenerate triangle, the light-sampled
  // triangle, and a sphere (one vertex, its centre: types/bvh.h).
  std::vector<VertexData> verts;
  auto vertex = [&](glm::vec3 p, glm::vec3 nrm, float has_n) {
    VertexData v;
    std::memset(&v, 0, sizeof v);
    v.p[0] = p.x, v.p[1] = p.y, v.p[2] = p.z;
    v.n[0] = nrm.x, v.n[1] = nrm.y, v.n[2] = nrm.z, v.n[3] = has_n;
    verts.push_back(v);
    return uint32_t(verts.size() - 1);
  };
  const glm::vec3 up(0, 1, 0);
  uint32_t f0 = vertex({-1, 0, -1}, up, 1), f1 = vertex({1, 0, -1}, glm::normalize(glm::vec3(0.1f, 1, 0)), 1),
           f2 = vertex({1, 0, 1}, up, 1), f3 = vertex({-1, 0, 1}, up, 0);
  uint32_t w0 = vertex({-1, 0, -1}, glm::normalize(glm::vec3(0, 1, 1)), 1),
           w1 = vertex({1, 0, -1}, glm::normalize(glm::vec3(0, -1, 0.2f)), 1),
           w2 = vertex({0, 2, -1}, glm::normalize(glm::vec3(0.3f, 0, 1)), 1);
  uint32_t d0 = vertex({0, 1, 0}, up, 0), d1 = vertex({0.5f, 1, 0}, up, 0), d2 = vertex({1, 1, 0}, up, 0);
  uint32_t l0 = vertex({-0.3f, 1.9f, -0.3f}, -up, 0), l1 = vertex({0.3f, 1.9f, -0.3f}, -up, 0),
           l2 = vertex({0, 1.9f, 0.3f}, -up, 0);
  VertexData sph;
  std::memset(&sph, 0, sizeof sph);
  sph.p[0] = 0.4f, sph.p[1] = 0.5f, sph.p[2] = 0.2f, sph.p[3] = 0.35f;
  sph.n[0] = 1.0f, sph.t[1] = 1.0f;
  verts.push_back(sph);
  const uint32_t sc_v = uint32_t(verts.size() - 1);
  std::vector<TriangleInfo> tris = {{{f0, f1, f2}, 0u}, {{f0, f2, f3}, 1u},  {{w0, w1, w2}, 2u},  {{d0, d1, d2}, 0u},
                                    {{l0, l1, l2}, 3u}, {{f0, f2, f3}, 4u},  {{f0, f1, f2}, 5u},  {{f0, f1, f2}, 6u},
                                    {{f0, f2, f3}, 7u}, {{w0, w1, w2}, 9u},  {{f0, f1, f2}, 10u}, {{w0, w1, w2}, 1u},
                                    {{f0, f2, f3}, 6u}, {{f0, f1, f2}, 1u}, {{sc_v, AW_SPHERE_MARK, sc_v}, 1u},
                                    {{sc_v, AW_SPHERE_MARK, sc_v}, 2u}, {{sc_v, AW_SPHERE_MARK, sc_v}, 8u}};
  const uint32_t sphere_first = 14u;
  // Lights: the soft sun (a light at infinity first), a quad, a point, a sphere, the triangle.
  LightGpu sun = shade_test_light(AW_LIGHT_SUN, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}, std::cos(0.3f), AW_LIGHT_VISIBLE);
  store_f3(sun.n, glm::normalize(glm::vec3(0.2f, 1.0f, 0.1f)));
  sun.area = 1.0f - std::cos(0.3f);
  LightGpu tri_l = shade_test_light(AW_LIGHT_TRIANGLE, {-0.3f, 1.9f, -0.3f}, {0.6f, 0, 0}, {0.3f, 0, 0.6f}, 0.0f, 0u);
  tri_l.area *= 0.5f;
  std::vector<LightGpu> lights = {
      sun,
      shade_test_light(AW_LIGHT_QUAD, {-0.5f, 1.99f, -0.5f}, {1.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}, 0.0f,
                       AW_LIGHT_RECTANGLE),
      shade_test_light(AW_LIGHT_POINT, {0.3f, 1.5f, 0.2f}, {0, 0, 0}, {0, 0, 0}, 0.0f, 0u),
      shade_test_light(AW_LIGHT_SPHERE, {-0.6f, 0.8f, 0.4f}, {0, 0, 0}, {0, 0, 0}, 0.2f, 0u), tri_l};
  for (size_t k = 0; k < lights.size(); ++k) {
    lights[k].select_pdf = 1.0f / 5.0f;
    lights[k].alias_q = 1.0f;
    lights[k].alias = uint32_t(k);
  }
  std::vector<uint32_t> tri_light(tris.size(), AW_NONE);
  tri_light[4] = 4u;
  const uint32_t hittable[] = {1u, 3u};  // lights a ray finds as lights (hit_light)

  std::vector<float> in((nstate + 1) * n);
  for (uint32_t i = 0; i < n; ++i) {
    float f[AW_SF_COUNT];
    for (uint32_t k = 0; k < nf; ++k) f[k] = uni(rng);
    uint32_t u[AW_SU_COUNT];
    for (uint32_t k = 0; k < nu; ++k) u[k] = rng();
    glm::vec3 o(2.0f * uni(rng) - 1.0f, 0.2f + 1.6f * uni(rng), 2.0f * uni(rng) - 1.0f);  // the previous vertex
    uint32_t kind = rng() % 8u;
    u[AW_SU_hit_light] = AW_NONE;
    u[AW_SU_hit_prim] = AW_NONE;
    u[AW_SU_hit_inst] = AW_NONE;
    glm::vec3 target;
    if (kind == 0) {  // a light
      uint32_t l = hittable[rng() % 2u];
      u[AW_SU_hit_light] = l;
      target = l == 1u ? glm::vec3(-0.5f + uni(rng), 1.99f, -0.5f + uni(rng))
                       : glm::vec3(-0.6f, 0.8f, 0.4f) + 0.2f * unit(rng);
    } else if (kind == 1) {  // the environment (half of them near the sun)
      target = o + (rng() % 2u ? unit(rng) : glm::normalize(glm::vec3(0.2f, 1.0f, 0.1f) + 0.2f * unit(rng)));
    } else {
      uint32_t t = rng() % uint32_t(tris.size());
      u[AW_SU_hit_prim] = t;
      if (t >= sphere_first) {
        target = glm::vec3(0.4f, 0.5f, 0.2f) + 0.35f * unit(rng);
        if (rng() % 4u == 0u) o = glm::vec3(0.4f, 0.5f, 0.2f) + 0.1f * unit(rng);  // from inside
        f[AW_SF_hit_u] = f[AW_SF_hit_v] = 0.0f;
      } else {
        float b1 = uni(rng), b2 = uni(rng);
        if (b1 + b2 > 1.0f) b1 = 1.0f - b1, b2 = 1.0f - b2;
        const TriangleInfo& ti = tris[t];
        auto pos = [&](uint32_t v) { return glm::vec3(verts[v].p[0], verts[v].p[1], verts[v].p[2]); };
        target = (1.0f - b1 - b2) * pos(ti.v[0]) + b1 * pos(ti.v[1]) + b2 * pos(ti.v[2]);
        f[AW_SF_hit_u] = b1, f[AW_SF_hit_v] = b2;
      }
    }
    glm::vec3 d = target - o;
    float dist = glm::length(d);
    d /= dist;
    f[AW_SF_ray_ox] = o.x, f[AW_SF_ray_oy] = o.y, f[AW_SF_ray_oz] = o.z;
    f[AW_SF_ray_dx] = d.x, f[AW_SF_ray_dy] = d.y, f[AW_SF_ray_dz] = d.z;
    f[AW_SF_hit_t] = dist;
    f[AW_SF_sp_px] = o.x, f[AW_SF_sp_py] = o.y, f[AW_SF_sp_pz] = o.z;
    f[AW_SF_bsdf_pdf] = rng() % 5u == 0u ? 0.0f : 4.0f * uni(rng);
    f[AW_SF_emit_scale] = rng() % 3u == 0u ? 0.5f : 1.0f;
    f[AW_SF_rad_r] = f[AW_SF_rad_g] = f[AW_SF_rad_b] = 0.0f;
    for (uint32_t k = 0; k < nf; ++k) in[k * n + i] = f[k];
    u[AW_SU_pixel] = rng() % 100000u;
    u[AW_SU_sample] = rng() % 512u;
    u[AW_SU_bounce] = rng() % 7u;
    u[AW_SU_flags] = rng() & (AW_PATH_SPECULAR | AW_PATH_FRONT | AW_PATH_HAS_SHADOW);
    if (rng() % 10u == 0u) u[AW_SU_flags] |= AW_PATH_EMITTERS_ONLY;
    u[AW_SU_depths] = (rng() % 3u) << 16;
    u[AW_SU_medium] = AW_NONE;
    u[AW_SU_material] = rng() % uint32_t(mats.size());
    for (uint32_t k = 0; k < nu; ++k) std::memcpy(&in[(nf + k) * n + i], &u[k], 4);
    in[nstate * n + i] = i % 7 == 3 ? 0.0f : 1.0f;
  }
  RenderParams rp;
  std::memset(&rp, 0, sizeof rp);
  rp.sampler = AW_SAMPLER_SOBOL;
  rp.seed = 5u;
  rp.max_depth = 5u;
  rp.num_lights = uint32_t(lights.size());
  rp.num_infinite = 1u;
  rp.has_mesh_lights = 1u;
  rp.env_radiance[0] = 0.1f, rp.env_radiance[1] = 0.2f, rp.env_radiance[2] = 0.3f;
  rp.num_materials = uint32_t(mats.size());  // above AW_SMALL_TABLE: gathered (ShadeLanes has both forms)
  std::vector<float> dev = aw::lobe_test::run_device_probe(
      "tests/probe_lanes.cl", "probe_classify_lanes", in, nstate + 1, n,
      {{tris.data(), tris.size() * sizeof(TriangleInfo)},
       {verts.data(), verts.size() * sizeof(VertexData)},
       {mats.data(), mats.size() * sizeof(MaterialGpu)},
       {lights.data(), lights.size() * sizeof(LightGpu)},
       {tri_light.data(), tri_light.size() * sizeof(uint32_t)},
       {&rp, sizeof rp}});
  HostState h(in, n);
  SceneRef sc;
  std::memset(&sc, 0, sizeof sc);
  sc.tri_info = tris.data();
  sc.verts = verts.data();
  sc.materials = mats.data();
  sc.lights = lights.data();
  sc.tri_light = tri_light.data();
  std::vector<uint32_t> q(n, 0u);
  size_t count[AW_Q_COUNT] = {};
  size_t live = 0, lit = 0;
  for (uint32_t i = 0; i < n; ++i) {
    if (in[nstate * n + i] == 0.0f) continue;
    ++live;
    q[i] = classify_hit(h.path(i), sc, &rp);
    if (q[i] < AW_Q_COUNT) ++count[q[i]];
    lit += h.sf[AW_SF_rad_r * n + i] > 0.0f;
  }
  const std::vector<uint32_t> texture_step = {AW_SF_cone_w, AW_SF_sp_tu, AW_SF_sp_tv, AW_SF_sp_tf, AW_SF_sp_tu2,
                                              AW_SF_sp_tv2, AW_SF_sp_tf2, AW_SF_COUNT + AW_SU_material};
  EXPECT_EQ(count_differences(h, in, dev, q, "", texture_step), 0u);
  // Every way out is taken, often.
  EXPECT_GT(count[AW_Q_DONE], live / 10);
  EXPECT_GT(count[AW_Q_AO], live / 100);
  for (uint32_t lid : {uint32_t(AW_LID_DIFFUSE), uint32_t(AW_LID_TRANSLUCENCY), uint32_t(AW_LID_REFLECTION),
                       uint32_t(AW_LID_REFRACTION)})
    EXPECT_GT(count[AW_Q_LOBE + lid], live / 50) << "lobe " << lid;
  // The second reflection lobe gets what the first leaves (two materials, three triangles).
  EXPECT_GT(count[AW_Q_LOBE + AW_LID_REFLECTION2], live / 200);
  std::printf("[ info     ] paths per lobe queue:");
  for (uint32_t lid = 0; lid < AW_LID_COUNT; ++lid) std::printf(" %zu", count[AW_Q_LOBE + lid]);
  std::printf(" (of %zu live)\n", live);
  EXPECT_GT(lit, live / 10);
}

}  // namespace
