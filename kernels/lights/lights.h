// Lights: selection, sampling for next-event estimation, and analytic intersection.
//
// Area lights are intersected analytically (not tessellated into the BVH) so that the shape a
// BSDF-sampled ray hits is exactly the shape light sampling draws from; otherwise MIS weights
// would disagree at silhouettes of disks and spheres. Units follow docs/scene-format.md: area
// lights store radiance, point lights radiant intensity.
//
// Selection, sampling and densities are written on lanes (common/lanes.h): at AW_LANES = 1 one
// path and one light, as the scalar code was; at W > 1 each lane's own light, its fields
// gathered per lane (light_load), every light type's branch taken when any lane needs it and
// its results selected into the lanes of that type. Intersection (light_intersect below) is
// still one ray per call.
#ifndef AW_LIGHTS_LIGHTS_H
#define AW_LIGHTS_LIGHTS_H

#include "common/compat.h"
#include "common/features.h"
#include "common/lanes.h"
#include "common/sampling.h"
#include "types/scene.h"

typedef struct {
  lfloat3 wi;        // unit direction from the shading point to the light
  lfloat dist;       // distance to the sampled point
  lfloat3 le;        // emitted radiance (area) or intensity / dist^2 (point) towards the point
  lfloat pdf;        // solid-angle pdf of wi given this light (1 for delta lights)
  lmask is_delta;
} LightSample;

AW_FN LightSample light_sample_sel(lmask m, LightSample a, LightSample b) {
  LightSample s;
  s.wi = l3_sel(m, a.wi, b.wi);
  s.dist = L_SEL(m, a.dist, b.dist);
  s.le = l3_sel(m, a.le, b.le);
  s.pdf = L_SEL(m, a.pdf, b.pdf);
  s.is_delta = L_SEL(m, a.is_delta, b.is_delta);
  return s;
}

// The fields of a light that sampling and the densities read: at W = 1 one LightGpu's, at
// W > 1 each lane's light's (`i` must name a light in every lane, masked-off lanes included).
typedef struct {
  luint type, flags;
  lfloat radius, area;
  lfloat3 p, u, v, n, radiance;
} LightL;

// `num_lights` is the table's size (RenderParams.num_lights): a small table is read by
// selects (L_TABLE, common/lanes.h).
#define AW_LIGHT_F3(lights, n, i, f)                                                               \
  make_lfloat3(L_TABLE(float, lights, n, i, f[0]), L_TABLE(float, lights, n, i, f[1]), \
               L_TABLE(float, lights, n, i, f[2]))
AW_FN LightL light_load(const AW_GLOBAL LightGpu* lights, uint num_lights, luint i) {
  (void)num_lights;  // (at W = 1 a table entry is one load whatever the table's size)
  LightL l;
  l.type = L_TABLE(uint, lights, num_lights, i, type);
  l.flags = L_TABLE(uint, lights, num_lights, i, flags);
  l.radius = L_TABLE(float, lights, num_lights, i, radius);
  l.area = L_TABLE(float, lights, num_lights, i, area);
  l.p = AW_LIGHT_F3(lights, num_lights, i, p);
  l.u = AW_LIGHT_F3(lights, num_lights, i, u);
  l.v = AW_LIGHT_F3(lights, num_lights, i, v);
  l.n = AW_LIGHT_F3(lights, num_lights, i, n);
  l.radiance = AW_LIGHT_F3(lights, num_lights, i, radiance);
  return l;
}
#undef AW_LIGHT_F3

// Picks a light with probability select_pdf (proportional to emitted power) in O(1), whatever
// the number of lights: Walker's alias method (Walker 1977, "An efficient method for generating
// discrete random variables with general distributions", ACM TOMS 3(3); the table is built by
// Vose's algorithm, Vose 1991, IEEE TSE 17(9), in host/render/alias_table.h). One uniform
// number does both draws: its bin, floor(u n), and the remainder u n - bin, which is uniform
// in [0, 1) given the bin and decides between the bin's light and its alias.
AW_FN luint light_pick(const AW_GLOBAL LightGpu* lights, uint num_lights, lfloat u) {
  lfloat x = u * (float)num_lights;
  luint i = min(L_TO_UINT(x), num_lights - 1u);
  lfloat r = x - L_TO_FLOAT(i);
  return L_SEL(r < L_TABLE(float, lights, num_lights, i, alias_q), i, L_TABLE(uint, lights, num_lights, i, alias));
}

