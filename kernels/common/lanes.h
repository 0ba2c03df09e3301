// Paths in SIMD lanes (issue 12): the types that shared code written "on lanes" uses, so that
// one source runs one path per call (AW_LANES = 1: the host's C++, GPUs, and every program
// built today) or W paths per call, one per lane of OpenCL's vector types (AW_LANES = 8 or
// 16: a program built for a CPU device, which runs each work-item's vector code at full SIMD
// width: docs/performance.md, "Paths in explicit lanes").
//
// At AW_LANES = 1 the types are plain float/uint/int/float2, so code written on them is the
// scalar code it replaces, bit for bit. At W > 1 every lane computes exactly what W = 1
// computes for its path, because OpenCL C gives arithmetic, comparisons, &&, ||, ! and the
// math built-ins the same meaning per component as on a scalar. The only differences, which
// the macros below hide:
// - a comparison is 0/1 on a scalar and 0/-1 per lane on a vector, so a choice per path is
//   L_SEL(mask, a, b) (m ? a : b), never `if` on a lane value;
// - any()/all() exist only for vectors (L_ANY, L_ALL);
// - conversions are casts on a scalar and convert_floatW/convert_intW on a vector (L_TO_FLOAT,
//   L_TO_INT, L_TO_UINT), bit reinterpretations as_int/as_uint/as_float and their W-lane
//   forms (L_AS_INT, L_AS_UINT, L_AS_FLOAT, L_UINT_AS_FLOAT);
// - loads and stores of W consecutive words are vloadW/vstoreW (L_LOAD, L_STORE), and a table
//   entry's field per lane one load per lane (L_GATHER).
// A program is built at one width (-DAW_LANES=16); a lane program and a scalar program built
// from the same headers are two programs, so no name is instantiated twice.
// Which shared code is written on lanes so far (docs/design.md): the samplers of
// common/rng.h, the warps, frames and MIS weight of common/sampling.h, and the robust ray
// origins of common/ray.h, the lobe contract (lobes/lobe.h) and the diffuse lobe (lobes/diffuse.h),
// and the sampling, densities and intersection of the analytic lights (lights/lights.h), the
// triangle and sphere tests (bvh/intersect_triangle.h, bvh/intersect_sphere.h) and the lane
// traversal (bvh/traverse_lanes.h), the path state's access, the ray stages, the diffuse
// shading stage and classification (integrator/), with the reflection lobes' sampled split:
// Fresnel (lobes/fresnel.h) and the GGX visible-normal sampler (lobes/microfacet.h).
#ifndef AW_COMMON_LANES_H
#define AW_COMMON_LANES_H

#include "common/compat.h"

#ifndef AW_LANES
#define AW_LANES 1
#endif

#define AW_LCAT_(a, b) a##b
#define AW_LCAT(a, b) AW_LCAT_(a, b)

