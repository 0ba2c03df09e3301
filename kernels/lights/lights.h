// Lights: selection, sampling for next-event estimation, and analytic intersection.
//
// Area lights are intersected analytically (not tessellated into the BVH) so that the shape a
// BSDF-sampled ray hits is exactly the shape light sampling draws from; otherwise MIS weights
// would disagree at silhouettes of disks and spheres. Units follow docs/scene-format.md: area
// lights store radiance, point lights radiant intensity.
#ifndef AW_LIGHTS_LIGHTS_H
#define AW_LIGHTS_LIGHTS_H

#include "common/compat.h"
#include "common/features.h"
#include "common/sampling.h"
#include "types/scene.h"

typedef struct {
  float3 wi;      // unit direction from the shading point to the light
  float dist;     // distance to the sampled point
  float3 le;      // emitted radiance (area) or intensity / dist^2 (point) towards the point
  float pdf;      // solid-angle pdf of wi given this light (1 for delta lights)
  int is_delta;
} LightSample;

// Picks a light with probability select_pdf (proportional to emitted power) in O(1), whatever
// the number of lights: Walker's alias method (Walker 1977, "An efficient method for generating
// discrete random variables with general distributions", ACM TOMS 3(3); the table is built by
// Vose's algorithm, Vose 1991, IEEE TSE 17(9), in host/render/alias_table.h). One uniform
// number does both draws: its bin, floor(u n), and the remainder u n - bin, which is uniform
// in [0, 1) given the bin and decides between the bin's light and its alias.
AW_FN uint light_pick(const AW_GLOBAL LightGpu* lights, uint num_lights, float u) {
  float x = u * (float)num_lights;
  uint i = min((uint)x, num_lights - 1u);
  float r = x - (float)i;
  return r < lights[i].alias_q ? i : lights[i].alias;
}

// Light-type tests below are written `AW_FEAT_LIGHT_X && type == X`: in a specialised build
// (kernels/common/features.h) the branches of absent light types fold away.

// Radiance leaving an area light towards direction -dir (dir = ray direction hitting it).
AW_FN float3 light_emitted(const AW_GLOBAL LightGpu* l, float3 dir) {
  float3 le = load_f3(l->radiance);
  if (AW_FEAT_LIGHT_SPHERE && l->type == AW_LIGHT_SPHERE) return le;
  float c = -dot(load_f3(l->n), dir);
  if (c > 0.0f || (l->flags & AW_LIGHT_TWO_SIDED)) return le;
  return make_float3(0.0f, 0.0f, 0.0f);
}