// Light-type tests below are written `AW_FEAT_LIGHT_X && type == X`: in a specialised build
// (kernels/common/features.h) the branches of absent light types fold away.

// Radiance leaving an area light towards direction -dir (dir = ray direction hitting it).
AW_FN lfloat3 light_emitted(LightL l, lfloat3 dir) {
  lfloat c = -l3_dot(l.n, dir);
  lmask lit = c > 0.0f || (l.flags & AW_LIGHT_TWO_SIDED) != 0u;
  if (AW_FEAT_LIGHT_SPHERE) lit = lit || l.type == AW_LIGHT_SPHERE;
  return l3_sel(lit, l.radiance, l3_splat((lfloat)(0.0f)));
}

// sin^2 of the half-angle a sphere subtends, and 1 - cos of it without cancellation.
AW_FN lfloat sphere_one_minus_cos_max(lfloat sin2_max) {
  lfloat cos_max = l_safe_sqrt(1.0f - sin2_max);
  return sin2_max / (1.0f + cos_max);
}

// Density of a sphere light's point drawn uniformly by area on its surface (from inside it),
// converted to solid angle at distance t along unit dir: t^2 / (A cos_l) (Veach 1997, Sec. 9.2).
AW_FN lfloat sphere_area_pdf(LightL l, lfloat3 p, lfloat3 dir, lfloat t) {
  lfloat3 y = l3_add(p, l3_scale(dir, t));
  lfloat cos_l = fabs(l3_dot(l3_normalize(l3_sub(y, l.p)), dir));
  return L_SEL(cos_l > 0.0f, (t * t) / (l.area * cos_l), (lfloat)(0.0f));
}

/* ------------------------------------- the sun ------------------------------------------ */
// A sun of angular diameter 2 alpha is a disc of uniform radiance L at infinity: the
// irradiance on a surface facing it is L times the projected solid angle of the cone,
// pi sin^2 alpha (Pharr, Jakob & Humphreys, PBR 3rd ed., Sec. 5.5.1, Eq. 5.5 integrated over
// the cone), so L = E / (pi sin^2 alpha) for the scene's irradiance E (host/render/scene_pack.cpp).
// It is sampled uniformly in that cone (pdf 1 / (2 pi (1 - cos alpha)), PBR Sec. 13.6.4) and
// found by escaping rays within it, MIS-weighted (classify_hit.h). A hard sun (alpha = 0) is
// a delta: sampled only, radiance = E along its one direction.

// Density of drawing `dir` from a soft sun; 0 outside its cone and for a hard sun.
AW_FN lfloat sun_pdf(LightL l, lfloat3 dir) {
  lmask in = l.area > 0.0f && !(l3_dot(dir, l.n) < l.radius);
  return L_SEL(in, 1.0f / (2.0f * M_PI_F * l.area), (lfloat)(0.0f));
}

// Distance given to samples of lights at infinity: shadow rays test the whole line.
#define AW_INFINITE_DISTANCE FLT_MAX

