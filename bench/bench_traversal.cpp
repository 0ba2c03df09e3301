// Traversal throughput: the OpenCL BVH kernel (kernels/bvh/trace_rays.cl through ClTracer)
// against Embree's rtcIntersect1 on the host, on the same ray batches:
//   primary  rays from a pinhole camera (coherent),
//   diffuse  rays: cosine-distributed from the primary hits (incoherent), the rays a path
//            tracer spends most of its time on.
// OpenCL: kernel time only (upload/download excluded), after one warm-up run, best of 3.
// Embree: the same rays with rtcIntersect1 on as many std::threads as the OpenCL device has
// compute units (so both use the same cores), and on 1 thread for reference; and with
// rtcIntersect8/rtcIntersect16 on packets of consecutive rays (what packet traversal could gain
// on these rays, docs/performance.md); best of 3.
// Embree's scene is EmbreeScene (robust mode), the one the scalar path and the tests use.
//
// Prints a Markdown table plus the machine; --out FILE writes the same text to FILE, --json
// FILE the same figures as JSON (read by scripts/bench_suite.py).
// Usage: bench_traversal [--tris N] [--scene FILE.json] [--width W] [--height H]
//                        [--device I] [--out FILE] [--json FILE]
#include <embree3/rtcore.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "host/bvh/cl_tracer.h"
#include "host/bvh/flat_bvh.h"
#include "host/cl/cl_runtime.h"
#include "host/cl/kernel_source.h"
#include "host/render/scene_pack.h"
#include "host/scene/scene.h"
#include "kernels/common/ray.h"
#include "kernels/common/sampling.h"

namespace {

using aw::RayIn;

struct Options {
  size_t tris = 1000000;
  std::string scene;
  int width = 1024, height = 1024;
  std::string device = "pocl";  // an index or a name, as archwave --device takes them
  std::string out;
  std::string json;
};

[[noreturn]] void usage(const char* msg) {
  std::fprintf(stderr,
               "bench_traversal: %s\n"
               "usage: bench_traversal [--tris N] [--scene FILE.json] [--width W] [--height H] [--device I|NAME] "
               "[--out FILE] [--json FILE]\n",
               msg);
  std::exit(2);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage(("missing value after " + a).c_str());
      return argv[++i];
    };
    auto number = [&](long lo) {
      std::string v = value();
      char* end = nullptr;
      long n = std::strtol(v.c_str(), &end, 10);
      if (!end || *end || n < lo) usage((a + " needs an integer >= " + std::to_string(lo) + ", got \"" + v + "\"").c_str());
      return n;
    };
    if (a == "--tris") o.tris = size_t(number(100));
    else if (a == "--scene") o.scene = value();
    else if (a == "--width") o.width = int(number(1));
    else if (a == "--height") o.height = int(number(1));
    else if (a == "--device") o.device = value();
    else if (a == "--out") o.out = value();
    else if (a == "--json") o.json = value();
    else if (a == "--help" || a == "-h") usage("traversal benchmark");
    else usage(("unknown option " + a).c_str());
  }
  return o;
}

struct Camera {
  glm::vec3 origin, forward, right, up;  // right/up unit length
  float tan_half_fov;
};

