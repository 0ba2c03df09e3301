// glTF 2.0 import (.gltf with external or data-URI buffers and images, and .glb) through
// tinygltf: the default scene's mesh primitives, flattened into the glTF scene's space, and
// the glTF materials converted to the Architectural material with their textures decoded.
// The mapping of materials is documented in docs/gltf.md. Private to host/scene.
#pragma once

#include <string>
#include <vector>

#include "host/scene/loader_parts.h"
#include "host/scene/material_desc.h"
#include "host/scene/texture_desc.h"

namespace aw {
namespace scene_detail {

struct GltfPrimitive {
  // In the glTF scene's space: every node transform of the hierarchy applied (in double
  // precision); normals by the inverse transpose and renormalised; tangents (xyz, w =
  // handedness) by the matrix, made orthogonal to the normal and renormalised, w negated under
  // a mirroring transform; winding flipped under a mirroring transform (finalize_mesh's
  // conventions, geometry.cpp). UVs are TEXCOORD_0 with V flipped, (u, 1 - v), so that image
  // row 0 is at V = 1 as TextureDesc expects. Normals, uvs and tangents are each empty or one
  // per position.
  DMesh mesh;
  int material = -1;  // index into GltfImport::materials; -1 = none given (the loader's default)
  std::string name;   // "mesh 'Chair' primitive 0 (node 'Chair.001')", for messages
};

struct GltfImport {
  // One entry per mesh primitive reached from the scene's nodes (a mesh instanced by several
  // nodes appears once per node), depth first in the nodes' order. May be empty (a scene
  // without meshes, or with only skipped primitives).
  std::vector<GltfPrimitive> primitives;
  std::vector<std::string> material_names;  // glTF material names ("material 3" when unnamed)
  // Same order and size as the glTF materials array. MaterialDesc::textures is left empty: a
  // material's texture inputs are bindings[i], whose TextureRef::texture indexes `textures`
  // below (to be offset when these are appended to Scene::textures).
  std::vector<MaterialDesc> materials;
  std::vector<TextureBindings> bindings;
  // Decoded by decode_texture_image / load_texture_file, one per distinct (glTF texture, colour
  // space, KHR_texture_transform) combination that some material uses.
  std::vector<TextureDesc> textures;
};

// Reads a .gltf (JSON plus external or data-URI buffers and images) or a .glb, recognised by
// its content. On any problem returns false with *error set to a message that names what is
// wrong (which accessor, mesh, buffer, image, ...) without repeating the path, and *out empty;
// never crashes or hangs on a malformed file. Warnings (approximated or ignored features,
// without the path) are appended to `warnings` (may be null); docs/gltf.md lists them.
bool load_gltf(const std::string& resolved_path, GltfImport* out, std::string* error,
               std::vector<std::string>* warnings);

}  // namespace scene_detail
}  // namespace aw