// sin^2 of the half-angle a sphere subtends, and 1 - cos of it without cancellation.
AW_FN float sphere_one_minus_cos_max(float sin2_max) {
  float cos_max = safe_sqrt(1.0f - sin2_max);
  return sin2_max / (1.0f + cos_max);
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
AW_FN float sun_pdf(const AW_GLOBAL LightGpu* l, float3 dir) {
  if (!(l->area > 0.0f) || dot(dir, load_f3(l->n)) < l->radius) return 0.0f;
  return 1.0f / (2.0f * M_PI_F * l->area);
}

// Distance given to samples of lights at infinity: shadow rays test the whole line.
#define AW_INFINITE_DISTANCE FLT_MAX

AW_FN LightSample sun_sample(const AW_GLOBAL LightGpu* l, float2 u) {
  LightSample s;
  s.dist = AW_INFINITE_DISTANCE;
  s.le = load_f3(l->radiance);
  float3 n = load_f3(l->n);
  if (!(l->area > 0.0f)) {
    s.wi = n;
    s.pdf = 1.0f;
    s.is_delta = 1;
    return s;
  }
  // Uniform in the cone, with 1 - cos theta = u.x (1 - cos alpha) kept as a small number so
  // that sin theta = sqrt((1 - cos)(1 + cos)) does not cancel for the sun's 0.27 degrees.
  float omc = u.x * l->area;
  float sin_t = safe_sqrt(omc * (2.0f - omc));
  float sp, cp;
  sincos_turn(u.y, &sp, &cp);  // phi = 2 pi u.y
  float3 t, b;
  make_frame(n, &t, &b);
  s.wi = normalize(frame_to_world(make_float3(cp * sin_t, sp * sin_t, 1.0f - omc), t, b, n));
  s.pdf = 1.0f / (2.0f * M_PI_F * l->area);
  s.is_delta = 0;
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
typedef struct {
  float3 o, x, y, z;           // the eye and the rectangle's frame (z points away from the eye's side)
  float x0, y0, z0, x1, y1;    // the rectangle in that frame: [x0, x1] x [y0, y1] at height z0 <= 0
  float b0, b1, k, S;          // Sec. 4-5: n0.z, n2.z, 2 pi - g2 - g3, the solid angle
} SphRect;

AW_FN SphRect sph_rect_make(float3 corner, float3 eu, float3 ev, float3 o) {
  SphRect r;
  float lu = length(eu), lv = length(ev);
  r.o = o;
  r.x = eu / lu;
  r.y = ev / lv;
  r.z = cross(r.x, r.y);
  float3 d = corner - o;
  r.z0 = dot(d, r.z);
  if (r.z0 > 0.0f) {  // look at the rectangle from the z < 0 side
    r.z = -r.z;
    r.z0 = -r.z0;
  }
  r.x0 = dot(d, r.x);
  r.y0 = dot(d, r.y);
  r.x1 = r.x0 + lu;
  r.y1 = r.y0 + lv;
  // Normals of the planes through o and each edge (Sec. 3, written out for the local frame).
  float3 n0 = normalize(make_float3(0.0f, r.z0, -r.y0));
  float3 n1 = normalize(make_float3(-r.z0, 0.0f, r.x1));
  float3 n2 = normalize(make_float3(0.0f, -r.z0, r.y1));
  float3 n3 = normalize(make_float3(r.z0, 0.0f, -r.x0));
  float g0 = acos(clamp(-dot(n0, n1), -1.0f, 1.0f));
  float g1 = acos(clamp(-dot(n1, n2), -1.0f, 1.0f));
  float g2 = acos(clamp(-dot(n2, n3), -1.0f, 1.0f));
  float g3 = acos(clamp(-dot(n3, n0), -1.0f, 1.0f));
  r.b0 = n0.z;
  r.b1 = n2.z;
  r.k = 2.0f * M_PI_F - g2 - g3;
  r.S = g0 + g1 - r.k;
  return r;
}

// The point for u in [0, 1)^2 (Sec. 5, Algorithm 1).
AW_FN float3 sph_rect_sample(const SphRect* r, float2 u) {
  float au = u.x * r->S + r->k;
  float fu = (cos(au) * r->b0 - r->b1) / sin(au);
  float cu = copysign(1.0f, fu) / sqrt(fu * fu + r->b0 * r->b0);
  cu = clamp(cu, -1.0f, 1.0f);
  float xu = -(cu * r->z0) / safe_sqrt(1.0f - cu * cu);
  xu = clamp(xu, r->x0, r->x1);
  float dd = sqrt(xu * xu + r->z0 * r->z0);
  float h0 = r->y0 / sqrt(dd * dd + r->y0 * r->y0);
  float h1 = r->y1 / sqrt(dd * dd + r->y1 * r->y1);
  float hv = h0 + u.y * (h1 - h0);
  float hv2 = hv * hv;
  float yv = hv2 < 1.0f - 1e-6f ? (hv * dd) / sqrt(1.0f - hv2) : r->y1;
  yv = clamp(yv, r->y0, r->y1);
  return r->o + xu * r->x + yv * r->y + r->z0 * r->z;
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
//   difference of angles near 2 pi in single precision, ~4e-7 sr of absolute error, relative
//   1e-7 at 0.2-2 sr, 4e-5 at 1e-2 sr, 1.5e-3 at 4e-4 sr against the closed form.)
// - Within 1e-2 sr of 2 pi (a point just above a huge light) the mapping degenerates; it is
//   still exact to 4e-6 at 6.17 sr (0.01 above a unit square).
#define AW_SPH_RECT_MIN_SOLID_ANGLE 1.0f
#define AW_SPH_RECT_MAX_SOLID_ANGLE (2.0f * M_PI_F - 1e-2f)

// Whether quad light l is sampled by solid angle from p, and the spherical rectangle if so.
// light_sample and light_pdf both decide here, from the same inputs, so MIS sees the density
// that produced the sample.
AW_FN int light_quad_by_solid_angle(const AW_GLOBAL LightGpu* l, float3 p, SphRect* r) {
  if (!(l->flags & AW_LIGHT_RECTANGLE)) return 0;
  // Skip the four acos when a cheap bound already says the light is too small, or when p is
  // behind a one-sided light (which gives it nothing whichever way it samples). The bound: the
  // solid angle is the integral of |h| / r^3 over the rectangle (h: p's distance to its
  // plane, r: to the point), so S <= A |h| / d^3 with d the distance from p to the nearest
  // point of the rectangle (its edges are orthogonal, so that point is p's projection clamped
  // to them). Tighter than A / h^2 beside the light, where the receiving points of a room
  // mostly are (measured: the acos of rejected rectangles were 2.4% of the spheres' render
  // on PoCL). It only skips what the exact S would reject, so images do not change.
  float3 c = load_f3(l->p), eu = load_f3(l->u), ev = load_f3(l->v);
  float3 pc = p - c;
  float h = dot(load_f3(l->n), pc);
  if (h <= 0.0f && !(l->flags & AW_LIGHT_TWO_SIDED)) return 0;
  float su = clamp(dot(pc, eu) / dot(eu, eu), 0.0f, 1.0f), sv = clamp(dot(pc, ev) / dot(ev, ev), 0.0f, 1.0f);
  float3 dq = pc - su * eu - sv * ev;
  float d2 = dot(dq, dq);
  if (l->area * fabs(h) < AW_SPH_RECT_MIN_SOLID_ANGLE * d2 * sqrt(d2)) return 0;
  *r = sph_rect_make(load_f3(l->p), load_f3(l->u), load_f3(l->v), p);
  return r->S > AW_SPH_RECT_MIN_SOLID_ANGLE && r->S < AW_SPH_RECT_MAX_SOLID_ANGLE && isfinite(r->S);
}

// Uniform area sampling of a flat light (quad, disk, triangle) converted to solid angle at
// distance t along unit dir: t^2 / (A cos_l) (Veach 1997, Sec. 9.2).
AW_FN float light_area_pdf(const AW_GLOBAL LightGpu* l, float3 dir, float t) {
  float cos_l = fabs(dot(load_f3(l->n), dir));
  return cos_l > 0.0f ? (t * t) / (l->area * cos_l) : 0.0f;
}

// Solid-angle pdf (given the light is chosen) of reaching `l` from `p` along unit `dir`,
// hitting it at distance `t`. Must match light_sample exactly (MIS relies on it).
AW_FN float light_pdf(const AW_GLOBAL LightGpu* l, float3 p, float3 dir, float t) {
  if (AW_FEAT_LIGHT_POINT && l->type == AW_LIGHT_POINT) return 0.0f;
  if (AW_FEAT_LIGHT_SUN && l->type == AW_LIGHT_SUN) return sun_pdf(l, dir);
  if (AW_FEAT_LIGHT_SPHERE && l->type == AW_LIGHT_SPHERE) {
    float3 c = load_f3(l->p);
    float3 pc = c - p;
    float d2 = dot(pc, pc);
    float r2 = l->radius * l->radius;
    if (d2 > r2) {
      // Uniform cone sampling: pbrt-v3, Sec. 14.2.2 ("Sampling Spheres").
      float omc = sphere_one_minus_cos_max(r2 / d2);
      return 1.0f / (2.0f * M_PI_F * omc);
    }
    float3 y = p + t * dir;
    float cos_l = fabs(dot(normalize(y - c), dir));
    return cos_l > 0.0f ? (t * t) / (l->area * cos_l) : 0.0f;
  }
  SphRect r;
  if (AW_FEAT_LIGHT_QUAD && l->type == AW_LIGHT_QUAD && light_quad_by_solid_angle(l, p, &r)) return 1.0f / r.S;
  return light_area_pdf(l, dir, t);
}

// Samples a point on light `l` as seen from `p` (Veach 1997, Sec. 9.2: area sampling
// converted to solid angle by dist^2 / cos). pdf = 0 when the sample cannot contribute.
AW_FN LightSample light_sample(const AW_GLOBAL LightGpu* l, float3 p, float2 u) {
  LightSample s;
  s.is_delta = 0;
  s.pdf = 0.0f;
  s.le = make_float3(0.0f, 0.0f, 0.0f);
  s.dist = 0.0f;
  s.wi = make_float3(0.0f, 0.0f, 1.0f);
  float3 y;
  float pdf_solid_angle = 0.0f;  // set when the point was drawn uniformly in solid angle
  int sphere_inside = 0;         // drawn on a sphere's surface from inside it (light_pdf's density)
  if (AW_FEAT_LIGHT_SUN && l->type == AW_LIGHT_SUN) return sun_sample(l, u);
  if (AW_FEAT_LIGHT_POINT && l->type == AW_LIGHT_POINT) {
    float3 d = load_f3(l->p) - p;
    float d2 = dot(d, d);
    if (!(d2 > 0.0f)) return s;
    s.dist = sqrt(d2);
    s.wi = d / s.dist;
    s.le = load_f3(l->radiance) / d2;
    s.pdf = 1.0f;
    s.is_delta = 1;
    return s;
  }
  if (AW_FEAT_LIGHT_SPHERE && l->type == AW_LIGHT_SPHERE) {
    float3 c = load_f3(l->p);
    float3 pc = c - p;
    float d2 = dot(pc, pc);
    float r2 = l->radius * l->radius;
    if (d2 > r2) {
      // Outside: sample the cone of directions the sphere subtends (pbrt-v3, Sec. 14.2.2).
      float dc = sqrt(d2);
      float omc = sphere_one_minus_cos_max(r2 / d2);
      float cos_t = 1.0f - u.x * omc;
      float sin2_t = fmax(0.0f, (1.0f - cos_t) * (1.0f + cos_t));
      float sp, cp;
      sincos_turn(u.y, &sp, &cp);  // phi = 2 pi u.y
      float3 w = pc / dc, t, b;
      make_frame(w, &t, &b);
      float sin_t = sqrt(sin2_t);
      s.wi = normalize(frame_to_world(make_float3(cp * sin_t, sp * sin_t, cos_t), t, b, w));
      // Nearest intersection along the sampled direction; the max() guards rays that graze
      // the silhouette by round-off.
      s.dist = dc * cos_t - safe_sqrt(r2 - d2 * sin2_t);
      s.pdf = 1.0f / (2.0f * M_PI_F * omc);
      s.le = load_f3(l->radiance);
      return s;
    }
    // Inside the sphere: uniform area sampling of its surface.
    float z = 1.0f - 2.0f * u.x;
    float rxy = safe_sqrt(1.0f - z * z);
    float sp, cp;
    sincos_turn(u.y, &sp, &cp);  // phi = 2 pi u.y
    float3 nrm = make_float3(rxy * cp, rxy * sp, z);
    y = c + l->radius * nrm;
    sphere_inside = 1;
  } else if (AW_FEAT_LIGHT_MESH && l->type == AW_LIGHT_TRIANGLE) {
    // Uniform by area: the square-root warp to barycentrics (Turk 1990, "Generating Random
    // Points in Triangles", Graphics Gems; PBR 3rd ed., Sec. 13.6.4). (Arvo's 1995 spherical
    // triangles would sample by solid angle; the fixtures' small triangles seen from afar
    // gain little from it, as the quads' measurement in docs/architecture.md shows.)
    float su = sqrt(u.x);
    y = load_f3(l->p) + (su * (1.0f - u.y)) * load_f3(l->u) + (su * u.y) * load_f3(l->v);
  } else if (AW_FEAT_LIGHT_QUAD && l->type == AW_LIGHT_QUAD) {
    SphRect r;
    if (light_quad_by_solid_angle(l, p, &r)) {
      y = sph_rect_sample(&r, u);
      pdf_solid_angle = 1.0f / r.S;
    } else {
      y = load_f3(l->p) + u.x * load_f3(l->u) + u.y * load_f3(l->v);
    }
  } else {  // disk
    float2 d = sample_concentric_disk(u);
    y = load_f3(l->p) + l->radius * (d.x * load_f3(l->u) + d.y * load_f3(l->v));
  }
  float3 d = y - p;
  float d2 = dot(d, d);
  if (!(d2 > 0.0f)) return s;
  s.dist = sqrt(d2);
  s.wi = d / s.dist;
  // Every other point was drawn uniformly by area on a flat light (triangle, quad, disk): its
  // density is the area one, taken directly, since light_pdf would dispatch on the type and,
  // for a quad, run the solid-angle test again (two divisions and a square root) only to reach
  // the same answer.
  float pdf = pdf_solid_angle > 0.0f ? pdf_solid_angle
              : sphere_inside        ? light_pdf(l, p, s.wi, s.dist)
                                     : light_area_pdf(l, s.wi, s.dist);
  if (!(pdf > 0.0f) || !isfinite(pdf)) return s;
  s.le = light_emitted(l, s.wi);
  s.pdf = pdf;
  return s;
}

// Distance along (org, dir) to area light `l` within (t_min, t_max), or -1.
AW_FN float light_intersect(const AW_GLOBAL LightGpu* l, float3 org, float3 dir, float t_min, float t_max) {
  if (AW_FEAT_LIGHT_POINT && l->type == AW_LIGHT_POINT) return -1.0f;
  // Lights at infinity are found by rays that escape the scene (classify_hit.h), triangle
  // lights as the geometry they are (classify_hit.h), not here.
  // (The switches are 0 or 1, so `|` is their "or"; `||` between constants makes clang warn,
  // -Wconstant-logical-operand, on every OpenCL compiler built on it: PoCL, Intel, NVIDIA.)
  if ((AW_FEAT_LIGHT_SUN | AW_FEAT_ENV_MAP | AW_FEAT_LIGHT_MESH) && l->type >= AW_LIGHT_SUN) return -1.0f;
  if (AW_FEAT_LIGHT_SPHERE && l->type == AW_LIGHT_SPHERE) {
    // Geometric form of the quadratic, stable for far spheres: the discriminant is formed
    // from the squared distance to the ray (Haines et al. 2019, Ray Tracing Gems Ch. 7, Eq. 8).
    float3 c = load_f3(l->p);
    float3 f = org - c;
    float b = -dot(f, dir);
    float3 perp = f + b * dir;
    float r2 = l->radius * l->radius;
    float disc = r2 - dot(perp, perp);
    if (disc < 0.0f) return -1.0f;
    float sq = sqrt(disc);
    float t0 = b - sq, t1 = b + sq;
    if (t0 > t_min && t0 < t_max) return t0;
    if (t1 > t_min && t1 < t_max) return t1;
    return -1.0f;
  }
  float3 n = load_f3(l->n);
  float denom = dot(n, dir);
  if (fabs(denom) < 1e-12f) return -1.0f;
  float3 p0 = load_f3(l->p);
  float t = dot(n, p0 - org) / denom;
  if (!(t > t_min && t < t_max)) return -1.0f;
  float3 q = org + t * dir - p0;
  if (AW_FEAT_LIGHT_QUAD && l->type == AW_LIGHT_QUAD) {
    // Parallelogram coordinates via cross products (edges need not be orthogonal).
    float3 eu = load_f3(l->u), ev = load_f3(l->v);
    float a = dot(cross(q, ev), n) / l->area;
    float bb = dot(cross(eu, q), n) / l->area;
    return (a >= 0.0f && a <= 1.0f && bb >= 0.0f && bb <= 1.0f) ? t : -1.0f;
  }
  return dot(q, q) <= l->radius * l->radius ? t : -1.0f;
}

// Closest area light along the ray, skipping `skip` (the light a shadow ray aims at) and, for
// camera rays, lights marked invisible. Returns the light index or -1; *t is updated.
AW_FN int lights_intersect(const AW_GLOBAL LightGpu* lights, uint num_lights, float3 org, float3 dir,
                           float t_min, float* t, int camera_ray, int skip) {
  int found = -1;
  for (uint i = 0; i < num_lights; ++i) {
    if ((int)i == skip) continue;
    if (camera_ray && !(lights[i].flags & AW_LIGHT_VISIBLE)) continue;
    float th = light_intersect(&lights[i], org, dir, t_min, *t);
    if (th > 0.0f) {
      *t = th;
      found = (int)i;
    }
  }
  return found;
}

#endif