// ---- procedural test geometry ---------------------------------------------------------------
// A 4 × 4 grid of displaced UV spheres standing in a closed room: rays see curved, finely
// tessellated surfaces at many depths (like a real scene, unlike random triangles), every
// ray inside the room hits something, and diffuse rays bounce between spheres and walls.
void add_box_room(aw::TriangleSoup& s, glm::vec3 lo, glm::vec3 hi) {
  uint32_t b = uint32_t(s.positions.size());
  for (int k = 0; k < 8; ++k)
    s.positions.emplace_back((k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z);
  const int faces[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
  for (const auto& f : faces) {
    s.indices.emplace_back(b + f[0], b + f[1], b + f[2]);
    s.indices.emplace_back(b + f[0], b + f[2], b + f[3]);
  }
}

void add_displaced_sphere(aw::TriangleSoup& s, glm::vec3 c, float radius, int rings, std::mt19937& rng) {
  const int seg = 2 * rings;
  std::uniform_real_distribution<float> noise(-1.0f, 1.0f);
  const float k1 = 3.0f + 4.0f * (noise(rng) + 1.0f), k2 = 3.0f + 4.0f * (noise(rng) + 1.0f);
  auto point = [&](float theta, float phi) {
    float r = radius * (1.0f + 0.08f * std::sin(k1 * theta) * std::sin(k2 * phi) + 0.004f * noise(rng));
    return c + r * glm::vec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
  };
  uint32_t north = uint32_t(s.positions.size());
  s.positions.push_back(c + glm::vec3(0, radius, 0));
  uint32_t first = uint32_t(s.positions.size());
  for (int j = 1; j < rings; ++j)
    for (int i = 0; i < seg; ++i)
      s.positions.push_back(point(float(M_PI) * float(j) / float(rings), 2.0f * float(M_PI) * float(i) / float(seg)));
  uint32_t south = uint32_t(s.positions.size());
  s.positions.push_back(c - glm::vec3(0, radius, 0));
  auto at = [&](int ring, int i) { return first + uint32_t(ring * seg + i % seg); };
  for (int i = 0; i < seg; ++i) s.indices.emplace_back(north, at(0, i + 1), at(0, i));
  for (int j = 0; j + 1 < rings - 1; ++j)
    for (int i = 0; i < seg; ++i) {
      s.indices.emplace_back(at(j, i), at(j, i + 1), at(j + 1, i + 1));
      s.indices.emplace_back(at(j, i), at(j + 1, i + 1), at(j + 1, i));
    }
  for (int i = 0; i < seg; ++i) s.indices.emplace_back(south, at(rings - 2, i), at(rings - 2, i + 1));
}

aw::TriangleSoup procedural_scene(size_t target_tris, Camera* cam) {
  aw::TriangleSoup s;
  add_box_room(s, glm::vec3(-10.0f, 0.0f, -10.0f), glm::vec3(10.0f, 8.0f, 10.0f));
  // 16 spheres of 2 seg (rings - 1) + ... ≈ 4 rings² triangles each.
  const int rings = std::max(4, int(std::lround(std::sqrt(double(target_tris) / 16.0 / 4.0))));
  std::mt19937 rng(2024);
  for (int gz = 0; gz < 4; ++gz)
    for (int gx = 0; gx < 4; ++gx)
      add_displaced_sphere(s, glm::vec3(-6.0f + 4.0f * float(gx), 1.7f + 0.5f * float((gx + gz) & 1), -6.0f + 4.0f * float(gz)),
                           1.6f, rings, rng);
  cam->origin = glm::vec3(1.5f, 6.0f, 9.5f);
  cam->forward = glm::normalize(glm::vec3(0.0f, 1.2f, -1.0f) - cam->origin);
  cam->right = glm::normalize(glm::cross(cam->forward, glm::vec3(0, 1, 0)));
  cam->up = glm::cross(cam->right, cam->forward);
  cam->tan_half_fov = std::tan(0.5f * 60.0f * float(M_PI) / 180.0f);
  return s;
}

// ---- rays -------------------------------------------------------------------------------------
std::vector<RayIn> camera_rays(const Camera& cam, int w, int h) {
  std::vector<RayIn> rays(size_t(w) * size_t(h));
  const float aspect = float(w) / float(h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float sx = (2.0f * (float(x) + 0.5f) / float(w) - 1.0f) * cam.tan_half_fov * aspect;
      float sy = (1.0f - 2.0f * (float(y) + 0.5f) / float(h)) * cam.tan_half_fov;
      RayIn& r = rays[size_t(y) * size_t(w) + size_t(x)];
      r.org = cam.origin;
      r.dir = glm::normalize(cam.forward + sx * cam.right + sy * cam.up);
      r.t_min = 0.0f;
      r.t_max = std::numeric_limits<float>::infinity();
    }
  return rays;
}

struct Hit {
  float t;
  float u, v;
  int prim;
};

// Diffuse bounce rays from the primary hits: the hit point from the barycentrics (more
// accurate than org + t dir), the geometric normal turned towards the incoming ray, the
// origin pushed off the surface with offset_ray_origin (kernels/common/ray.h) and a
// cosine-distributed direction (kernels/common/sampling.h), as the diffuse lobe does.
std::vector<RayIn> diffuse_rays(const aw::TriangleSoup& s, const std::vector<RayIn>& primary,
                                const std::vector<Hit>& hits) {
  std::vector<RayIn> out;
  out.reserve(primary.size());
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  for (size_t i = 0; i < primary.size(); ++i) {
    const Hit& h = hits[i];
    if (h.prim < 0) continue;
    const glm::uvec3& t = s.indices[size_t(h.prim)];
    glm::vec3 a = s.positions[t.x], b = s.positions[t.y], c = s.positions[t.z];
    glm::vec3 p = (1.0f - h.u - h.v) * a + h.u * b + h.v * c;
    glm::vec3 n = glm::cross(b - a, c - a);
    float len = glm::length(n);
    if (!(len > 0.0f)) continue;
    n /= len;
    if (glm::dot(n, primary[i].dir) > 0.0f) n = -n;
    float3 tu, tv;
    make_frame(n, &tu, &tv);
    float2 xi = make_float2(u01(rng), u01(rng));
    RayIn r;
    // The kernels' offset (common/ray.h): the hit point's error bound along n.
    r.org = offset_ray_origin(p, n, triangle_point_error(p, a, b, c, 1.0f - h.u - h.v, h.u, h.v, float3(0.0f), n));
    r.dir = glm::normalize(frame_to_world(sample_cosine_hemisphere(xi), tu, tv, n));
    r.t_min = 0.0f;
    r.t_max = std::numeric_limits<float>::infinity();
    out.push_back(r);
  }
  return out;
}

// ---- Embree on host threads ---------------------------------------------------------------------
// Runs trace(begin, end) over [0, n) on `threads` std::threads pulling chunks of 1024 rays from a
// shared counter (load balance: incoherent rays vary a lot in cost). Each thread makes its own
// tracer with make_tracer() (holding its own Embree context). Returns wall seconds.
template <typename MakeTracer>
double run_chunks(size_t n, unsigned threads, MakeTracer make_tracer) {
  std::atomic<size_t> next{0};
  const size_t chunk = 1024;  // a multiple of every packet size below
  auto work = [&]() {
    auto trace = make_tracer();
    for (;;) {
      size_t begin = next.fetch_add(chunk);
      if (begin >= n) return;
      trace(begin, std::min(n, begin + chunk));
    }
  };
  auto t0 = std::chrono::steady_clock::now();
  std::vector<std::thread> pool;
  for (unsigned k = 1; k < threads; ++k) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// rtcIntersect1 over the batch.
double embree_trace(RTCScene scene, const std::vector<RayIn>& rays, unsigned threads, std::vector<Hit>* hits) {
  hits->assign(rays.size(), Hit{0, 0, 0, -1});
  return run_chunks(rays.size(), threads, [&]() {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    return [&, ctx](size_t begin, size_t end) mutable {
      for (size_t i = begin; i < end; ++i) {
        const RayIn& r = rays[i];
        RTCRayHit rh;
        rh.ray.org_x = r.org.x; rh.ray.org_y = r.org.y; rh.ray.org_z = r.org.z;
        rh.ray.dir_x = r.dir.x; rh.ray.dir_y = r.dir.y; rh.ray.dir_z = r.dir.z;
        rh.ray.tnear = r.t_min;
        rh.ray.tfar = r.t_max;
        rh.ray.time = 0.0f;
        rh.ray.mask = 0xffffffffu;
        rh.ray.id = 0;
        rh.ray.flags = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &ctx, &rh);
        if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) (*hits)[i] = Hit{rh.ray.tfar, rh.hit.u, rh.hit.v, int(rh.hit.primID)};
      }
    };
  });
}

// The same batch through Embree's packet interface, rtcIntersect8 or rtcIntersect16 on packets of
// N consecutive rays of the batch (for primary rays: N neighbouring pixels of one image row;
// for diffuse rays: the bounces of those pixels), with Embree's coherent-rays hint for primary
// rays. Embree's hybrid traversal (Benthin et al. 2012, "Combining Single and Packet-Ray Tracing
// for Arbitrary Ray Distributions on the Intel MIC Architecture", Sec. 4) runs a packet while
// its rays stay together and falls back to single rays when they scatter: this is the upper
// bound of what tracing a packet of N rays per SIMD instruction stream can give on these rays.
template <int N, typename RayHitN>
double embree_trace_packets(RTCScene scene, const std::vector<RayIn>& rays, unsigned threads, bool coherent,
                            std::vector<Hit>* hits,
                            void (*intersect)(const int*, RTCScene, RTCIntersectContext*, RayHitN*)) {
  hits->assign(rays.size(), Hit{0, 0, 0, -1});
  return run_chunks(rays.size(), threads, [&]() {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    if (coherent) ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    return [&, ctx](size_t begin, size_t end) mutable {
      alignas(64) RayHitN rh;
      alignas(64) int valid[N];
      for (size_t p = begin; p < end; p += N) {
        for (int k = 0; k < N; ++k) {
          size_t i = p + size_t(k);
          valid[k] = i < end ? -1 : 0;
          const RayIn& r = rays[i < end ? i : p];
          rh.ray.org_x[k] = r.org.x; rh.ray.org_y[k] = r.org.y; rh.ray.org_z[k] = r.org.z;
          rh.ray.dir_x[k] = r.dir.x; rh.ray.dir_y[k] = r.dir.y; rh.ray.dir_z[k] = r.dir.z;
          rh.ray.tnear[k] = r.t_min;
          rh.ray.tfar[k] = r.t_max;
          rh.ray.time[k] = 0.0f;
          rh.ray.mask[k] = 0xffffffffu;
          rh.ray.id[k] = 0;
          rh.ray.flags[k] = 0;
          rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
          rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
        }
        intersect(valid, scene, &ctx, &rh);
        for (int k = 0; k < N && p + size_t(k) < end; ++k)
          if (rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID)
            (*hits)[p + size_t(k)] = Hit{rh.ray.tfar[k], rh.hit.u[k], rh.hit.v[k], int(rh.hit.primID[k])};
      }
    };
  });
}

// Best of `runs` after one untimed warm-up (first-touch page faults, OpenCL first launch).
double best_of(int runs, const std::function<double()>& f) {
  f();
  double best = 1e300;
  for (int i = 0; i < runs; ++i) best = std::min(best, f());
  return best;
}

// Hit/miss disagreements, and hits on different triangles at different distances (1e-5
// relative: not a tie). A few are expected at edges (two watertight tests rounding
// differently); tests/bvh checks the exact criteria, this is a sanity check of the batch.
template <typename HitB>
double mismatch_fraction(const std::vector<Hit>& a, const std::vector<HitB>& b) {
  size_t bad = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    if ((a[i].prim < 0) != (b[i].prim < 0)) ++bad;
    else if (a[i].prim >= 0 && a[i].prim != b[i].prim &&
             std::fabs(a[i].t - b[i].t) > 1e-5f * std::max(a[i].t, b[i].t))
      ++bad;
  }
  return a.empty() ? 0.0 : double(bad) / double(a.size());
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) {
      size_t p = line.find(':');
      if (p != std::string::npos) return line.substr(line.find_first_not_of(" \t", p + 1));
    }
  return "unknown CPU";
}

}  // namespace

