// Analytic spheres (objects[].shape "sphere"): the ray-sphere test of the traversal, and the
// sphere's parametrisation (UV, dP/du, dP/dv) as the tessellated sphere had it
// (host/scene/geometry.cpp, make_sphere), so textures, anisotropy and bump read the same.
// Shared by the device traversal, the scalar path's Embree user geometry and classify_hit.
#ifndef AW_BVH_INTERSECT_SPHERE_H
#define AW_BVH_INTERSECT_SPHERE_H

#include "common/compat.h"
#include "common/lanes.h"

// Nearest t in (t_min, t_max) where org + t dir meets the sphere (c, r), or 0 for none.
// The quadratic's discriminant is computed as r^2 - |f - (f.d / d.d) d|^2 with f = org - c,
// which loses no precision when the ray passes far from the centre, and the two roots as
// c'/q and q/a with q = b' + sign(b') sqrt(a disc), which avoids cancellation (Haines,
// Günther & Akenine-Möller 2019, "Precision Improvements for Ray/Sphere Intersection", Ray
// Tracing Gems ch. 7, Sec. 7.2.2 and eq. 7.8-7.10).
// On lanes (common/lanes.h): W rays against one sphere at W > 1; where it returns false,
// *t_hit holds anything.
AW_FN lmask intersect_sphere(lfloat3 org, lfloat3 dir, float3 c, float r, lfloat t_min, lfloat t_max, lfloat* t_hit) {
  lfloat3 f = l3_sub(org, l3_bcast(c));
  lfloat a = l3_dot(dir, dir);
  lfloat b = -l3_dot(f, dir);  // b' = -f.d (the half b, sign flipped)
  lfloat3 l = l3_add(f, l3_scale(dir, b / a));
  lfloat disc = r * r - l3_dot(l, l);
  lmask hit = disc >= 0.0f && a > 0.0f;
  if (!L_ANY(hit)) return hit;
  lfloat cc = l3_dot(f, f) - r * r;
  lfloat q = b + copysign(sqrt(a * disc), b);
  lfloat t0 = L_SEL(q != 0.0f, cc / q, (lfloat)(0.0f));
  lfloat t1 = q / a;
  lfloat lo = fmin(t0, t1), hi = fmax(t0, t1);
  lmask lo_in = lo > t_min && lo < t_max, hi_in = hi > t_min && hi < t_max;
  *t_hit = L_SEL(lo_in, lo, hi);
  return hit && (lo_in || hi_in);
}

// The sphere's frame: its pole axis y (UV v runs from -y to +y) and the axis x where u = 0,
// z = x cross y (make_sphere's local direction is (sin t cos p, -cos t, -sin t sin p) for
// u = p / 2 pi, v = t / pi). `w` is the unit direction from the centre to the point.
AW_FN float2 sphere_uv(float3 w, float3 ax, float3 ay) {
  float3 az = cross(ax, ay);
  float x = dot(w, ax), y = dot(w, ay), z = dot(w, az);
  float v = acos(clamp(-y, -1.0f, 1.0f)) / M_PI_F;
  float u = atan2(-z, x) / (2.0f * M_PI_F);
  return make_float2(u < 0.0f ? u + 1.0f : u, v);
}

// dP/du and dP/dv at UV (u, v) of a sphere of radius r (the derivatives of make_sphere's
// position): dP/du = 2 pi r sin t (-sin p, 0, -cos p), dP/dv = pi r (cos t cos p, sin t, -cos t sin p).
AW_FN void sphere_dpduv(float2 uv, float r, float3 ax, float3 ay, float3* dpdu, float3* dpdv) {
  float3 az = cross(ax, ay);
  float p = 2.0f * M_PI_F * uv.x, th = M_PI_F * uv.y;
  float sp = sin(p), cp = cos(p), st = sin(th), ct = cos(th);
  *dpdu = (ax * (-sp) + az * (-cp)) * (2.0f * M_PI_F * r * st);
  *dpdv = (ax * (ct * cp) + ay * st + az * (-ct * sp)) * (M_PI_F * r);
}

#endif