AW_FN LightSample sun_sample(LightL l, lfloat2 u) {
  LightSample s;
  s.dist = (lfloat)(AW_INFINITE_DISTANCE);
  s.le = l.radiance;
  lmask hard = !(l.area > 0.0f);
  s.is_delta = hard;
  s.wi = l.n;
  s.pdf = (lfloat)(1.0f);
  if (L_ALL(hard)) return s;
  // Uniform in the cone, with 1 - cos theta = u.x (1 - cos alpha) kept as a small number so
  // that sin theta = sqrt((1 - cos)(1 + cos)) does not cancel for the sun's 0.27 degrees.
  lfloat omc = u.x * l.area;
  lfloat sin_t = l_safe_sqrt(omc * (2.0f - omc));
  lfloat sp, cp;
  sincos_turn(u.y, &sp, &cp);  // phi = 2 pi u.y
  lfloat3 t, b;
  make_frame(l.n, &t, &b);
  lfloat3 wi = l3_normalize(frame_to_world(make_lfloat3(cp * sin_t, sp * sin_t, 1.0f - omc), t, b, l.n));
  s.wi = l3_sel(hard, s.wi, wi);
  s.pdf = L_SEL(hard, s.pdf, 1.0f / (2.0f * M_PI_F * l.area));
  return s;
}

/* ------------------------------ spherical rectangles ------------------------------------ */
// Uniform sampling of the solid angle a rectangle subtends: Urena, Fajardo & King 2013, "An
// Area-Preserving Parametrization for Spherical Rectangles", EGSR (Computer Graphics Forum
// 32(4)), Sec. 3 (the rectangle's local frame and the four planes through the eye and its
// edges), Sec. 4 (the solid angle S = g0 + g1 + g2 + g3 - 2 pi from the internal angles)
// and Sec. 5 (inverting the area of the sub-rectangle for x, then uniform in the height h for
// y). The density is 1 / S everywhere on the rectangle, so the light sample's weight no longer
// carries the 1 / d^2 and cos factors that make area sampling noisy close to a light.
// The angles are l_acos and the sine and cosine l_sincos (common/lanes.h, common/sampling.h):
// the same rounding at every width and on the host.
typedef struct {
  lfloat3 o, x, y, z;           // the eye and the rectangle's frame (z points away from the eye's side)
  lfloat x0, y0, z0, x1, y1;    // the rectangle in that frame: [x0, x1] x [y0, y1] at height z0 <= 0
  lfloat b0, b1, k, S;          // Sec. 4-5: n0.z, n2.z, 2 pi - g2 - g3, the solid angle
} SphRect;

AW_FN SphRect sph_rect_make(lfloat3 corner, lfloat3 eu, lfloat3 ev, lfloat3 o) {
  SphRect r;
  lfloat lu = l3_length(eu), lv = l3_length(ev);
  r.o = o;
  r.x = l3_div(eu, lu);
  r.y = l3_div(ev, lv);
  r.z = l3_cross(r.x, r.y);
  lfloat3 d = l3_sub(corner, o);
  r.z0 = l3_dot(d, r.z);
  lmask flip = r.z0 > 0.0f;  // look at the rectangle from the z < 0 side
  r.z = l3_sel(flip, l3_neg(r.z), r.z);
  r.z0 = L_SEL(flip, -r.z0, r.z0);
  r.x0 = l3_dot(d, r.x);
  r.y0 = l3_dot(d, r.y);
  r.x1 = r.x0 + lu;
  r.y1 = r.y0 + lv;
  // Normals of the planes through o and each edge (Sec. 3, written out for the local frame).
  lfloat zero = (lfloat)(0.0f);
  lfloat3 n0 = l3_normalize(make_lfloat3(zero, r.z0, -r.y0));
  lfloat3 n1 = l3_normalize(make_lfloat3(-r.z0, zero, r.x1));
  lfloat3 n2 = l3_normalize(make_lfloat3(zero, -r.z0, r.y1));
  lfloat3 n3 = l3_normalize(make_lfloat3(r.z0, zero, -r.x0));
  lfloat g0 = l_acos(clamp(-l3_dot(n0, n1), -1.0f, 1.0f));
  lfloat g1 = l_acos(clamp(-l3_dot(n1, n2), -1.0f, 1.0f));
  lfloat g2 = l_acos(clamp(-l3_dot(n2, n3), -1.0f, 1.0f));
  lfloat g3 = l_acos(clamp(-l3_dot(n3, n0), -1.0f, 1.0f));
  r.b0 = n0.z;
  r.b1 = n2.z;
  r.k = 2.0f * M_PI_F - g2 - g3;
  r.S = g0 + g1 - r.k;
  return r;
}

