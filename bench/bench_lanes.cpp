// What running W paths per work-item in explicit SIMD lanes gains on a CPU OpenCL device
// (issue 12; docs/performance.md, "Paths in explicit lanes"). bench/lanes_model.cl is built
// at W = 1 (one path per work-item: archwave's stages today) and at W = 8 and 16 (OpenCL vector
// types), from one source, and two of its kernels are timed at each width:
//   arith        64 dependent iterations of cross/normalize/dot with a data-dependent choice
//                (issue 12's micro-benchmark), 2^20 paths;
//   shade_model  the work of the diffuse shading stage on the Cornell box (next-event
//                estimation on a quad light, a cosine bounce, Russian roulette, state gathered
//                and scattered through a queue of slots), 2^18 paths (archwave's CPU pool),
//                the queue in slot order (state read with vector loads, or per lane) or
//                shuffled (per lane: the scattered order that queue appends leave);
//   compact_model the shuffled queue's paths (all 30 state words) copied into slot order;
//   sampler_sum  the renderer's own Sobol' sampler (kernels/common/rng.h, written on lanes),
//                64 2-D samples per path, 2^20 paths, against the host's C++ build of it.
// Every width must produce the same bits as W = 1 for every output (the lanes compute each
// path exactly as one work-item does), and W = 1 the same bits as the same source compiled as
// C++ on the host; the bench says so per row and exits 1 otherwise.
//
// Usage: bench_lanes [--device SPEC]... [--reps N] [--out FILE]
//   --device: as archwave's (an index or a name substring); repeatable; default every CPU
//   device. --reps: timed runs per case (default 7; the median is reported).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "host/cl/cl_runtime.h"
#include "host/cl/kernel_source.h"
#include "kernels/common/rng.h"

// The model compiled as C++ at W = 1: OpenCL C's names it uses, with OpenCL's meaning.
namespace host_model {
#define __kernel
#define __global
#ifndef M_PI_F
#define M_PI_F 3.14159265358979323846f
#endif
typedef uint32_t uint;
static thread_local uint g_global_id = 0;
static inline uint get_global_id(int) { return g_global_id; }
static inline float select(float a, float b, int c) { return c ? b : a; }
static inline uint select(uint a, uint b, int c) { return c ? b : a; }
static inline int select(int a, int b, int c) { return c ? b : a; }
static inline float as_float(uint32_t u) { float f; std::memcpy(&f, &u, 4); return f; }
static inline float as_float(int32_t u) { float f; std::memcpy(&f, &u, 4); return f; }
static inline uint as_uint(float f) { uint u; std::memcpy(&u, &f, 4); return u; }
static inline int as_int(float f) { int i; std::memcpy(&i, &f, 4); return i; }
static inline float convert_float(uint u) { return float(u); }
static inline int isfinite(float x) { return std::isfinite(x) ? 1 : 0; }
using std::copysign;
using std::fabs;
using std::fmax;
using std::fmin;
using std::sqrt;
// The model has its own small lane layer (its names predate common/lanes.h, which the sampler
// above brought in): its macros replace those of the same names here.
#undef L_SEL
#undef L_ANY
#undef L_LOAD
#undef L_STORE
#define W 1
#include "bench/lanes_model.cl"
#undef W
#undef __kernel
#undef __global
}  // namespace host_model

namespace {

// The renderer's own Sobol' sampler (kernels/common/rng.h, written on lanes): `iters` 2-D
// samples per path (sample index k, bounce k & 7, the BSDF dimension), summed per path.
const char* kSamplerKernel = R"CL(
__kernel void sampler_sum(__global const uint* pixels, __global float* out, uint iters, uint seed) {
  uint g = get_global_id(0);
  luint pixel = L_LOAD(pixels, g);
  Sampler smp = sampler_make(AW_SAMPLER_SOBOL, seed, 0u, 0u, 0u);
  lfloat acc = (lfloat)(0.0f);
  for (uint k = 0u; k < iters; ++k) {
    lfloat2 u = rng_2d(smp, pixel, (luint)(k), (luint)(k & 7u), AW_DIM_BSDF);
    acc += u.x + u.y;
  }
  L_STORE(acc, out, g);
}
)CL";

