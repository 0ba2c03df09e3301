// The scene a stage reads, bundled so that every stage takes (PathRef, SceneRef, RenderParams).
// The ray caster behind it differs by side (integrator/ray_cast.h): the flattened BVH on the
// device, Embree in the host scalar path.
#ifndef AW_INTEGRATOR_SCENE_REF_H
#define AW_INTEGRATOR_SCENE_REF_H

#include "common/compat.h"
#include "types/bvh.h"
#include "types/scene.h"
#include "texture/material_textures.h"

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
  const AW_GLOBAL TextureGpu* textures;       // textures (texture/texture.h), when the scene has them
  const AW_GLOBAL TexBindingGpu* tex_bindings;
  const AW_GLOBAL uchar* texels;
  // Instances of shared meshes (types/bvh.h): the traversal enters them, the shading takes
  // their vertices to world space (integrator/classify_hit.h), when the scene has them.
  const AW_GLOBAL InstanceGpu* insts;
  // Per path slot: the material of the path's shading point with its textures applied
  // (integrator/shading_material.h); the scalar path gives each thread its own.
  AW_GLOBAL MaterialGpu* mat_resolved;
#if AW_DEVICE
  const __global float4* nodes;  // the flattened BVH (kernels/types/bvh.h)
  const __global float4* tris;
  uint num_nodes;
#else
  const struct HostRayCaster* caster;
#endif
} SceneRef;

AW_FN TextureScene scene_texture_ref(SceneRef sc) {
  TextureScene ts;
  ts.tri_info = sc.tri_info;
  ts.verts = sc.verts;
  ts.materials = sc.materials;
  ts.textures = sc.textures;
  ts.bindings = sc.tex_bindings;
  ts.texels = sc.texels;
  return ts;
}

#endif
