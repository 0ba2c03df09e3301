// The film's sums: exact, so the image does not depend on the order samples arrive in.
//
// Each pixel's channel sum is a 128-bit unsigned fixed-point number (two 64-bit words, low
// first) in units of 2^-AW_FILM_FRAC_BITS. A sample value (a finite float in [0, 2^60), which
// path_result guarantees: accumulate.h) converts to that grid with integer operations only:
// exactly when its lowest mantissa bit is at or above 2^-40, rounded to nearest (ties up)
// below, so anything under 4.5e-13 counts as 0. Sums of such integers are exact and
// associative. That is what makes
//   - parts of one render (--sample-range, --pixel-bounds) merge bit for bit into the single
//     render (archwave merge adds the integers: docs/production.md),
//   - a resumed render equal the uninterrupted one bit for bit,
//   - the wavefront, whatever its batches, and the scalar path, whatever its thread split,
//     sum the same samples to the same bits.
// A float running sum (the previous film) has none of these: (a + b) + c != a + (b + c).
// Headroom: a sample is below 2^100 on this grid, so 2^28 samples per pixel cannot overflow.
// The conversion back (film_value) is done once, on the host, in double precision.
#ifndef AW_INTEGRATOR_FILM_H
#define AW_INTEGRATOR_FILM_H

#include "common/compat.h"

#define AW_FILM_FRAC_BITS 40
// Largest sample value the film takes (2^60); path_result discards larger ones as it does
// Inf: no scene's radiance is near it, only a numerical blow-up is.
#define AW_FILM_MAX_SAMPLE 1.152921504606846976e18f
#define AW_FILM_WORDS 6  // per pixel: R lo, R hi, G lo, G hi, B lo, B hi

// v (finite, 0 <= v < AW_FILM_MAX_SAMPLE) on the grid, as two words.
AW_FN void film_grid(float v, ulong* lo_out, ulong* hi_out) {
  uint bits = as_uint(v);
  uint e = (bits >> 23) & 0xffu;
  ulong m = (ulong)(bits & 0x7fffffu);
  if (e != 0u) m |= 0x800000ul;  // the implicit bit of a normal number
  else e = 1u;                   // subnormal: m * 2^(1 - 150)
  // v = m * 2^(e - 150), so on the grid v = m * 2^(e - 150 + FRAC).
  int sh = (int)e - 150 + AW_FILM_FRAC_BITS;
  ulong lo, hi;
  if (sh >= 0) {
    // m < 2^24 and sh <= 60 + 40 - 24 for v < 2^60: at most 100 bits, across the two words.
    if (sh >= 64) {
      lo = 0ul;
      hi = m << (uint)(sh - 64);
    } else {
      lo = m << (uint)sh;
      hi = sh == 0 ? 0ul : (m >> (uint)(64 - sh));
    }
  } else {
    int r = -sh;  // round m / 2^r to nearest, ties up; m < 2^24 so r >= 25 gives 0
    lo = r >= 25 ? 0ul : ((m + (1ul << (uint)(r - 1))) >> (uint)r);
    hi = 0ul;
  }
  *lo_out = lo;
  *hi_out = hi;
}

// Adds v (finite, 0 <= v < AW_FILM_MAX_SAMPLE) to the 128-bit sum at w[0] (low), w[1] (high).
AW_FN void film_add_channel(AW_GLOBAL ulong* w, float v) {
  ulong lo, hi;
  film_grid(v, &lo, &hi);
  ulong sum_lo = w[0] + lo;
  w[1] = w[1] + hi + (sum_lo < lo ? 1ul : 0ul);
  w[0] = sum_lo;
}

// The same for a value of either sign (|v| < AW_FILM_MAX_SAMPLE): the sum is two's
// complement, and stays exact and order-independent (the AOVs: integrator/aov.h).
AW_FN void film_add_signed(AW_GLOBAL ulong* w, float v) {
  ulong lo, hi;
  film_grid(fabs(v), &lo, &hi);
  if (v < 0.0f) {  // w - q
    ulong borrow = w[0] < lo ? 1ul : 0ul;
    w[0] = w[0] - lo;
    w[1] = w[1] - hi - borrow;
  } else {
    ulong sum_lo = w[0] + lo;
    w[1] = w[1] + hi + (sum_lo < lo ? 1ul : 0ul);
    w[0] = sum_lo;
  }
}

// Adds a sample's RGB to a pixel's AW_FILM_WORDS words.
AW_FN void film_add(AW_GLOBAL ulong* px, float3 v) {
  film_add_channel(px + 0, v.x);
  film_add_channel(px + 2, v.y);
  film_add_channel(px + 4, v.z);
}

#endif