// The point for u in [0, 1)^2 (Sec. 5, Algorithm 1).
AW_FN lfloat3 sph_rect_sample(const SphRect* r, lfloat2 u) {
  lfloat au = u.x * r->S + r->k;
  lfloat sa, ca;
  l_sincos(au, &sa, &ca);
  lfloat fu = (ca * r->b0 - r->b1) / sa;
  lfloat cu = copysign((lfloat)(1.0f), fu) / sqrt(fu * fu + r->b0 * r->b0);
  cu = clamp(cu, -1.0f, 1.0f);
  lfloat xu = -(cu * r->z0) / l_safe_sqrt(1.0f - cu * cu);
  xu = clamp(xu, r->x0, r->x1);
  lfloat dd = sqrt(xu * xu + r->z0 * r->z0);
  lfloat h0 = r->y0 / sqrt(dd * dd + r->y0 * r->y0);
  lfloat h1 = r->y1 / sqrt(dd * dd + r->y1 * r->y1);
  lfloat hv = h0 + u.y * (h1 - h0);
  lfloat hv2 = hv * hv;
  lfloat yv = L_SEL(hv2 < 1.0f - 1e-6f, (hv * dd) / sqrt(1.0f - hv2), r->y1);
  yv = clamp(yv, r->y0, r->y1);
  return l3_add(l3_add(l3_add(r->o, l3_scale(r->x, xu)), l3_scale(r->y, yv)), l3_scale(r->z, r->z0));
}

// The solid angles sampled this way; outside them, area sampling (measured, see
// docs/architecture.md, "Light sampling").
// - Below 1 sr, for speed: a spherical-rectangle sample costs about 6x an area sample (host:
//   280 vs 43 ns, four acos), and what it removes, the variation of cos_l / d^2 over the
//   light, matters only for a light that fills much of the view. For a unit square seen from
//   h above its centre, area sampling's relative variance is 0.28 at h = 0.5 (S = 2.1 sr),
//   0.037 at h = 1 (S = 0.8), 0.003 at h = 2 and 0.0002 at h = 4, small next to a path's
//   visibility and BSDF noise below 1 sr; on the Cornell box a threshold of 1e-2 sr cost 25%
//   more shading time for 5% less squared error. (Precision would allow less: S is a
//   difference of angles near 2 pi in single precision. Against the closed form, with l_acos
//   (2026-12-05; a unit square seen from above its centre and a 1.2 x 0.7 rectangle seen from
//   above a corner, heights 0.01-10): absolute error 6e-8 to 5e-7 sr, relative at most 1.1e-6
//   at 0.2-2 sr and 1.2e-5 at 1e-2 sr; with the library's acos it was ~4e-7 sr, relative 1e-7
//   at 0.2-2 sr, 4e-5 at 1e-2 sr, 1.5e-3 at 4e-4 sr.)
// - Within 1e-2 sr of 2 pi (a point just above a huge light) the mapping degenerates; it is
//   still exact to 4.4e-6 at 6.17 sr (0.01 above a unit square).
#define AW_SPH_RECT_MIN_SOLID_ANGLE 1.0f
#define AW_SPH_RECT_MAX_SOLID_ANGLE (2.0f * M_PI_F - 1e-2f)

