// Instance transforms (kernels/types/bvh.h, InstanceGpu): row-major 3 x 4 matrices [L | t],
// applied to points, vectors and normals. Shared by the traversal (world ray into object space)
// and the shading (object-space vertices into world space), on the device and in C++.
#ifndef AW_BVH_INSTANCE_H
#define AW_BVH_INSTANCE_H

#include "common/compat.h"
#include "types/bvh.h"

AW_FN float3 xform_point(const AW_GLOBAL float* m, float3 p) {
  return make_float3(m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3], m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7],
                     m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11]);
}

AW_FN float3 xform_vector(const AW_GLOBAL float* m, float3 v) {
  return make_float3(m[0] * v.x + m[1] * v.y + m[2] * v.z, m[4] * v.x + m[5] * v.y + m[6] * v.z,
                     m[8] * v.x + m[9] * v.y + m[10] * v.z);
}

// A normal transforms by the inverse transpose of the linear part (pbrt-v3 Sec. 2.8.3): with
// w2o = M^-1 at hand, that is w2o's linear part transposed. Not normalised.
AW_FN float3 xform_normal(const AW_GLOBAL float* w2o, float3 n) {
  return make_float3(w2o[0] * n.x + w2o[4] * n.y + w2o[8] * n.z, w2o[1] * n.x + w2o[5] * n.y + w2o[9] * n.z,
                     w2o[2] * n.x + w2o[6] * n.y + w2o[10] * n.z);
}

#endif
