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
// - int -> float conversion is a cast on a scalar and convert_floatW on a vector (L_TO_FLOAT);
// - loads and stores of W consecutive words are vloadW/vstoreW (L_LOAD, L_STORE).
// A program is built at one width (-DAW_LANES=16); a lane program and a scalar program built
// from the same headers are two programs, so no name is instantiated twice.
// Which shared code is written on lanes so far: the samplers of common/rng.h.
#ifndef AW_COMMON_LANES_H
#define AW_COMMON_LANES_H

#include "common/compat.h"

#ifndef AW_LANES
#define AW_LANES 1
#endif

#define AW_LCAT_(a, b) a##b
#define AW_LCAT(a, b) AW_LCAT_(a, b)

#if AW_LANES == 1
typedef float lfloat;
typedef uint luint;
typedef int lmask;  // a comparison's result (0 or 1)
typedef float2 lfloat2;
#define make_lfloat2(x, y) make_float2((x), (y))
#define L_SEL(m, a, b) ((m) ? (a) : (b))
#define L_ANY(m) ((m) != 0)
#define L_ALL(m) ((m) != 0)
#define L_TO_FLOAT(x) ((float)(x))
#define L_LOAD(p, i) ((p)[i])
#define L_STORE(v, p, i) ((p)[i] = (v))
#elif AW_DEVICE && (AW_LANES == 8 || AW_LANES == 16)
typedef AW_LCAT(float, AW_LANES) lfloat;
typedef AW_LCAT(uint, AW_LANES) luint;
typedef AW_LCAT(int, AW_LANES) lmask;  // a comparison's result (0 or -1 per lane)
// Two lane floats (a 2-D sample of W paths): x and y are each one vector.
typedef struct {
  lfloat x, y;
} lfloat2;
AW_FN lfloat2 make_lfloat2(lfloat x, lfloat y) {
  lfloat2 r;
  r.x = x;
  r.y = y;
  return r;
}
#define L_SEL(m, a, b) select((b), (a), (m))  // select's own order is (b, a, m)
#define L_ANY(m) any(m)
#define L_ALL(m) all(m)
#define L_TO_FLOAT(x) AW_LCAT(convert_float, AW_LANES)(x)
#define L_LOAD(p, i) AW_LCAT(vload, AW_LANES)((i), (p))
#define L_STORE(v, p, i) AW_LCAT(vstore, AW_LANES)((v), (i), (p))
#else
#error "AW_LANES must be 1, or 8 or 16 in OpenCL C"
#endif

#endif