// Whether quad light l is sampled by solid angle from p, and the spherical rectangle if so.
// light_sample and light_pdf both decide here, from the same inputs, so MIS sees the density
// that produced the sample. (r->S is always written, so that lanes may read it unselected.)
AW_FN lmask light_quad_by_solid_angle(LightL l, lfloat3 p, SphRect* r) {
  r->S = (lfloat)(0.0f);
  lmask m = (l.flags & AW_LIGHT_RECTANGLE) != 0u;
  if (!L_ANY(m)) return m;
  // Skip the four acos when a cheap bound already says the light is too small, or when p is
  // behind a one-sided light (which gives it nothing whichever way it samples). The bound: the
  // solid angle is the integral of |h| / r^3 over the rectangle (h: p's distance to its
  // plane, r: to the point), so S <= A |h| / d^3 with d the distance from p to the nearest
  // point of the rectangle (its edges are orthogonal, so that point is p's projection clamped
  // to them). Tighter than A / h^2 beside the light, where the receiving points of a room
  // mostly are (measured: the acos of rejected rectangles were 2.4% of the spheres' render
  // on PoCL). It only skips what the exact S would reject, so images do not change.
  lfloat3 pc = l3_sub(p, l.p);
  lfloat h = l3_dot(l.n, pc);
  m = m && !(h <= 0.0f && (l.flags & AW_LIGHT_TWO_SIDED) == 0u);
  lfloat su = clamp(l3_dot(pc, l.u) / l3_dot(l.u, l.u), 0.0f, 1.0f);
  lfloat sv = clamp(l3_dot(pc, l.v) / l3_dot(l.v, l.v), 0.0f, 1.0f);
  lfloat3 dq = l3_sub(l3_sub(pc, l3_scale(l.u, su)), l3_scale(l.v, sv));
  lfloat d2 = l3_dot(dq, dq);
  m = m && !(l.area * fabs(h) < AW_SPH_RECT_MIN_SOLID_ANGLE * d2 * sqrt(d2));
  if (!L_ANY(m)) return m;
  *r = sph_rect_make(l.p, l.u, l.v, p);
  return m && r->S > AW_SPH_RECT_MIN_SOLID_ANGLE && r->S < AW_SPH_RECT_MAX_SOLID_ANGLE && isfinite(r->S);
}

// Uniform area sampling of a flat light (quad, disk, triangle) converted to solid angle at
// distance t along unit dir: t^2 / (A cos_l) (Veach 1997, Sec. 9.2).
AW_FN lfloat light_area_pdf(LightL l, lfloat3 dir, lfloat t) {
  lfloat cos_l = fabs(l3_dot(l.n, dir));
  return L_SEL(cos_l > 0.0f, (t * t) / (l.area * cos_l), (lfloat)(0.0f));
}

// Solid-angle pdf (given the light is chosen) of reaching `l` from `p` along unit `dir`,
// hitting it at distance `t`. Must match light_sample exactly (MIS relies on it).
AW_FN lfloat light_pdf(LightL l, lfloat3 p, lfloat3 dir, lfloat t) {
  lfloat pdf = light_area_pdf(l, dir, t);  // triangle, disk, a quad drawn by area
  if (AW_FEAT_LIGHT_QUAD) {
    lmask quad = l.type == AW_LIGHT_QUAD;
    if (L_ANY(quad)) {
      SphRect r;
      lmask by_sa = quad && light_quad_by_solid_angle(l, p, &r);
      pdf = L_SEL(by_sa, 1.0f / r.S, pdf);
    }
  }
  if (AW_FEAT_LIGHT_SPHERE) {
    lmask sphere = l.type == AW_LIGHT_SPHERE;
    if (L_ANY(sphere)) {
      lfloat3 pc = l3_sub(l.p, p);
      lfloat d2 = l3_dot(pc, pc);
      lfloat r2 = l.radius * l.radius;
      // Outside: uniform cone sampling, pbrt-v3, Sec. 14.2.2 ("Sampling Spheres").
      pdf = L_SEL(sphere, L_SEL(d2 > r2, 1.0f / (2.0f * M_PI_F * sphere_one_minus_cos_max(r2 / d2)),
                                sphere_area_pdf(l, p, dir, t)),
                  pdf);
    }
  }
  if (AW_FEAT_LIGHT_SUN) pdf = L_SEL(l.type == AW_LIGHT_SUN, sun_pdf(l, dir), pdf);
  if (AW_FEAT_LIGHT_POINT) pdf = L_SEL(l.type == AW_LIGHT_POINT, (lfloat)(0.0f), pdf);
  return pdf;
}

