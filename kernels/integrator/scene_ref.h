// The scene buffers a shading stage reads, bundled so stage signatures stay short.
#ifndef AW_INTEGRATOR_SCENE_REF_H
#define AW_INTEGRATOR_SCENE_REF_H

#include "common/compat.h"
#include "types/bvh.h"
#include "types/scene.h"

typedef struct {
  const AW_GLOBAL TriangleInfo* tri_info;
  const AW_GLOBAL VertexData* verts;
  const AW_GLOBAL MaterialGpu* materials;
  const AW_GLOBAL LightGpu* lights;
} SceneRef;

#endif
