// Embree builds the tree (SAH, rtcBuildBVH); a single-threaded depth-first pass flattens it
// into the layout the kernels traverse (kernels/types/bvh.h, docs/bvh-layout.md).
// Also: the Embree scene the host scalar path and the tests cast rays with.
#pragma once

#include <embree3/rtcore.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "kernels/types/bvh.h"
#include "kernels/texture/material_textures.h"

namespace aw {

class EmbreeDevice {
 public:
  EmbreeDevice();
  ~EmbreeDevice();
  EmbreeDevice(const EmbreeDevice&) = delete;
  EmbreeDevice& operator=(const EmbreeDevice&) = delete;
  RTCDevice get() const { return device_; }

 private:
  RTCDevice device_;
};

// A shared mesh (instancing): triangles [first_tri, first_tri + tri_count) of the soup, in
// object space, with their own tree in the flattened BVH.
struct SoupPrototype {
  uint32_t first_tri = 0;
  uint32_t tri_count = 0;
};

// All triangles of the scene in one list: ids are indices into `indices` (Embree's primID).
// Those before the first prototype's are in world space; the prototypes' follow, in object space. Then the
// analytic spheres (centre, radius), whose ids follow the triangles': sphere k is primitive
// indices.size() + k (kernels/bvh/intersect_sphere.h). Then the instances, each a placement of
// a prototype (kernels/types/bvh.h, InstanceGpu: its transforms and prototype; build_flat_bvh
// sets the root of the prototype's tree).
struct TriangleSoup {
  std::vector<glm::vec3> positions;
  std::vector<glm::uvec3> indices;
  std::vector<glm::vec4> spheres;
  std::vector<SoupPrototype> prototypes;
  std::vector<InstanceGpu> instances;
  size_t primitive_count() const { return indices.size() + spheres.size(); }
  size_t world_tris() const { return prototypes.empty() ? indices.size() : prototypes.front().first_tri; }
};

// Object-space bounds of each prototype (lo, hi), computed once for all its instances.
std::vector<std::pair<glm::vec3, glm::vec3>> prototype_bounds(const TriangleSoup& soup);

// World-space bounds of an instance: its prototype's object-space box (`protos`, from
// prototype_bounds) carried through the instance's transform (its eight corners).
void instance_bounds(const TriangleSoup& soup, size_t instance, const std::vector<std::pair<glm::vec3, glm::vec3>>& protos,
                     glm::vec3* lo, glm::vec3* hi);

struct FlatBvh {
  std::vector<BvhNode> nodes;        // nodes[0] is the root; empty for a scene with no triangles
  std::vector<LeafTriangle> leaf_tris;
  // The soup's instances, each with the root of its prototype's tree (docs/bvh-layout.md#instances).
  std::vector<InstanceGpu> instances;
  int max_depth = 0;             // of the top-level tree (the only one without instances)
  int max_prototype_depth = 0;   // of the deepest prototype's tree
  size_t leaf_count = 0;
  double build_seconds = 0.0;    // Embree builds
  double flatten_seconds = 0.0;  // our depth-first passes
};

// Deterministic: the same soup gives byte-identical nodes and leaf_tris.
FlatBvh build_flat_bvh(const EmbreeDevice& device, const TriangleSoup& soup);

// Embree's own scene over the same triangles (robust mode: watertight like our kernels).
class EmbreeScene {
 public:
  // With `cutouts`, Embree's filter functions drop hits in cutout holes (opacity below 0.5,
  // kernels/texture/material_textures.h, material_opaque_at: the same test the device's
  // traversal makes) for closest-hit and occlusion queries alike. The pointed-to arrays must
  // outlive the scene.
  EmbreeScene(const EmbreeDevice& device, const TriangleSoup& soup, const TextureScene* cutouts = nullptr);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;
  RTCScene get() const { return scene_; }

  struct Hit {
    float t;
    float u, v;
    int prim;    // -1 = miss
    uint32_t inst;  // the soup's instance it was hit in, AW_NONE for world geometry
  };
  Hit intersect(glm::vec3 org, glm::vec3 dir, float t_min, float t_max) const;
  bool occluded(glm::vec3 org, glm::vec3 dir, float t_min, float t_max) const;

 private:
  RTCScene scene_ = nullptr;
  TextureScene cutouts_{};
  bool has_cutouts_ = false;
  const TriangleSoup* soup_ = nullptr;  // the spheres, for the user geometry's callbacks
  unsigned sphere_geom_ = RTC_INVALID_GEOMETRY_ID;
  // Instancing: one Embree scene per prototype, one instance geometry per instance (its
  // geometry id maps back to the soup's instance), and per triangle geometry the first
  // triangle id, for the cutout filter (a prototype's primIDs count from 0).
  std::vector<RTCScene> prototype_scenes_;
  std::vector<uint32_t> instance_of_geom_;
  struct CutoutGeom {
    const TextureScene* ts;
    uint32_t base;
  };
  std::vector<CutoutGeom> cutout_geoms_;

 public:
  // For the user geometry's callbacks (flat_bvh.cpp).
  const TriangleSoup& soup() const { return *soup_; }
  const TextureScene* cutouts() const { return has_cutouts_ ? &cutouts_ : nullptr; }
};

}  // namespace aw