// Samples a point on light `l` as seen from `p` (Veach 1997, Sec. 9.2: area sampling
// converted to solid angle by dist^2 / cos). pdf = 0 when the sample cannot contribute.
// Suns, point lights and spheres seen from outside give their sample directly ("done"); every
// other light a point y on it, turned into a direction at the end.
AW_FN LightSample light_sample(LightL l, lfloat3 p, lfloat2 u) {
  LightSample s;
  lfloat zero = (lfloat)(0.0f);
  s.is_delta = (lmask)(0);
  s.pdf = zero;
  s.le = l3_splat(zero);
  s.dist = zero;
  s.wi = make_lfloat3(zero, zero, (lfloat)(1.0f));
  lmask done = (lmask)(0);      // the lanes whose sample is complete
  lmask taken = (lmask)(0);     // the lanes of a type handled before the disk
  lfloat3 y = p;                // the point drawn on the light
  lfloat pdf_solid_angle = zero;  // set when the point was drawn uniformly in solid angle
  lmask sphere_inside = (lmask)(0);  // drawn on a sphere's surface from inside it
  if (AW_FEAT_LIGHT_SUN) {
    lmask sun = l.type == AW_LIGHT_SUN;
    if (L_ANY(sun)) s = light_sample_sel(sun, sun_sample(l, u), s);
    done = done || sun;
  }
  if (AW_FEAT_LIGHT_POINT) {
    lmask point = l.type == AW_LIGHT_POINT;
    if (L_ANY(point)) {
      lfloat3 d = l3_sub(l.p, p);
      lfloat d2 = l3_dot(d, d);
      lmask ok = point && d2 > 0.0f;
      lfloat dist = sqrt(d2);
      s.dist = L_SEL(ok, dist, s.dist);
      s.wi = l3_sel(ok, l3_div(d, dist), s.wi);
      s.le = l3_sel(ok, l3_div(l.radiance, d2), s.le);
      s.pdf = L_SEL(ok, (lfloat)(1.0f), s.pdf);
      s.is_delta = s.is_delta || ok;
    }
    done = done || point;
  }
  if (L_ALL(done)) return s;
  if (AW_FEAT_LIGHT_SPHERE) {
    lmask sphere = l.type == AW_LIGHT_SPHERE;
    if (L_ANY(sphere)) {
      lfloat3 c = l.p;
      lfloat3 pc = l3_sub(c, p);
      lfloat d2 = l3_dot(pc, pc);
      lfloat r2 = l.radius * l.radius;
      lmask outside = sphere && d2 > r2;
      if (L_ANY(outside)) {
        // Outside: sample the cone of directions the sphere subtends (pbrt-v3, Sec. 14.2.2).
        lfloat dc = sqrt(d2);
        lfloat omc = sphere_one_minus_cos_max(r2 / d2);
        lfloat cos_t = 1.0f - u.x * omc;
        lfloat sin2_t = fmax(zero, (1.0f - cos_t) * (1.0f + cos_t));
        lfloat sp, cp;
        sincos_turn(u.y, &sp, &cp);  // phi = 2 pi u.y
        lfloat3 w = l3_div(pc, dc), t, b;
        make_frame(w, &t, &b);
        lfloat sin_t = sqrt(sin2_t);
        s.wi = l3_sel(outside, l3_normalize(frame_to_world(make_lfloat3(cp * sin_t, sp * sin_t, cos_t), t, b, w)), s.wi);
        // Nearest intersection along the sampled direction; the max() guards rays that graze
        // the silhouette by round-off.
        s.dist = L_SEL(outside, dc * cos_t - l_safe_sqrt(r2 - d2 * sin2_t), s.dist);
        s.pdf = L_SEL(outside, 1.0f / (2.0f * M_PI_F * omc), s.pdf);
        s.le = l3_sel(outside, l.radiance, s.le);
      }
      done = done || outside;
      // Inside the sphere: uniform area sampling of its surface.
      sphere_inside = sphere && !outside;
      if (L_ANY(sphere_inside)) {
        lfloat z = 1.0f - 2.0f * u.x;
        lfloat rxy = l_safe_sqrt(1.0f - z * z);
        lfloat sp, cp;
        sincos_turn(u.y, &sp, &cp);  // phi = 2 pi u.y
        lfloat3 nrm = make_lfloat3(rxy * cp, rxy * sp, z);
        y = l3_sel(sphere_inside, l3_add(c, l3_scale(nrm, l.radius)), y);
      }
    }
    taken = taken || sphere;
  }
  if (AW_FEAT_LIGHT_MESH) {
    lmask tri = l.type == AW_LIGHT_TRIANGLE && !taken;
    if (L_ANY(tri)) {
      // Uniform by area: the square-root warp to barycentrics (Turk 1990, "Generating Random
      // Points in Triangles", Graphics Gems; PBR 3rd ed., Sec. 13.6.4). (Arvo's 1995 spherical
      // triangles would sample by solid angle; the fixtures' small triangles seen from afar
      // gain little from it, as the quads' measurement in docs/architecture.md shows.)
      lfloat su = sqrt(u.x);
      y = l3_sel(tri, l3_add(l3_add(l.p, l3_scale(l.u, su * (1.0f - u.y))), l3_scale(l.v, su * u.y)), y);
    }
    taken = taken || tri;
  }
  if (AW_FEAT_LIGHT_QUAD) {
    lmask quad = l.type == AW_LIGHT_QUAD && !taken;
    if (L_ANY(quad)) {
      SphRect r;
      lmask by_sa = quad && light_quad_by_solid_angle(l, p, &r);
      if (L_ANY(by_sa)) {
        y = l3_sel(by_sa, sph_rect_sample(&r, u), y);
        pdf_solid_angle = L_SEL(by_sa, 1.0f / r.S, pdf_solid_angle);
      }
      y = l3_sel(quad && !by_sa, l3_add(l3_add(l.p, l3_scale(l.u, u.x)), l3_scale(l.v, u.y)), y);
    }
    taken = taken || quad;
  }
  lmask disk = !(done || taken);
  if (L_ANY(disk)) {
    lfloat2 dk = sample_concentric_disk(u);
    y = l3_sel(disk, l3_add(l.p, l3_scale(l3_add(l3_scale(l.u, dk.x), l3_scale(l.v, dk.y)), l.radius)), y);
  }
  lmask area = !done;  // every lane that drew a point y
  lfloat3 d = l3_sub(y, p);
  lfloat d2 = l3_dot(d, d);
  lmask ok = area && d2 > 0.0f;
  if (!L_ANY(ok)) return s;
  lfloat dist = sqrt(d2);
  lfloat3 wi = l3_div(d, dist);
  s.dist = L_SEL(ok, dist, s.dist);
  s.wi = l3_sel(ok, wi, s.wi);
  // Every other point was drawn uniformly by area on a flat light (triangle, quad, disk): its
  // density is the area one, taken directly, since light_pdf would dispatch on the type and,
  // for a quad, run the solid-angle test again (two divisions and a square root) only to reach
  // the same answer.
  lfloat pdf = L_SEL(pdf_solid_angle > 0.0f, pdf_solid_angle,
                     L_SEL(sphere_inside, sphere_area_pdf(l, p, wi, dist), light_area_pdf(l, wi, dist)));
  ok = ok && pdf > 0.0f && isfinite(pdf);
  s.le = l3_sel(ok, light_emitted(l, wi), s.le);
  s.pdf = L_SEL(ok, pdf, s.pdf);
  return s;
}

