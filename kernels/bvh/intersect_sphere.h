// Analytic spheres (objects[].shape "sphere"): the ray-sphere test of the traversal, and the
// sphere's parametrisation (UV, dP/du, dP/dv) as the tessellated sphere had it
// (host/scene/geometry.cpp, make_sphere), so textures, anisotropy and bump read the same.
// Shared by the device traversal, the scalar path's Embree user geometry and classify_hit.
#ifndef AW_BVH_INTERSECT_SPHERE_H
#define AW_BVH_INTERSECT_SPHERE_H

#include "common/compat.h"

// Nearest t in (t_min, t_max) where org + t dir meets the sphere (c, r), or 0 for none.
// The quadratic's discriminant is computed as r^2 - |f - (f.d / d.d) d|^2 with f = org - c,
// which loses no precision when the ray passes far from the centre, and the two roots as
// c'/q and q/a with q = b' + sign(b') sqrt(a disc), which avoids cancellation (Haines,
// Günther & Akenine-Möller 2019, "Precision Improvements for Ray/Sphere Intersection", Ray
// Tracing Gems ch. 7, Sec. 7.2.2 and eq. 7.8-7.10).
AW_FN int intersect_sphere(float3 org, float3 dir, float3 c, float r, float t_min, float t_max, float* t_hit) {
  float3 f = org - c;
  float a = dot(dir, dir);
  float b = -dot(f, dir);  // b' = -f.d (the half b, sign flipped)
  float3 l = f + dir * (b / a);
  float disc = r * r - dot(l, l);
  if (!(disc >= 0.0f) || !(a > 0.0f)) return 0;
  float cc = dot(f, f) - r * r;
  float q = b + copysign(sqrt(a * disc), b);
  float t0 = q != 0.0f ? cc / q : 0.0f;
  float t1 = q / a;
  float lo = fmin(t0, t1), hi = fmax(t0, t1);
  if (lo > t_min && lo < t_max) {
    *t_hit = lo;
    return 1;
  }
  if (hi > t_min && hi < t_max) {
    *t_hit = hi;
    return 1;
  }
  return 0;
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
