// One physics source for two compilers: this header lets every file under kernels/ compile
// unchanged as OpenCL C 1.2 (device) and as C++17 (host scalar path, tests).
//
// Rules for shared code (docs/design.md, "Rules for shared code"):
// - functions are AW_FN (static inline), snake_case, no overloads in shared code;
// - pointers into buffers are AW_GLOBAL (empty on the host);
// - float3 is a math type only: OpenCL's float3 is 16 bytes, so structs shared with the host
//   (kernels/types/) store plain float[3] and convert with load_f3/store_f3;
// - only the math names mapped below are used, so both sides round the same way
//   (no fast-math on either side).
#ifndef AW_COMMON_COMPAT_H
#define AW_COMMON_COMPAT_H

#ifdef __OPENCL_C_VERSION__
/* ------------------------------- OpenCL C ------------------------------------------------ */
#define AW_DEVICE 1
// OpenCL C lets the compiler fuse a*b+c into an FMA and PoCL does; the host build does not
// (-ffp-contract=off). Fused and unfused results differ in the last bit, which breaks the
// bit-identical host/device comparisons and the edge-function symmetry the watertight
// triangle test relies on (tests/bvh found both). So contraction is off on both sides.
#pragma OPENCL FP_CONTRACT OFF
#define AW_FN static inline
#define AW_GLOBAL __global
// Invariant checks cost nothing on the device (see the host's definition below).
#define AW_KERNEL_ASSERT(x) ((void)0)

#define make_float2(x, y) ((float2)((x), (y)))
#define make_float3(x, y, z) ((float3)((x), (y), (z)))
#define make_float4(x, y, z, w) ((float4)((x), (y), (z), (w)))
#define make_int3(x, y, z) ((int3)((x), (y), (z)))

#ifndef M_PI_F
#define M_PI_F 3.14159265358979323846f
#endif

// Kernel attribute: do not vectorise this kernel across work-items (Intel's CPU runtime, its
// cl_intel_vec_len_hint extension with length 1; nothing elsewhere). For the ray stages, whose
// gathers lose when vectorised: measured in integrator/kernels.cl and docs/performance.md.
#if defined(cl_intel_vec_len_hint)
#define AW_SCALAR_KERNEL __attribute__((intel_vec_len_hint(1)))
#else
#define AW_SCALAR_KERNEL
#endif

#else
/* --------------------------------- C++ host ---------------------------------------------- */
#include <glm/glm.hpp>

#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <algorithm>

#define AW_DEVICE 0
#define AW_FN static inline
#define AW_GLOBAL

// Invariant checks of the shared code, as Cycles' kernel_assert: compiled out of the device
// build, and checked wherever the same code runs on the host (the scalar path, the tests),
// in every build type: a broken invariant there names the file and line and aborts instead
// of rendering a wrong image. Only cheap checks belong here (they run per path and stage).
[[noreturn]] static inline void aw_kernel_assert_failed(const char* what, const char* file, int line) {
  std::fprintf(stderr, "archwave: kernel invariant failed: %s (%s:%d)\n", what, file, line);
  std::abort();
}
#define AW_KERNEL_ASSERT(x) ((x) ? (void)0 : aw_kernel_assert_failed(#x, __FILE__, __LINE__))

typedef glm::vec2 float2;
typedef glm::vec3 float3;
typedef glm::vec4 float4;
typedef glm::ivec3 int3;
typedef uint32_t uint;
typedef uint64_t ulong;
typedef uint8_t uchar;
typedef uint16_t ushort;

using glm::cross;
using glm::dot;
using glm::length;
using glm::normalize;
using std::fabs;
using std::fmax;
using std::fmin;
using std::sqrt;
using std::exp;
using std::log;
using std::log2;
using std::pow;
using std::sin;
using std::cos;
using std::tan;
using std::acos;
using std::asin;
using std::atan2;
using std::floor;
using std::ceil;
using std::isfinite;
using std::isnan;
using std::copysign;
using std::fma;
using std::max;
using std::min;

#ifndef M_PI_F
#define M_PI_F 3.14159265358979323846f
#endif

static inline float2 make_float2(float x, float y) { return float2(x, y); }
static inline float3 make_float3(float x, float y, float z) { return float3(x, y, z); }
static inline float4 make_float4(float x, float y, float z, float w) { return float4(x, y, z, w); }
static inline int3 make_int3(int x, int y, int z) { return int3(x, y, z); }

// OpenCL built-ins the shared code uses, with OpenCL's semantics.
static inline float clamp(float x, float lo, float hi) { return std::fmin(std::fmax(x, lo), hi); }
static inline float mix(float a, float b, float t) { return a + (b - a) * t; }
static inline float3 fmin(float3 a, float3 b) { return glm::min(a, b); }
static inline float3 fmax(float3 a, float3 b) { return glm::max(a, b); }
static inline float3 fabs(float3 a) { return glm::abs(a); }
static inline uint as_uint(float f) { uint u; std::memcpy(&u, &f, 4); return u; }
static inline int as_int(float f) { int i; std::memcpy(&i, &f, 4); return i; }
static inline float as_float(uint u) { float f; std::memcpy(&f, &u, 4); return f; }
static inline float as_float_i(int i) { float f; std::memcpy(&f, &i, 4); return f; }
static inline uint mul_hi(uint a, uint b) { return (uint)(((uint64_t)a * b) >> 32); }
#endif

#ifdef __OPENCL_C_VERSION__
#define as_float_i(x) as_float(x)
#endif

/* ------------------------- shared helpers (both sides) ------------------------------------ */

// Storage <-> math: shared structs keep float[3], math uses float3.
// "No index" in every index field of the path state and the scene (a light, a triangle, a lobe).
#define AW_NONE 0xffffffffu

AW_FN float3 load_f3(const AW_GLOBAL float* p) { return make_float3(p[0], p[1], p[2]); }
AW_FN float3 load_f3p(const float* p) { return make_float3(p[0], p[1], p[2]); }
AW_FN void store_f3(AW_GLOBAL float* p, float3 v) { p[0] = v.x; p[1] = v.y; p[2] = v.z; }

// min/max without IEEE NaN handling: one minss/maxss instead of fmin's compare-unordered and
// blend (which dominated the BVH slab test on PoCL). Only for operands that cannot be NaN.
AW_FN float min_nn(float a, float b) { return a < b ? a : b; }
AW_FN float max_nn(float a, float b) { return a > b ? a : b; }

AW_FN float max3(float3 v) { return fmax(v.x, fmax(v.y, v.z)); }
AW_FN float luminance(float3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }
AW_FN float sqr(float x) { return x * x; }
AW_FN float safe_sqrt(float x) { return sqrt(fmax(x, 0.0f)); }
AW_FN int finite3(float3 v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

#endif  // AW_COMMON_COMPAT_H