// Tables of at most this many entries are read by selects on lanes (L_TABLE).
#define AW_SMALL_TABLE 4u
#if AW_LANES == 1
typedef float lfloat;
typedef uint luint;
typedef int lmask;  // a comparison's result (0 or 1)
typedef int lint;
typedef float2 lfloat2;
typedef float3 lfloat3;
#define make_lfloat2(x, y) make_float2((x), (y))
#define make_lfloat3(x, y, z) make_float3((x), (y), (z))
#define L_SEL(m, a, b) ((m) ? (a) : (b))
#define L_ANY(m) ((m) != 0)
#define L_ALL(m) ((m) != 0)
#define L_TO_FLOAT(x) ((float)(x))
#define L_TO_INT(x) ((int)(x))
#define L_TO_UINT(x) ((uint)(x))
#define L_AS_INT(x) as_int(x)
#define L_AS_FLOAT(i) as_float_i(i)
#define L_AS_UINT(x) as_uint(x)
#define L_UINT_AS_FLOAT(u) as_float(u)
#define L_LOAD(p, i) ((p)[i])
#define L_STORE(v, p, i) ((p)[i] = (v))
#define L_GATHER(T, base, i, field) ((base)[i].field)
#define L_TABLE(T, base, n, i, field) ((base)[i].field)
#define L_GATHER_V(T, base, i) ((base)[i])
#elif AW_DEVICE && (AW_LANES == 8 || AW_LANES == 16)
typedef AW_LCAT(float, AW_LANES) lfloat;
typedef AW_LCAT(uint, AW_LANES) luint;
typedef AW_LCAT(int, AW_LANES) lmask;  // a comparison's result (0 or -1 per lane)
typedef AW_LCAT(int, AW_LANES) lint;
// Two and three lane floats (a 2-D sample, a direction of W paths): each coordinate is one
// vector.
typedef struct {
  lfloat x, y;
} lfloat2;
typedef struct {
  lfloat x, y, z;
} lfloat3;
AW_FN lfloat2 make_lfloat2(lfloat x, lfloat y) {
  lfloat2 r;
  r.x = x;
  r.y = y;
  return r;
}
AW_FN lfloat3 make_lfloat3(lfloat x, lfloat y, lfloat z) {
  lfloat3 r;
  r.x = x;
  r.y = y;
  r.z = z;
  return r;
}
#define L_SEL(m, a, b) select((b), (a), (m))  // select's own order is (b, a, m)
#define L_ANY(m) any(m)
#define L_ALL(m) all(m)
#define L_TO_FLOAT(x) AW_LCAT(convert_float, AW_LANES)(x)
#define L_TO_INT(x) AW_LCAT(convert_int, AW_LANES)(x)
#define L_TO_UINT(x) AW_LCAT(convert_uint, AW_LANES)(x)
#define L_AS_INT(x) AW_LCAT(as_int, AW_LANES)(x)
#define L_AS_FLOAT(i) AW_LCAT(as_float, AW_LANES)(i)
#define L_AS_UINT(x) AW_LCAT(as_uint, AW_LANES)(x)
#define L_UINT_AS_FLOAT(u) AW_LCAT(as_float, AW_LANES)(u)
#define L_LOAD(p, i) AW_LCAT(vload, AW_LANES)((i), (p))
#define L_STORE(v, p, i) AW_LCAT(vstore, AW_LANES)((v), (i), (p))
// Field `field` of table entry i of each lane (T: float or uint), one load per lane: what a
// path reads from the scene's tables (lights, materials) when its lanes' entries differ.
#if AW_LANES == 8
#define L_GATHER(T, base, i, field)                                                                 \
  ((AW_LCAT(T, 8))((base)[(i).s0].field, (base)[(i).s1].field, (base)[(i).s2].field, (base)[(i).s3].field, \
                    (base)[(i).s4].field, (base)[(i).s5].field, (base)[(i).s6].field, (base)[(i).s7].field))
#else
#define L_GATHER(T, base, i, field)                                                                  \
  ((AW_LCAT(T, 16))((base)[(i).s0].field, (base)[(i).s1].field, (base)[(i).s2].field, (base)[(i).s3].field, \
                     (base)[(i).s4].field, (base)[(i).s5].field, (base)[(i).s6].field, (base)[(i).s7].field, \
                     (base)[(i).s8].field, (base)[(i).s9].field, (base)[(i).sa].field, (base)[(i).sb].field, \
                     (base)[(i).sc].field, (base)[(i).sd].field, (base)[(i).se].field, (base)[(i).sf].field))
#endif
// Field `field` of table entry i of each lane, from a table of n entries (the scene's lights,
// its materials): a table of at most AW_SMALL_TABLE entries is read as one broadcast per entry
// and a select per lane (i == j), not gathered: a gather is W scalar loads and W - 1 inserts,
// and the light's 19 fields alone were about a fifth of the diffuse shading stage's
// instructions on a scene of two lights (docs/performance.md, "Small light and material tables
// on lanes"). A GNU statement expression (clang's OpenCL C has them; only lane programs see it).
#define L_TABLE(T, base, n, i, field)                                                              \
  ({                                                                                               \
    AW_LCAT(T, AW_LANES) l_table_r_;                                                               \
    if ((n) <= AW_SMALL_TABLE) {                                                                   \
      l_table_r_ = (AW_LCAT(T, AW_LANES))((base)[0].field);                                        \
      for (uint l_table_j_ = 1u; l_table_j_ < (n); ++l_table_j_)                                   \
        l_table_r_ = L_SEL((i) == (luint)(l_table_j_), (AW_LCAT(T, AW_LANES))((base)[l_table_j_].field), l_table_r_); \
    } else {                                                                                       \
      l_table_r_ = L_GATHER(T, base, i, field);                                                    \
    }                                                                                              \
    l_table_r_;                                                                                    \
  })
