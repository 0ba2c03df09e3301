// OBJ with its Wavefront MTL materials: the OBJ's triangles grouped by the material their
// `usemtl` names, and the materials of the `mtllib` files converted to the Architectural
// material with their texture maps decoded. The same shape as the glTF importer's result
// (gltf_mesh.h), so that the scene loader can treat both alike. The mapping of MTL statements
// and what is approximated or ignored: docs/obj-mtl.md. Private to host/scene.
#pragma once

#include <string>
#include <vector>

#include "host/scene/gltf_mesh.h"
#include "host/scene/material_desc.h"
#include "host/scene/texture_desc.h"

namespace aw {
namespace scene_detail {

// An OBJ read with its MTL libraries has the shape of a glTF import (gltf_mesh.h), so the
// scene loader takes both the same way. What the fields hold for an OBJ:
//   primitives: one per material that some triangle uses, in order of first use in the file;
//     material -1 gathers the triangles without one (no usemtl before them, or a usemtl name
//     that no loaded library defines). Each is de-indexed like load_obj's mesh (unique
//     (position, normal, uv) corners in order of first use within the primitive), in the OBJ's
//     own space, UVs as the file has them (OBJ's v points up the image, as TextureDesc
//     expects). A primitive keeps normals (UVs) when every corner of its triangles has a valid
//     one, so a textured part keeps its UVs even when another part has none. Empty when the
//     file has no triangles.
//   material_names: every material the mtllib files define, in the order they are defined
//     (libraries in the order the OBJ names them); a name defined twice keeps its first
//     definition (warning). The names are the MTL's own ("OBJFILE#name" is the caller's).
//   materials, bindings: as for glTF; MaterialDesc::textures is left empty, bindings[i] index
//     `textures` (to be offset when these are appended to Scene::textures).
//   textures: decoded by load_texture_file, one per distinct (image file, colour space, -s / -o
//     / -clamp) that some material uses, named after the file as the MTL writes it
//     ("tex/wood.png", then "tex/wood.png (2)", ... for further forms); `source` is the
//     resolved path.
using ObjImport = GltfImport;

// Reads an OBJ and the MTL files its `mtllib` statements name, relative to the OBJ's folder;
// texture maps are relative to the folder of the .mtl that names them. The OBJ is checked
// exactly as load_obj checks it (same numbers, indices and messages). A missing .mtl file is a
// warning (the faces using its materials take material -1); a malformed one (a value that is
// not a number, a wrong count of values, an unknown texture option, a statement before
// `newmtl`, ...) is an error naming the .mtl file, the line and what is wrong; so is a texture
// map that cannot be loaded (naming the material, the statement and the file). On failure
// returns false with *error set (without the OBJ's path) and *out empty. Warnings (approximated
// or ignored statements, without the OBJ's path; once per material and statement) are
// appended to `warnings` (may be null).
bool load_obj_with_materials(const std::string& resolved_path, ObjImport* out, std::string* error,
                             std::vector<std::string>* warnings);

}  // namespace scene_detail
}  // namespace aw
