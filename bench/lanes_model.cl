// Paths in explicit SIMD lanes: a measurement for issue 12 (docs/performance.md, "Paths in
// explicit lanes"). Built by bench/bench_lanes.cpp with -DW=1, 8 or 16. One source: every
// function below is written once on the lane types (lf, lu, lm) of the small lane layer at the
// top; W = 1 makes them plain float/uint/int (one path per work-item, what archwave's stages
// do today), W = 8 or 16 makes them OpenCL vector types (W paths per work-item). OpenCL C's
// arithmetic, comparisons, &&, || and ! and the math built-ins have the same meaning on a
// scalar and on each component of a vector, and select() takes a comparison's result on both;
// only any()/all() and loads/stores differ, and the layer hides those. Each lane therefore
// computes exactly what W = 1 computes for that path: the bench compares every output bit.
//
// This is a model, not a renderer stage: `shade_model` does the work of archwave's diffuse
// shading stage on the Cornell box (kernels/integrator/shade_surface.h with the Lambert lobe and
// one quad light; next-event estimation by area with the power heuristic, a cosine-weighted
// bounce, Russian roulette, the shadow ray and the extension ray written to the path state) with
// the same kinds of memory traffic (state gathered and scattered through a queue of slots, the
// albedo gathered by material), but with a hash instead of the Sobol' sampler and without the
// material system's generality. Both widths run this same model, so their ratio is what lanes
// gain on this kind of work (docs/performance.md compares the renderer's own stage).
//
// As C++ (bench_lanes.cpp includes this file at W = 1 after a few definitions of OpenCL C's
// names), the same functions run on the host: the third instantiation a lane design needs
// (the host's scalar path), compared bit for bit with the device's.
//
// -DCONTIG=1: the queue is known to be slot order (a dense launch), so the state's fields are
// read with vector loads and written with a masked read-modify-write instead of per-lane
// gathers and scatters; the table is still gathered per lane.
#ifdef __OPENCL_C_VERSION__
#pragma OPENCL FP_CONTRACT OFF
#endif
#ifndef W
#define W 16
#endif
#define L_CAT_(a, b) a##b
#define L_CAT(a, b) L_CAT_(a, b)

/* ----------------------------------- the lane layer ----------------------------------------- */
#if W == 1
typedef float lf;
typedef uint lu;
typedef int lm;  // a comparison's result: 0 or 1
#define L_ANY(m) ((m) != 0)
#define L_TRUE 1  // a mask with every lane set
#define L_U2F(x) convert_float(x)
#define L_AS_F(x) as_float(x)
#define L_AS_U(x) as_uint(x)
#define L_AS_I(x) as_int(x)
typedef int li;
#define L_LOAD(p, i) ((p)[i])  // W consecutive words from p + i * W (any 32-bit type)
#define L_STORE(v, p, i) ((p)[i] = (v))
#else
typedef L_CAT(float, W) lf;
typedef L_CAT(uint, W) lu;
typedef L_CAT(int, W) lm;  // a comparison's result: -1 or 0 per lane
typedef L_CAT(int, W) li;
#define L_ANY(m) any(m)
#define L_TRUE ((lm)(-1))
#define L_U2F(x) L_CAT(convert_float, W)(x)
#define L_AS_I(x) L_CAT(as_int, W)(x)
#define L_AS_F(x) L_CAT(as_float, W)(x)
#define L_AS_U(x) L_CAT(as_uint, W)(x)
#define L_LOAD(p, i) L_CAT(vload, W)((i), (p))
#define L_STORE(v, p, i) L_CAT(vstore, W)((v), (i), (p))
#endif
// m ? a : b per lane (select's own argument order is (b, a, m)).
#define L_SEL(m, a, b) select((b), (a), (m))

