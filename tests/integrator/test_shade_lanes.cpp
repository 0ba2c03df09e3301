// The shading stages' shared steps on lanes (kernels/integrator/shade_common.h and the path
// state's lane access, path_state.h): 16 paths per work-item, on a path state of many slots
// in blocks of 16 with lanes that are not the stage's, equal the host's one-path C++ bit for
// bit, every field of every slot (docs/testing.md).
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

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
size_t count_differences(const HostState& h, const std::vector<float>& in, const std::vector<float>& dev,
                         const std::vector<uint32_t>& q, const std::string& what) {
  const uint32_t n = h.n, nf = AW_SF_COUNT, nstate = AW_SF_COUNT + AW_SU_COUNT;
  size_t differ = 0;
  for (uint32_t f = 0; f < nstate; ++f)
    for (uint32_t i = 0; i < n; ++i) {
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
  for (uint32_t gi : {1u, 0u}) {
    RenderParams rp;
    std::memset(&rp, 0, sizeof rp);
    rp.sampler = AW_SAMPLER_SOBOL;
    rp.seed = 11u;
    rp.rr_depth = 2u;
    rp.cutoff = 0.05f;
    rp.gi = gi;
    rp.num_lights = uint32_t(lights.size());
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
    size_t differ = count_differences(h, in, dev, q, "gi " + std::to_string(gi) + ": ");
    EXPECT_EQ(differ, 0u) << "gi " << gi;
    EXPECT_GT(rays, live / 4) << "gi " << gi;
    EXPECT_GT(shadows, live / 4) << "gi " << gi;
  }
}

}  // namespace