int main(int argc, char** argv) {
  Options opt = parse(argc, argv);
  try {
    auto now = [] { return std::chrono::steady_clock::now(); };
    auto secs = [](auto t0) { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };

    // ---- geometry and camera
    aw::TriangleSoup soup;
    Camera cam;
    std::string geometry;
    if (!opt.scene.empty()) {
      aw::Scene scene = aw::load_scene(opt.scene);
      std::vector<std::string> warnings;
      aw::PackedScene packed = aw::pack_scene(scene, &warnings);
      soup = std::move(packed.soup);
      // The batches and the hit comparison below read hits as triangles of the world mesh
      // (Embree's primID into the soup's indices); an analytic sphere or an instance would be
      // compared under another id and bounce off another triangle's normal.
      if (!soup.spheres.empty() || !soup.instances.empty())
        usage((opt.scene + ": " + std::to_string(soup.spheres.size()) + " analytic spheres and " +
               std::to_string(soup.instances.size()) +
               " instances; the traversal benchmark measures triangle scenes only (tests/bvh checks spheres and "
               "instances)")
                  .c_str());
      const RenderParams& p = packed.params;
      cam.origin = load_f3p(p.cam_origin);
      cam.forward = load_f3p(p.cam_forward);
      cam.right = load_f3p(p.cam_right);
      cam.up = load_f3p(p.cam_up);
      cam.tan_half_fov = p.tan_half_fov;
      geometry = opt.scene;
    } else {
      soup = procedural_scene(opt.tris, &cam);
      geometry = "procedural: 16 displaced UV spheres in a closed room";
    }
    std::fprintf(stderr, "geometry: %s, %zu triangles\n", geometry.c_str(), soup.indices.size());

    aw::EmbreeDevice embree;
    auto t0 = now();
    aw::FlatBvh bvh = aw::build_flat_bvh(embree, soup);
    double t_flat = secs(t0);
    t0 = now();
    aw::EmbreeScene escene(embree, soup);
    double t_escene = secs(t0);
    aw::ClRuntime rt(aw::resolve_device(opt.device, aw::list_devices()));
    t0 = now();
    aw::ClTracer tracer(rt, bvh, aw::default_kernel_dir());
    double t_cl_build = secs(t0);
    const unsigned cu = std::max(1u, rt.info().compute_units);
    std::fprintf(stderr, "flat BVH %.2fs (Embree build %.2fs + flatten %.2fs), %zu nodes, depth %d; Embree scene %.2fs; "
                         "OpenCL tracer setup %.2fs\n",
                 t_flat, bvh.build_seconds, bvh.flatten_seconds, bvh.nodes.size(), bvh.max_depth, t_escene, t_cl_build);

    // ---- ray batches: primary, then diffuse from the primary hits (Embree's)
    std::vector<RayIn> primary = camera_rays(cam, opt.width, opt.height);
    std::vector<Hit> primary_hits;
    embree_trace(escene.get(), primary, cu, &primary_hits);
    std::vector<RayIn> diffuse = diffuse_rays(soup, primary, primary_hits);

    struct Row {
      std::string kind;
      size_t rays;
      double cl_s, embree_s, embree1_s, embree8_s, embree16_s;
      double mismatch;
    };
    std::vector<Row> rows;
    for (int kind = 0; kind < 2; ++kind) {
      const std::vector<RayIn>& rays = kind == 0 ? primary : diffuse;
      Row row;
      row.kind = kind == 0 ? "primary (camera)" : "diffuse (cosine, 1 bounce)";
      row.rays = rays.size();
      std::fprintf(stderr, "tracing %zu %s rays...\n", rays.size(), row.kind.c_str());
      std::vector<TriangleHit> cl_hits;
      row.cl_s = best_of(3, [&] {
        double s = 0.0;
        cl_hits = tracer.trace(rays, false, &s);
        return s;
      });
      std::vector<Hit> e_hits;
      row.embree_s = best_of(3, [&] { return embree_trace(escene.get(), rays, cu, &e_hits); });
      std::vector<Hit> e1_hits;
      row.embree1_s = best_of(3, [&] { return embree_trace(escene.get(), rays, 1, &e1_hits); });
      std::vector<Hit> e8_hits, e16_hits;
      const bool coherent = kind == 0;
      row.embree8_s = best_of(3, [&] {
        return embree_trace_packets<8, RTCRayHit8>(escene.get(), rays, cu, coherent, &e8_hits, rtcIntersect8);
      });
      row.embree16_s = best_of(3, [&] {
        return embree_trace_packets<16, RTCRayHit16>(escene.get(), rays, cu, coherent, &e16_hits, rtcIntersect16);
      });
      // Packets must find what single rays find. Embree's packet triangle test rounds apart from
      // its single-ray one, so rays through an edge may differ (as the kernel's do: the last
      // column); more than 0.1% of rays would be a bug in the packet code above.
      if (mismatch_fraction(e1_hits, e16_hits) > 1e-3 || mismatch_fraction(e1_hits, e8_hits) > 1e-3)
        throw std::runtime_error("Embree's packet hits differ from its single-ray hits");
      row.mismatch = mismatch_fraction(e_hits, cl_hits);
      rows.push_back(row);
    }

    // ---- report
    std::ostringstream o;
    char buf[512];
    o << "## BVH traversal: OpenCL kernel vs Embree rtcIntersect1\n\n";
    o << "- CPU: " << cpu_model() << ", " << std::thread::hardware_concurrency() << " hardware threads\n";
    o << "- OpenCL device " << opt.device << ": " << rt.info().name << " (" << rt.info().platform << ", "
      << rt.info().version << "), " << cu << " compute units\n";
    o << "- Embree: " << RTC_VERSION_STRING << ", robust scene, rtcIntersect1 on " << cu
      << " threads (= compute units) and on 1 thread; rtcIntersect8/16 on packets of consecutive rays on " << cu
      << " threads (native packet support: 8 "
      << (rtcGetDeviceProperty(embree.get(), RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED) ? "yes" : "no") << ", 16 "
      << (rtcGetDeviceProperty(embree.get(), RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED) ? "yes" : "no") << ")\n";
    o << "- geometry: " << geometry << ", " << soup.indices.size() << " triangles; flat BVH " << bvh.nodes.size()
      << " nodes, depth " << bvh.max_depth << "\n";
    std::snprintf(buf, sizeof(buf), "- primary rays: %d x %d pinhole camera; diffuse rays: one per primary hit\n",
                  opt.width, opt.height);
    o << buf;
    o << "- OpenCL: kernel time only, best of 3 after a warm-up; Embree: wall time, best of 3 after a warm-up\n\n";
    std::snprintf(buf, sizeof(buf),
                  "| ray kind | rays | OpenCL Mrays/s | Embree Mrays/s (%u threads) | ratio OpenCL/Embree | "
                  "Embree 1-thread Mrays/s | Embree rtcIntersect8 Mrays/s | Embree rtcIntersect16 Mrays/s | "
                  "hit mismatch OpenCL vs Embree |\n",
                  cu);
    o << buf;
    o << "|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const Row& r : rows) {
      double cl = double(r.rays) / r.cl_s * 1e-6, em = double(r.rays) / r.embree_s * 1e-6,
             em1 = double(r.rays) / r.embree1_s * 1e-6;
      double em8 = double(r.rays) / r.embree8_s * 1e-6, em16 = double(r.rays) / r.embree16_s * 1e-6;
      std::snprintf(buf, sizeof(buf), "| %s | %zu | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.4f%% |\n", r.kind.c_str(),
                    r.rays, cl, em, cl / em, em1, em8, em16, 100.0 * r.mismatch);
      o << buf;
    }
    std::fputs(o.str().c_str(), stdout);
    if (!opt.json.empty()) {
      nlohmann::json j = {{"cpu", cpu_model()},
                          {"hardware_threads", std::thread::hardware_concurrency()},
                          {"device", rt.info().name},
                          {"compute_units", cu},
                          {"embree", RTC_VERSION_STRING},
                          {"geometry", geometry},
                          {"triangles", soup.indices.size()},
                          {"bvh_nodes", bvh.nodes.size()},
                          {"bvh_depth", bvh.max_depth},
                          {"width", opt.width},
                          {"height", opt.height},
                          {"rows", nlohmann::json::array()}};
      for (const Row& r : rows)
        j["rows"].push_back({{"kind", r.kind},
                             {"rays", r.rays},
                             {"opencl_mrays", double(r.rays) / r.cl_s * 1e-6},
                             {"embree_mrays", double(r.rays) / r.embree_s * 1e-6},
                             {"embree1_mrays", double(r.rays) / r.embree1_s * 1e-6},
                             {"embree8_mrays", double(r.rays) / r.embree8_s * 1e-6},
                             {"embree16_mrays", double(r.rays) / r.embree16_s * 1e-6},
                             {"mismatch", r.mismatch}});
      std::ofstream f(opt.json);
      f << j.dump(2) << "\n";
      if (!f) throw std::runtime_error("cannot write " + opt.json);
    }
    if (!opt.out.empty()) {
      std::ofstream f(opt.out);
      if (!f) throw std::runtime_error("cannot write " + opt.out);
      f << o.str();
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_traversal: %s\n", e.what());
    return 1;
  }
}
