// The scene a stage reads, bundled so that every stage takes (PathRef, SceneRef, RenderParams).
// The ray caster behind it differs by side (integrator/ray_cast.h): the flattened BVH on the
// device, Embree in the host scalar path.
#ifndef AW_INTEGRATOR_SCENE_REF_H
#define AW_INTEGRATOR_SCENE_REF_H

#include "common/compat.h"
#include "types/bvh.h"
#include "types/scene.h"

#if !AW_DEVICE
struct HostRayCaster;  // host/scalar/ray_cast_embree.cpp
#endif

typedef struct {
  const AW_GLOBAL TriangleInfo* tri_info;
  const AW_GLOBAL VertexData* verts;
  const AW_GLOBAL MaterialGpu* materials;
  const AW_GLOBAL LightGpu* lights;
  const AW_GLOBAL float* env;  // the environment map (lights/environment.h), when the scene has one
  const AW_GLOBAL LightTreeNode* light_tree;  // many lights (lights/light_tree.h), when the scene has it
  const AW_GLOBAL uint* tri_light;  // per triangle its light or AW_NONE, when the scene has mesh lights
#if AW_DEVICE
  const __global float4* nodes;  // the flattened BVH (kernels/types/bvh.h)
  const __global float4* tris;
  uint num_nodes;
#else
  const struct HostRayCaster* caster;
#endif
  // Whether shadow rays must step through cutout surfaces (intersect_shadow.h). A device
  // build knows it when it is compiled (AW_FEAT_CUTOUT); the scalar path is one generic build
  // for every scene, so it is told by the scene's features, and takes the cheaper occlusion
  // query when there are none.
  int cutouts;
} SceneRef;

#endif