constexpr unsigned kFields = 25, kUFields = 5;

std::string read_text(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error("bench_lanes: cannot read " + path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Median seconds of `reps` launches of k over `global` work-items (after one warm-up launch);
// `reset` restores the kernel's inputs before each launch, outside the timed interval.
template <class Reset>
double time_kernel(cl::CommandQueue& q, cl::Kernel& k, size_t global, int reps, Reset reset) {
  std::vector<double> ts;
  for (int r = 0; r <= reps; ++r) {
    reset();
    auto t0 = std::chrono::steady_clock::now();
    q.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(global), cl::NDRange(64));
    q.finish();
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (r > 0) ts.push_back(s);
  }
  return median(ts);
}

// Sets a kernel's arguments in order.
template <class... A>
void set_args(cl::Kernel& k, const A&... a) {
  cl_uint i = 0;
  (k.setArg(i++, a), ...);
}

// A Cornell-box-like set of shading points: on the five walls of the unit box, facing in,
// hit by rays from inside; albedos of its white, red and green walls.
struct ShadeInput {
  std::vector<float> sf;
  std::vector<uint32_t> su;
  std::vector<float> albedo = {0.73f, 0.73f, 0.73f, 0.63f, 0.065f, 0.05f, 0.14f, 0.45f, 0.091f};
  std::vector<float> light = {0.35f, 0.999f, 0.35f, 0.3f, 0.0f, 0.0f, 0.0f, 0.0f, 0.3f,
                              0.0f,  -1.0f,  0.0f,  17.0f, 12.0f, 4.0f, 0.09f};
};

ShadeInput make_shade_input(uint32_t pool) {
  ShadeInput in;
  in.sf.assign(size_t(kFields) * pool, 0.0f);
  in.su.assign(size_t(kUFields) * pool, 0u);
  std::mt19937 rng(20261204);
  std::uniform_real_distribution<float> uni(0.0f, 1.0f);
  auto F = [&](unsigned field, uint32_t s) -> float& { return in.sf[size_t(field) * pool + s]; };
  auto U = [&](unsigned field, uint32_t s) -> uint32_t& { return in.su[size_t(field) * pool + s]; };
  for (uint32_t s = 0; s < pool; ++s) {
    int wall = int(uni(rng) * 5.0f) % 5;  // floor, ceiling, back, left, right
    float a = uni(rng), b = uni(rng);
    float p[3], n[3];
    switch (wall) {
      case 0: p[0] = a; p[1] = 0; p[2] = b; n[0] = 0; n[1] = 1; n[2] = 0; break;
      case 1: p[0] = a; p[1] = 1; p[2] = b; n[0] = 0; n[1] = -1; n[2] = 0; break;
      case 2: p[0] = a; p[1] = b; p[2] = 0; n[0] = 0; n[1] = 0; n[2] = 1; break;
      case 3: p[0] = 0; p[1] = a; p[2] = b; n[0] = 1; n[1] = 0; n[2] = 0; break;
      default: p[0] = 1; p[1] = a; p[2] = b; n[0] = -1; n[1] = 0; n[2] = 0; break;
    }
    // An incoming direction from the box's inside: towards the wall.
    float d[3] = {uni(rng) - 0.5f, uni(rng) - 0.5f, uni(rng) - 0.5f};
    float dn = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
    if (dn > 0) for (int k = 0; k < 3; ++k) d[k] -= 2.0f * dn * n[k];
    float len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int k = 0; k < 3; ++k) {
      F(0 + k, s) = p[k];
      F(3 + k, s) = n[k];
      F(6 + k, s) = d[k] / len;
      F(9 + k, s) = 0.1f + 0.9f * uni(rng);
    }
    F(12, s) = 1e-6f;
    F(13, s) = 1.0f;
    U(0, s) = uint32_t(uni(rng) * 65536.0f);
    U(1, s) = uint32_t(uni(rng) * 64.0f);
    U(2, s) = uint32_t(uni(rng) * 8.0f);
    U(3, s) = wall == 3 ? 1u : wall == 4 ? 2u : 0u;
    U(4, s) = 0u;
  }
  return in;
}