// Distance along (org, dir) to area light `l` within (t_min, t_max), or -1. On lanes: W rays
// against one light.
AW_FN lfloat light_intersect(const AW_GLOBAL LightGpu* l, lfloat3 org, lfloat3 dir, lfloat t_min, lfloat t_max) {
  const lfloat none = (lfloat)(-1.0f);
  if (AW_FEAT_LIGHT_POINT && l->type == AW_LIGHT_POINT) return none;
  // Lights at infinity are found by rays that escape the scene (classify_hit.h), triangle
  // lights as the geometry they are (classify_hit.h), not here.
  // (The switches are 0 or 1, so `|` is their "or"; `||` between constants makes clang warn,
  // -Wconstant-logical-operand, on every OpenCL compiler built on it: PoCL, Intel, NVIDIA.)
  if ((AW_FEAT_LIGHT_SUN | AW_FEAT_ENV_MAP | AW_FEAT_LIGHT_MESH) && l->type >= AW_LIGHT_SUN) return none;
  if (AW_FEAT_LIGHT_SPHERE && l->type == AW_LIGHT_SPHERE) {
    // Geometric form of the quadratic, stable for far spheres: the discriminant is formed
    // from the squared distance to the ray (Haines et al. 2019, Ray Tracing Gems Ch. 7, Eq. 8).
    lfloat3 f = l3_sub(org, l3_bcast(load_f3(l->p)));
    lfloat b = -l3_dot(f, dir);
    lfloat3 perp = l3_add(f, l3_scale(dir, b));
    float r2 = l->radius * l->radius;
    lfloat disc = r2 - l3_dot(perp, perp);
    lfloat sq = sqrt(disc);  // NaN where disc < 0: neither root below is then in range
    lfloat t0 = b - sq, t1 = b + sq;
    lfloat t = L_SEL(t0 > t_min && t0 < t_max, t0, L_SEL(t1 > t_min && t1 < t_max, t1, none));
    return L_SEL(disc < 0.0f, none, t);
  }
  lfloat3 n = l3_bcast(load_f3(l->n));
  lfloat denom = l3_dot(n, dir);
  lfloat3 p0 = l3_bcast(load_f3(l->p));
  lfloat t = l3_dot(n, l3_sub(p0, org)) / denom;
  lmask in = !(fabs(denom) < 1e-12f) && t > t_min && t < t_max;
  if (!L_ANY(in)) return none;
  lfloat3 q = l3_sub(l3_add(org, l3_scale(dir, t)), p0);
  if (AW_FEAT_LIGHT_QUAD && l->type == AW_LIGHT_QUAD) {
    // Parallelogram coordinates via cross products (edges need not be orthogonal).
    lfloat3 eu = l3_bcast(load_f3(l->u)), ev = l3_bcast(load_f3(l->v));
    lfloat a = l3_dot(l3_cross(q, ev), n) / l->area;
    lfloat bb = l3_dot(l3_cross(eu, q), n) / l->area;
    return L_SEL(in && a >= 0.0f && a <= 1.0f && bb >= 0.0f && bb <= 1.0f, t, none);
  }
  return L_SEL(in && l3_dot(q, q) <= l->radius * l->radius, t, none);
}

// Closest area light along the ray, skipping `skip` (the light a shadow ray aims at) and, for
// camera rays, lights marked invisible. Returns the light index or -1; *t is updated. On
// lanes: per lane.
AW_FN lint lights_intersect(const AW_GLOBAL LightGpu* lights, uint num_lights, lfloat3 org, lfloat3 dir,
                            lfloat t_min, lfloat* t, lmask camera_ray, lint skip) {
  lint found = (lint)(-1);
  for (uint i = 0; i < num_lights; ++i) {
    lmask consider = (lint)((int)i) != skip;
    if (!(lights[i].flags & AW_LIGHT_VISIBLE)) consider = consider && !camera_ray;
    if (!L_ANY(consider)) continue;
    lfloat th = light_intersect(&lights[i], org, dir, t_min, *t);
    lmask take = consider && th > 0.0f;
    *t = L_SEL(take, th, *t);
    found = L_SEL(take, (lint)((int)i), found);
  }
  return found;
}

#endif
