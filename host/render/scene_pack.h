// Turns a loaded Scene into the flat arrays the kernels (and the scalar path) read.
#pragma once

#include <string>
#include <vector>

#include "host/bvh/flat_bvh.h"
#include "host/render/features.h"
#include "host/scene/scene.h"
#include "kernels/common/compat.h"
#include "kernels/common/features.h"
#include "kernels/types/bvh.h"
#include "kernels/types/scene.h"

namespace aw {

struct PackedScene {
  TriangleSoup soup;  // world-space triangles, global ids (BVH and Embree input)
  std::vector<TriangleInfo> tri_info;
  std::vector<VertexData> verts;
  std::vector<MaterialGpu> materials;
  std::vector<LightGpu> lights;      // lights at infinity first (num_infinite of them)
  uint32_t num_infinite = 0;
  std::vector<float> env;            // the environment map's buffer (kernels/lights/environment.h), or empty
  std::vector<LightTreeNode> light_tree;  // many lights (kernels/lights/light_tree.h), or empty
  float tree_prob = 0.0f;                 // with a tree: the probability of choosing among its lights
  std::vector<uint32_t> tri_light;        // per triangle its mesh light or AW_NONE; empty without mesh lights
  int env_width = 0, env_height = 0;
  // Textures (kernels/texture/texture.h; host/render/texture_pack.h): empty without them.
  std::vector<TextureGpu> textures;
  std::vector<TexBindingGpu> tex_bindings;
  std::vector<uint8_t> texels;
  RenderParams params{};  // camera, environment, settings; pool and batch fields left 0
  FeatureSet features;    // what the scene uses (decide_features), decided once here
};

// Throws SceneError for a scene that cannot be rendered (a degenerate camera). Appends
// notes about parameters the current kernels do not render yet to *warnings. Decides the
// scene's features (decide_features) and the parameters that follow from them (split_spp).
PackedScene pack_scene(const Scene& scene, std::vector<std::string>* warnings);

// Bytes of the arrays both renderers read besides a BVH (instances, triangle info, vertices,
// materials, lights): the scene's share of the memory in the stats.
inline size_t packed_arrays_bytes(const PackedScene& p) {
  return p.soup.instances.size() * sizeof(InstanceGpu) + p.tri_info.size() * sizeof(TriangleInfo) + p.verts.size() * sizeof(VertexData) +
         p.materials.size() * sizeof(MaterialGpu) + p.lights.size() * sizeof(LightGpu) + p.env.size() * sizeof(float) +
         p.light_tree.size() * sizeof(LightTreeNode) + p.tri_light.size() * sizeof(uint32_t) +
         p.textures.size() * sizeof(TextureGpu) + p.tex_bindings.size() * sizeof(TexBindingGpu) + p.texels.size();
}

// What a sample's value depends on, as a 64-bit hash (FNV-1a over bytes): every array the
// renderers read and the render parameters except the per-launch ones (batch, pool) and the
// film's window and sample range, which select samples without changing any. Parts and
// resumed renders of one scene must agree on it (docs/production.md); a different material,
// light, mesh, camera, seed, depth or sampler gives another. (The structs' padding is explicit
// and zero-initialised, so equal scenes hash equally: tests/render/test_parts.cpp.)
uint64_t scene_identity(const PackedScene& p);

}  // namespace aw