// Entry i of each lane of a table of plain values (T: float or uint), one load per lane.
#if AW_LANES == 8
#define L_GATHER_V(T, base, i)                                                                       \
  ((AW_LCAT(T, 8))((base)[(i).s0], (base)[(i).s1], (base)[(i).s2], (base)[(i).s3], (base)[(i).s4], \
                    (base)[(i).s5], (base)[(i).s6], (base)[(i).s7]))
#else
#define L_GATHER_V(T, base, i)                                                                        \
  ((AW_LCAT(T, 16))((base)[(i).s0], (base)[(i).s1], (base)[(i).s2], (base)[(i).s3], (base)[(i).s4], \
                     (base)[(i).s5], (base)[(i).s6], (base)[(i).s7], (base)[(i).s8], (base)[(i).s9], \
                     (base)[(i).sa], (base)[(i).sb], (base)[(i).sc], (base)[(i).sd], (base)[(i).se], \
                     (base)[(i).sf]))
#endif
#else
#error "AW_LANES must be 1, or 8 or 16 in OpenCL C"
#endif

// 3-vector arithmetic on lanes. At W = 1 these are float3's own operators and dot(), so code
// written with them is the float3 code it replaces; at W > 1 each coordinate is one vector
// operation, in the same order (dot: (x + y) + z, as glm's and PoCL's).
#if AW_LANES == 1
AW_FN lfloat3 l3_add(lfloat3 a, lfloat3 b) { return a + b; }
AW_FN lfloat3 l3_sub(lfloat3 a, lfloat3 b) { return a - b; }
AW_FN lfloat3 l3_mul(lfloat3 a, lfloat3 b) { return a * b; }
AW_FN lfloat3 l3_scale(lfloat3 a, lfloat s) { return a * s; }
AW_FN lfloat l3_dot(lfloat3 a, lfloat3 b) { return dot(a, b); }
AW_FN lfloat3 l3_div(lfloat3 a, lfloat s) { return a / s; }
AW_FN lfloat3 l3_fmax(lfloat3 a, lfloat3 b) { return fmax(a, b); }
AW_FN lfloat3 l3_sel(lmask m, lfloat3 a, lfloat3 b) { return m ? a : b; }
#else
AW_FN lfloat3 l3_add(lfloat3 a, lfloat3 b) { return make_lfloat3(a.x + b.x, a.y + b.y, a.z + b.z); }
AW_FN lfloat3 l3_sub(lfloat3 a, lfloat3 b) { return make_lfloat3(a.x - b.x, a.y - b.y, a.z - b.z); }
AW_FN lfloat3 l3_mul(lfloat3 a, lfloat3 b) { return make_lfloat3(a.x * b.x, a.y * b.y, a.z * b.z); }
AW_FN lfloat3 l3_scale(lfloat3 a, lfloat s) { return make_lfloat3(a.x * s, a.y * s, a.z * s); }
AW_FN lfloat l3_dot(lfloat3 a, lfloat3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
AW_FN lfloat3 l3_div(lfloat3 a, lfloat s) { return make_lfloat3(a.x / s, a.y / s, a.z / s); }
AW_FN lfloat3 l3_fmax(lfloat3 a, lfloat3 b) { return make_lfloat3(fmax(a.x, b.x), fmax(a.y, b.y), fmax(a.z, b.z)); }
AW_FN lfloat3 l3_sel(lmask m, lfloat3 a, lfloat3 b) {
  return make_lfloat3(L_SEL(m, a.x, b.x), L_SEL(m, a.y, b.y), L_SEL(m, a.z, b.z));
}
#endif
AW_FN lfloat l_safe_sqrt(lfloat x) { return sqrt(fmax(x, (lfloat)(0.0f))); }
AW_FN lfloat3 l3_splat(lfloat x) { return make_lfloat3(x, x, x); }
AW_FN lfloat l3_max3(lfloat3 v) { return fmax(v.x, fmax(v.y, v.z)); }  // max3 of compat.h
AW_FN lfloat3 l3_neg(lfloat3 a) { return make_lfloat3(-a.x, -a.y, -a.z); }
AW_FN lfloat3 l3_fabs(lfloat3 a) { return make_lfloat3(fabs(a.x), fabs(a.y), fabs(a.z)); }
// Rec. 709 luminance, luminance() of compat.h on lanes.
AW_FN lfloat l_luminance(lfloat3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }
// A 3-vector that is the same in every lane (a triangle's vertex, a light's position): at
// W = 1 the float3 itself.
#if AW_LANES == 1
AW_FN lfloat3 l3_bcast(float3 v) { return v; }
AW_FN float l_hmin(lfloat v) { return v; }
#else
AW_FN lfloat3 l3_bcast(float3 v) { return make_lfloat3((lfloat)(v.x), (lfloat)(v.y), (lfloat)(v.z)); }
// The smallest of the lanes (a tree reduction of halves; no lane may be NaN). By selects, not
// fmin: fmin's rule for a NaN operand cost Intel's runtime a compare and a blend per step on
// top of each min (AVX-512; the traversal's sort keys, bvh/traverse_lanes.h), and without NaNs
// a select gives the same value but for which of two zeros of opposite sign, which compare equal.
AW_FN float l_hmin(lfloat v) {
#if AW_LANES == 16
  float8 h8 = v.lo < v.hi ? v.lo : v.hi;
#else
  float8 h8 = v;
#endif
  float4 h4 = h8.lo < h8.hi ? h8.lo : h8.hi;
  float2 h2 = h4.lo < h4.hi ? h4.lo : h4.hi;
  return h2.x < h2.y ? h2.x : h2.y;
}
#endif
// Component k (0, 1, 2: x, y, z) of each lane's vector, k per lane.
AW_FN lfloat l3_get(lfloat3 v, lint k) { return L_SEL(k == 0, v.x, L_SEL(k == 1, v.y, v.z)); }
// Double precision per lane, where the device has it (the host always does): the triangle
// test's exact edge cases (bvh/intersect_triangle.h).
#if !AW_DEVICE || defined(cl_khr_fp64)
#define AW_HAVE_LDOUBLE 1
#if AW_LANES == 1
typedef double ldouble;
#define L_TO_DOUBLE(x) ((double)(x))
#define L_DOUBLE_TO_FLOAT(x) ((float)(x))
#else
typedef AW_LCAT(double, AW_LANES) ldouble;
#define L_TO_DOUBLE(x) AW_LCAT(convert_double, AW_LANES)(x)
#define L_DOUBLE_TO_FLOAT(x) AW_LCAT(convert_float, AW_LANES)(x)
#endif
#else
#define AW_HAVE_LDOUBLE 0
#endif
// Three consecutive floats of a table entry per lane (a colour, a position): L_GATHER of each.
#define L_GATHER3(base, i, field) \
  make_lfloat3(L_GATHER(float, base, i, field[0]), L_GATHER(float, base, i, field[1]), L_GATHER(float, base, i, field[2]))
// cross, length and normalize are written out at every width, W = 1 included, rather than
// taken from OpenCL's built-ins (or glm's on the host): a built-in may round differently on a
// float3 and on lanes, and differently on each device (as acos did, below). These are the
// textbook forms, the ones glm uses: normalize is v times 1 / sqrt(v . v).
AW_FN lfloat3 l3_cross(lfloat3 a, lfloat3 b) {
  return make_lfloat3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
AW_FN lfloat l3_length(lfloat3 a) { return sqrt(l3_dot(a, a)); }
AW_FN lfloat3 l3_normalize(lfloat3 a) { return l3_scale(a, 1.0f / sqrt(l3_dot(a, a))); }

// arccos of x in [-1, 1], by Cephes' single-precision acosf (S. L. Moshier 1989, "Methods and
// Programs for Mathematical Functions", Cephes Math Library: asinf.c): asin's minimax
// polynomial on [-1/2, 1/2], and acos x = 2 asin(sqrt((1 - |x|) / 2)) beyond (pi minus that
// below -1/2). Why not acos(): PoCL's acos for float16 and for float round differently (an ulp,
// DiffuseLanes.* found it), and so do the host's and the device's libraries; these few
// operations round the same at every width and on every side. Error against double precision:
// tests/lobes/test_diffuse.cpp (LaneMath.AcosIsCephesAccurate).
AW_FN lfloat l_acos(lfloat x) {
  lmask below = x < -0.5f, above = x > 0.5f;
  lfloat y = L_SEL(below || above, sqrt(0.5f * (1.0f - fabs(x))), x);
  lfloat z = y * y;
  lfloat a = y + y * z * ((((4.2163199048e-2f * z + 2.4181311049e-2f) * z + 4.5470025998e-2f) * z + 7.4953002686e-2f) * z +
                          1.6666752422e-1f);  // asin y
  return L_SEL(below, M_PI_F - 2.0f * a, L_SEL(above, 2.0f * a, (M_PI_F / 2.0f) - a));
}

#endif