// Per-lane gather of 32-bit words (a table such as the materials' albedos, or the state through
// a queue of slots). Written as one vector literal, PoCL emits a gather instruction (4.2 against
// 3.6 M paths/s through a private array and a loop: the shuffled queue, this bench).
static inline lf l_gather_idx(const __global float* a, lu idx) {
#if W == 1
  return a[idx];
#elif W == 16
  return (float16)(a[idx.s0], a[idx.s1], a[idx.s2], a[idx.s3], a[idx.s4], a[idx.s5], a[idx.s6], a[idx.s7],
                   a[idx.s8], a[idx.s9], a[idx.sa], a[idx.sb], a[idx.sc], a[idx.sd], a[idx.se], a[idx.sf]);
#elif W == 8
  return (float8)(a[idx.s0], a[idx.s1], a[idx.s2], a[idx.s3], a[idx.s4], a[idx.s5], a[idx.s6], a[idx.s7]);
#else
#error "W must be 1, 8 or 16"
#endif
}

// A state field of the paths in slots idx: one vector load where the slots are this
// work-item's W consecutive ones (CONTIG), else per lane.
static inline lf l_gather(const __global float* a, lu idx) {
#ifdef CONTIG
  if (CONTIG) return L_LOAD(a, get_global_id(0));
#endif
  return l_gather_idx(a, idx);
}

// Writes v to the lanes where m holds: a read-modify-write of one vector for consecutive slots
// (CONTIG), else a store per active lane.
static inline void l_scatter(__global float* a, lu idx, lf v, lm m) {
#ifdef CONTIG
  if (CONTIG) {
    L_STORE(L_SEL(m, v, L_LOAD(a, get_global_id(0))), a, get_global_id(0));
    return;
  }
#endif
#if W == 1
  if (m) a[idx] = v;
#else
  uint ix[W];
  float t[W];
  int mk[W];
  L_STORE(idx, ix, 0);
  L_STORE(v, t, 0);
  L_STORE(m, mk, 0);
  for (int k = 0; k < W; ++k)
    if (mk[k]) a[ix[k]] = t[k];
#endif
}

// The same for uint fields: the words' bits move unchanged through float lanes (loads,
// stores and selects do not touch them).
static inline lu l_gather_u(const __global uint* a, lu idx) { return L_AS_U(l_gather((const __global float*)a, idx)); }
static inline void l_scatter_u(__global uint* a, lu idx, lu v, lm m) {
  l_scatter((__global float*)a, idx, L_AS_F(v), m);
}