struct Options {
  std::vector<std::string> devices;
  int reps = 7;
  std::string out;
};

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "bench_lanes: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--device") opt.devices.push_back(value());
    else if (a == "--reps") opt.reps = std::max(1, std::atoi(value().c_str()));
    else if (a == "--out") opt.out = value();
    else {
      std::fprintf(stderr, "bench_lanes: unknown argument '%s'\nusage: bench_lanes [--device SPEC]... [--reps N] [--out FILE]\n",
                   a.c_str());
      return 2;
    }
  }
  try {
    std::vector<aw::DeviceInfo> all = aw::list_devices();
    std::vector<int> chosen;
    if (opt.devices.empty()) {
      for (const auto& d : all)
        if (d.type == "CPU") chosen.push_back(d.index);
    } else {
      for (const auto& s : opt.devices) chosen.push_back(aw::resolve_device(s, all));
    }
    const std::string source = read_text(std::string(ARCHWAVE_SOURCE_DIR) + "/bench/lanes_model.cl");
    const std::string rng_source = aw::assemble_kernel_source("common/rng.h", aw::default_kernel_dir());
    const uint32_t n_arith = 1u << 20, pool = 1u << 18;
    const int iters = 64;
    ShadeInput in = make_shade_input(pool);
    std::vector<uint32_t> dense(pool), shuffled(pool);
    for (uint32_t s = 0; s < pool; ++s) dense[s] = shuffled[s] = s;
    std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(7));
    std::vector<float> xyz(n_arith);
    for (uint32_t k = 0; k < n_arith; ++k) xyz[k] = float(k % 97) * 0.01f + 0.1f;

    // The same model compiled as C++ (host_model, W = 1) over the same inputs: what the device's
    // W = 1 must equal bit for bit.
    std::vector<float> host_x = xyz, host_y = xyz, host_z = xyz;
    for (uint32_t k = 0; k < n_arith; ++k) {
      host_model::g_global_id = k;
      host_model::arith(host_x.data(), host_y.data(), host_z.data(), iters);
    }
    std::vector<uint32_t> sampler_pixels(n_arith);
    std::vector<float> host_sums(n_arith);
    {
      std::mt19937 prng(99);
      Sampler smp = sampler_make(AW_SAMPLER_SOBOL, 7u, 0u, 0u, 0u);
      for (uint32_t k = 0; k < n_arith; ++k) {
        sampler_pixels[k] = uint32_t(prng() % 4000000u);
        float acc = 0.0f;
        for (uint32_t j = 0; j < uint32_t(iters); ++j) {
          float2 u = rng_2d(smp, sampler_pixels[k], j, j & 7u, AW_DIM_BSDF);
          acc += u.x + u.y;
        }
        host_sums[k] = acc;
      }
    }
    std::vector<float> host_sf[2];
    std::vector<uint32_t> host_su[2], host_q[2];
    for (int o = 0; o < 2; ++o) {  // 0: slot order, 1: shuffled
      host_sf[o] = in.sf;
      host_su[o] = in.su;
      host_q[o].assign(pool, 0u);
      const std::vector<uint32_t>& qv = o == 0 ? dense : shuffled;
      for (uint32_t k = 0; k < pool; ++k) {
        host_model::g_global_id = k;
        host_model::shade_model(host_sf[o].data(), host_su[o].data(), in.albedo.data(), qv.data(), host_q[o].data(),
                                in.light.data(), pool, pool, 3u);
      }
    }

    std::ostringstream table;
    table << "| device | W | arith (G iterations/s) | renderer's Sobol' sampler (M 2-D samples/s) | shade, slot order, vector loads (M paths/s) | "
             "shade, slot order, per-lane loads | shade, shuffled queue | compaction (M paths/s) | "
             "bits equal (W = 1: to the C++ build; W > 1: to W = 1) |\n|---|---:|---:|---:|---:|---:|---:|---:|---|\n";
    bool all_equal = true;
    for (int dev : chosen) {
      aw::ClRuntime rt(dev);
      std::string dev_name = rt.info().platform.find("Portable") != std::string::npos ? "PoCL" : rt.info().platform;
      std::vector<float> ref_arith, ref_sf[3];
      std::vector<uint32_t> ref_su[3], ref_q[3];
      for (int w : {1, 8, 16}) {
        cl::Program prog = rt.build(source, "-DW=" + std::to_string(w));
        cl::Program prog_c = rt.build(source, "-DCONTIG=1 -DW=" + std::to_string(w));
        cl::CommandQueue& q = rt.queue();
        // arith
        cl::Buffer bx = rt.buffer("x", n_arith * 4), by = rt.buffer("y", n_arith * 4), bz = rt.buffer("z", n_arith * 4);
        cl::Kernel ka(prog, "arith");
        set_args(ka, bx, by, bz, iters);
        std::vector<float> out_x(n_arith);
        double t_arith = time_kernel(q, ka, n_arith / w, opt.reps, [&] {
          for (cl::Buffer* b : {&bx, &by, &bz}) q.enqueueWriteBuffer(*b, CL_TRUE, 0, n_arith * 4, xyz.data());
        });
        q.enqueueReadBuffer(bx, CL_TRUE, 0, n_arith * 4, out_x.data());
        bool equal = true;
        if (w == 1) ref_arith = out_x;
        equal = std::memcmp((w == 1 ? host_x : ref_arith).data(), out_x.data(), n_arith * 4) == 0;
        // the renderer's sampler
        cl::Program prog_s = rt.build("#define AW_LANES " + std::to_string(w) + "\n" + rng_source + kSamplerKernel, "");
        cl::Buffer bpix = rt.buffer("pixels", n_arith * 4, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                    const_cast<uint32_t*>(sampler_pixels.data()));
        cl::Buffer bsum = rt.buffer("sums", n_arith * 4);
        cl::Kernel kr(prog_s, "sampler_sum");
        set_args(kr, bpix, bsum, uint32_t(iters), 7u);
        double t_sampler = time_kernel(q, kr, n_arith / w, opt.reps, [] {});
        std::vector<float> sums(n_arith);
        q.enqueueReadBuffer(bsum, CL_TRUE, 0, n_arith * 4, sums.data());
        equal = equal && std::memcmp(host_sums.data(), sums.data(), n_arith * 4) == 0;
        // shade_model, dense and queued
        // order 0: slot order, vector loads (CONTIG); 1: slot order, per-lane access; 2: shuffled.
        double shade_rate[3];
        for (int order = 0; order < 3; ++order) {
          const std::vector<uint32_t>& qv = order == 2 ? shuffled : dense;
          cl::Buffer sf = rt.buffer("sf", in.sf.size() * 4), su = rt.buffer("su", in.su.size() * 4);
          cl::Buffer alb = rt.buffer("albedo", in.albedo.size() * 4, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                     in.albedo.data());
          cl::Buffer light = rt.buffer("light", in.light.size() * 4, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                       in.light.data());
          cl::Buffer queue = rt.buffer("queue", pool * 4, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                       const_cast<uint32_t*>(qv.data()));
          cl::Buffer outq = rt.buffer("out_q", pool * 4);
          cl::Kernel ks(order == 0 ? prog_c : prog, "shade_model");
          set_args(ks, sf, su, alb, queue, outq, light, pool, pool, 3u);
          shade_rate[order] = pool / time_kernel(q, ks, pool / w, opt.reps, [&] {
            q.enqueueWriteBuffer(sf, CL_TRUE, 0, in.sf.size() * 4, in.sf.data());
            q.enqueueWriteBuffer(su, CL_TRUE, 0, in.su.size() * 4, in.su.data());
          }) / 1e6;
          std::vector<float> o_sf(in.sf.size());
          std::vector<uint32_t> o_su(in.su.size()), o_q(pool);
          q.enqueueReadBuffer(sf, CL_TRUE, 0, o_sf.size() * 4, o_sf.data());
          q.enqueueReadBuffer(su, CL_TRUE, 0, o_su.size() * 4, o_su.data());
          q.enqueueReadBuffer(outq, CL_TRUE, 0, pool * 4, o_q.data());
          if (w == 1) {
            ref_sf[order] = o_sf;
            ref_su[order] = o_su;
            ref_q[order] = o_q;
            int o = order == 2 ? 1 : 0;
            equal = equal && std::memcmp(host_sf[o].data(), o_sf.data(), o_sf.size() * 4) == 0 &&
                    std::memcmp(host_su[o].data(), o_su.data(), o_su.size() * 4) == 0 &&
                    std::memcmp(host_q[o].data(), o_q.data(), pool * 4) == 0;
          } else {
            equal = equal && std::memcmp(ref_sf[order].data(), o_sf.data(), o_sf.size() * 4) == 0 &&
                    std::memcmp(ref_su[order].data(), o_su.data(), o_su.size() * 4) == 0 &&
                    std::memcmp(ref_q[order].data(), o_q.data(), pool * 4) == 0;
          }
        }
        // compact_model: the shuffled queue's paths copied into slot order.
        double compact_rate;
        {
          cl::Buffer sf = rt.buffer("sf", in.sf.size() * 4, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, in.sf.data());
          cl::Buffer su = rt.buffer("su", in.su.size() * 4, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, in.su.data());
          cl::Buffer sf2 = rt.buffer("sf_out", in.sf.size() * 4), su2 = rt.buffer("su_out", in.su.size() * 4);
          cl::Buffer queue = rt.buffer("queue", pool * 4, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, shuffled.data());
          cl::Kernel kc(prog, "compact_model");
          set_args(kc, sf, su, queue, sf2, su2, pool, pool);
          compact_rate = pool / time_kernel(q, kc, pool / w, opt.reps, [] {}) / 1e6;
          std::vector<float> o_sf(in.sf.size());
          q.enqueueReadBuffer(sf2, CL_TRUE, 0, o_sf.size() * 4, o_sf.data());
          for (uint32_t k = 0; k < pool && equal; ++k)
            equal = std::memcmp(&o_sf[k], &in.sf[shuffled[k]], 4) == 0;  // field 0 moved exactly
        }
        all_equal = all_equal && equal;
        char row[256];
        std::snprintf(row, sizeof row, "| %s | %d | %.3f | %.1f | %.1f | %.1f | %.1f | %.1f | %s |\n", dev_name.c_str(), w,
                      double(n_arith) * iters / t_arith / 1e9, double(n_arith) * iters / t_sampler / 1e6, shade_rate[0], shade_rate[1], shade_rate[2], compact_rate,
                      equal ? "yes" : "NO");
        table << row;
        std::fputs(row, stderr);
      }
    }
    std::printf("%s", table.str().c_str());
    if (!opt.out.empty()) std::ofstream(opt.out) << table.str();
    if (!all_equal) {
      std::fprintf(stderr, "bench_lanes: a width computed different bits from W = 1\n");
      return 1;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_lanes: %s\n", e.what());
    return 1;
  }
  return 0;
}