// Three lanes-wide floats: a 3-vector of W paths (x, y and z each one SIMD register).
typedef struct {
  lf x, y, z;
} lf3;
static inline lf3 v3(lf x, lf y, lf z) {
  lf3 r;
  r.x = x;
  r.y = y;
  r.z = z;
  return r;
}
static inline lf3 v3_add(lf3 a, lf3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline lf3 v3_sub(lf3 a, lf3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline lf3 v3_mul(lf3 a, lf3 b) { return v3(a.x * b.x, a.y * b.y, a.z * b.z); }
static inline lf3 v3_scale(lf3 a, lf s) { return v3(a.x * s, a.y * s, a.z * s); }
static inline lf v3_dot(lf3 a, lf3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline lf3 v3_cross(lf3 a, lf3 b) {
  return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline lf3 v3_normalize(lf3 a) { return v3_scale(a, (lf)(1.0f) / sqrt(v3_dot(a, a))); }
static inline lf v3_max_comp(lf3 a) { return fmax(fmax(a.x, a.y), a.z); }
static inline lf3 v3_sel(lm m, lf3 a, lf3 b) { return v3(L_SEL(m, a.x, b.x), L_SEL(m, a.y, b.y), L_SEL(m, a.z, b.z)); }
static inline lf3 v3_gather(const __global float* a, uint pool, uint field, lu slot) {
  return v3(l_gather(a + field * pool, slot), l_gather(a + (field + 1u) * pool, slot),
            l_gather(a + (field + 2u) * pool, slot));
}
static inline void v3_scatter(__global float* a, uint pool, uint field, lu slot, lf3 v, lm m) {
  l_scatter(a + field * pool, slot, v.x, m);
  l_scatter(a + (field + 1u) * pool, slot, v.y, m);
  l_scatter(a + (field + 2u) * pool, slot, v.z, m);
}

/* ------------------------- 1. arithmetic alone (the issue's micro-benchmark) ---------------- */
// 64 dependent iterations of cross/normalize/dot with a data-dependent choice, per path.
__kernel void arith(__global float* X, __global float* Y, __global float* Z, int iters) {
  uint i = get_global_id(0);
  lf3 v = v3(L_LOAD(X, i), L_LOAD(Y, i), L_LOAD(Z, i));
  lf3 w = v3((lf)(0.3f), (lf)(0.5f), (lf)(0.7f));
  lf acc = (lf)(0.0f);
  for (int k = 0; k < iters; ++k) {
    lf3 c = v3_normalize(v3_cross(v, w));
    lf d = v3_dot(c, w);
    lm pos = d > 0.0f;
    acc += L_SEL(pos, d, -d * 0.5f);
    v = v3(L_SEL(pos, c.x + 0.1f, c.x), L_SEL(pos, c.y, c.y + 0.2f), c.z);
    w = v3(w.y, w.z, w.x + 0.01f);
  }
  L_STORE(v.x + acc, X, i);
  L_STORE(v.y, Y, i);
  L_STORE(v.z, Z, i);
}

/* ------------------------- 2. the diffuse shading stage, modelled ---------------------------- */
// Path state fields (field-major SoA, as kernels/integrator/path_state.h).
#define F_P 0u
#define F_NG 3u
#define F_DIR 6u
#define F_THR 9u
#define F_ERR 12u
#define F_ETA 13u
#define F_SH_O 14u
#define F_SH_D 17u
#define F_SH_TMAX 20u
#define F_SH_C 21u
#define F_PDF 24u
#define F_COUNT 25u
#define U_PIXEL 0u
#define U_SAMPLE 1u
#define U_BOUNCE 2u
#define U_MAT 3u
#define U_FLAGS 4u
#define U_COUNT 5u
#define FLAG_HAS_SHADOW 1u
#define Q_RAY 1u
#define Q_DONE 2u

// A 32-bit integer hash (the "PCG hash" of Jarzynski & Olano 2020, "Hash Functions for GPU
// Rendering", JCGT 9(3), Sec. 3), standing in for the Sobol' sampler.
static inline lu l_hash(lu v) {
  lu s = v * 747796405u + 2891336453u;
  lu w = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
  return (w >> 22u) ^ w;
}
static inline lf l_u01(lu h) { return L_U2F(h >> 8u) * 0x1p-24f; }

// One float step away from zero along s (kernels/common/ray.h, aw_float_step).
static inline lf l_float_step(lf x, lf s) {
  lm up = (x > 0.0f) == (s > 0.0f);
  lf stepped = L_AS_F(L_AS_I(x) + L_SEL(up, (li)(1), (li)(-1)));
  lf r = L_SEL(x == 0.0f, copysign((lf)(1.17549435e-38f), s), stepped);
  return L_SEL(s == 0.0f, x, r);
}
static inline lf3 l_offset(lf3 p, lf3 n, lf err) {
  lf3 o = v3_add(p, v3_scale(n, err));
  return v3(l_float_step(o.x, n.x), l_float_step(o.y, n.y), l_float_step(o.z, n.z));
}

// Cephes' quarter-range sin/cos (kernels/common/sampling.h, sincos_quarter).
static inline void l_sincos_quarter(lf x, lf* s, lf* c) {
  lf z = x * x;
  *s = x + x * z * (-1.6666654611e-1f + z * (8.3321608736e-3f + z * -1.9515295891e-4f));
  *c = 1.0f - 0.5f * z + z * z * (4.166664568298827e-2f + z * (-1.388731625493765e-3f + z * 2.443315711809948e-5f));
}

// Cosine-weighted hemisphere by the concentric map (Shirley & Chiu 1997, Sec. 3; Malley's method).
static inline lf3 l_sample_cosine(lf u0, lf u1) {
  lf a = 2.0f * u0 - 1.0f, b = 2.0f * u1 - 1.0f;
  lm wide = fabs(a) > fabs(b);
  lf r = L_SEL(wide, a, b);
  lf ratio = L_SEL(wide, b, a) / L_SEL(r == 0.0f, (lf)(1.0f), r);
  lf s, c;
  l_sincos_quarter((M_PI_F / 4.0f) * ratio, &s, &c);
  lf dx = L_SEL(wide, a * c, b * s), dy = L_SEL(wide, a * s, b * c);
  lm origin = a == 0.0f && b == 0.0f;
  dx = L_SEL(origin, (lf)(0.0f), dx);
  dy = L_SEL(origin, (lf)(0.0f), dy);
  return v3(dx, dy, sqrt(fmax(1.0f - dx * dx - dy * dy, 0.0f)));
}

// Duff et al. 2017, "Building an Orthonormal Basis, Revisited", JCGT 6(1), Listing 3.
static inline void l_make_frame(lf3 n, lf3* t, lf3* b) {
  lf s = copysign((lf)(1.0f), n.z);
  lf a = -1.0f / (s + n.z);
  lf c = n.x * n.y * a;
  *t = v3(1.0f + s * n.x * n.x * a, s * c, -s * n.x);
  *b = v3(c, s + n.y * n.y * a, -n.y);
}

// Veach 1997, Eq. 9.13 (kernels/common/sampling.h, mis_power).
static inline lf l_mis_power(lf pa, lf pb) {
  lf a = pa * pa, b = pb * pb;
  lf w = a / (a + b);
  w = L_SEL(isfinite(a), w, (lf)(1.0f));
  return L_SEL(a + b > 0.0f, w, (lf)(0.0f));
}

// light: corner (0-2), edge u (3-5), edge v (6-8), unit normal (9-11), radiance (12-14), area (15).
__kernel void shade_model(__global float* sf, __global uint* su, const __global float* albedo,
                          const __global uint* queue, __global uint* out_q, const __global float* light,
                          uint pool, uint count, uint rr_depth) {
  uint i = get_global_id(0);
  if (i * W >= count) return;  // the host pads count to a multiple of W
  lu slot = L_LOAD(queue, i);
  lf3 p = v3_gather(sf, pool, F_P, slot);
  lf3 ng = v3_gather(sf, pool, F_NG, slot);
  lf3 dir = v3_gather(sf, pool, F_DIR, slot);
  lf3 thr = v3_gather(sf, pool, F_THR, slot);
  lf err = l_gather(sf + F_ERR * pool, slot);
  lf eta = l_gather(sf + F_ETA * pool, slot);
  lu pixel = l_gather_u(su + U_PIXEL * pool, slot);
  lu sample = l_gather_u(su + U_SAMPLE * pool, slot);
  lu bounce = l_gather_u(su + U_BOUNCE * pool, slot);
  lu mat = l_gather_u(su + U_MAT * pool, slot);
  lu flags = l_gather_u(su + U_FLAGS * pool, slot);
  lf3 alb = v3(l_gather_idx(albedo, mat * 3u), l_gather_idx(albedo, mat * 3u + 1u), l_gather_idx(albedo, mat * 3u + 2u));

  lf3 t, b;
  l_make_frame(ng, &t, &b);
  lf3 nd = v3_scale(dir, (lf)(-1.0f));
  lf3 wo = v3(v3_dot(nd, t), v3_dot(nd, b), v3_dot(nd, ng));
  lu h = l_hash(pixel ^ l_hash(sample * 16u + bounce));
  lu h1 = l_hash(h + 1u), h2 = l_hash(h + 2u), h3 = l_hash(h + 3u), h4 = l_hash(h + 4u), h5 = l_hash(h + 5u);

  // Next-event estimation: the quad sampled uniformly by area, converted to solid angle.
  lf3 lc = v3((lf)(light[0]), (lf)(light[1]), (lf)(light[2]));
  lf3 lu_ = v3((lf)(light[3]), (lf)(light[4]), (lf)(light[5]));
  lf3 lv = v3((lf)(light[6]), (lf)(light[7]), (lf)(light[8]));
  lf3 ln = v3((lf)(light[9]), (lf)(light[10]), (lf)(light[11]));
  lf3 le = v3((lf)(light[12]), (lf)(light[13]), (lf)(light[14]));
  lf area = (lf)(light[15]);
  lf3 lp = v3_add(lc, v3_add(v3_scale(lu_, l_u01(h1)), v3_scale(lv, l_u01(h2))));
  lf3 d = v3_sub(lp, p);
  lf dist2 = v3_dot(d, d);
  lf dist = sqrt(dist2);
  lf3 wi = v3_scale(d, 1.0f / dist);
  lf cos_l = -v3_dot(wi, ln);
  lf cg = v3_dot(wi, ng);
  lf pdf_l = dist2 / (cos_l * area);
  lm nee = cos_l > 0.0f && cg > 0.0f && pdf_l > 0.0f && wo.z > 0.0f;
  lf cos_i = cg;  // the shading normal is the geometric one here
  lf3 f = v3_scale(alb, cos_i * (1.0f / M_PI_F));
  lf w = l_mis_power(pdf_l, cos_i * (1.0f / M_PI_F));
  lf3 contrib = v3_scale(v3_mul(v3_mul(thr, f), le), w / pdf_l);
  nee = nee && v3_max_comp(contrib) > 0.0f;
  lf3 o = l_offset(p, ng, err);
  lf3 sd = v3_sub(lp, o);
  lf len = sqrt(v3_dot(sd, sd));
  v3_scatter(sf, pool, F_SH_O, slot, o, nee);
  v3_scatter(sf, pool, F_SH_D, slot, v3_scale(sd, 1.0f / len), nee);
  l_scatter(sf + F_SH_TMAX * pool, slot, len * (1.0f - 1e-4f), nee);
  v3_scatter(sf, pool, F_SH_C, slot, contrib, nee);
  flags = L_SEL(nee, flags | FLAG_HAS_SHADOW, flags & ~FLAG_HAS_SHADOW);

  // The bounce: cosine-weighted, weight = albedo (Lambert), then Russian roulette.
  lf3 sl = l_sample_cosine(l_u01(h3), l_u01(h4));
  lf pdf = sl.z * (1.0f / M_PI_F);
  lf3 wn = v3_add(v3_add(v3_scale(t, sl.x), v3_scale(b, sl.y)), v3_scale(ng, sl.z));
  lf3 thr2 = v3_mul(thr, alb);
  lf m = v3_max_comp(thr2) * eta;
  lm alive = pdf > 0.0f && v3_dot(wn, ng) > 0.0f && m > 0.0f && isfinite(m);
  lf q = L_SEL(bounce + 1u >= rr_depth, fmin((lf)(1.0f), sqrt(m)), (lf)(1.0f));
  alive = alive && !(q < 1.0f && l_u01(h5) >= q);
  thr2 = v3_sel(q < 1.0f, v3_scale(thr2, 1.0f / q), thr2);
  v3_scatter(sf, pool, F_THR, slot, thr2, alive);
  v3_scatter(sf, pool, F_P, slot, o, alive);  // the extension ray's origin
  v3_scatter(sf, pool, F_DIR, slot, wn, alive);
  l_scatter(sf + F_PDF * pool, slot, pdf, alive);
  l_scatter_u(su + U_BOUNCE * pool, slot, bounce + 1u, alive);
  l_scatter_u(su + U_FLAGS * pool, slot, flags, L_TRUE);
  L_STORE(L_SEL(alive, (lu)(Q_RAY), (lu)(Q_DONE)), out_q, i);
}

/* ------------------------- 3. compaction: moving queued paths into slot order ---------------- */
// Copies the state of the paths in `queue` (shuffled slots) into consecutive slots of a second
// pool, every float and uint field: what a lane design would pay to make a scattered queue
// contiguous before its stages read it with vector loads.
__kernel void compact_model(const __global float* sf, const __global uint* su, const __global uint* queue,
                            __global float* sf_out, __global uint* su_out, uint pool, uint count) {
  uint i = get_global_id(0);
  if (i * W >= count) return;
  lu slot = L_LOAD(queue, i);
  for (uint f = 0u; f < F_COUNT; ++f) L_STORE(l_gather_idx(sf + f * pool, slot), sf_out + f * pool, i);
  for (uint f = 0u; f < U_COUNT; ++f)
    L_STORE(L_AS_U(l_gather_idx((const __global float*)(su + f * pool), slot)), su_out + f * pool, i);
}
