// The steps of reading an OBJ that load_obj (loader_parts.h) and load_obj_with_materials
// (obj_materials.h) share, so that both check a file the same way and with the same messages:
// read the text and check its numbers, parse it with tinyobjloader and check every face's
// indices, then de-index chosen triangles into a DMesh. Implemented in obj_mesh.cpp. Private to
// host/scene.
#pragma once

#include <tiny_obj_loader.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "host/scene/loader_parts.h"

namespace aw {
namespace scene_detail {

// A decimal number as OBJ writers emit it: [+-] digits [. digits] [e [+-] digits] (or a leading
// "."); "nan", "inf", "1,5" and words are not.
bool is_decimal_number(const std::string& t);

// Reads the whole file into *text and checks that every value of its v, vn and vt lines is a
// finite decimal number that fits a float. On failure returns false with a message without the
// path ("no such file", "line 4: 'v' value \"nan\" is not a finite decimal number", ...).
bool read_obj_text(const std::string& resolved_path, std::string* text, std::string* error);

struct ObjData {
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  // Filled by the material reader given to parse_obj_text (none: empty); shape_t's per-face
  // material_ids index it, -1 for faces without a (known) material.
  std::vector<tinyobj::material_t> materials;
  // Every face corner of the file has a normal (a texture coordinate); false for a file with
  // no faces.
  bool all_normals = false, all_uvs = false;
};

// Parses `text` with tinyobjloader (polygons triangulated as fans) and checks every triangle's
// indices in file order: a position that does not exist, or a normal / texture coordinate that
// does not exist while every corner of the file has one, fails with "face N of shape \"S\"
// refers to a vertex, normal or texture coordinate that does not exist". `materials` is
// tinyobjloader's reader for mtllib statements; nullptr ignores them. tinyobjloader's warnings
// are appended to `warnings` one line each.
bool parse_obj_text(const std::string& text, tinyobj::MaterialReader* materials, ObjData* out,
                    std::string* error, std::vector<std::string>* warnings);

// One triangle of the parsed file: its shape, its face within the shape, and the offset of its
// first corner in the shape's index list.
struct ObjTriangle {
  uint32_t shape = 0;
  uint32_t face = 0;
  size_t offset = 0;
};

// Every triangle of the file in file order (shapes in order, faces in order).
std::vector<ObjTriangle> obj_triangles(const ObjData& d);

// Appends `triangles` (indices checked by parse_obj_text) to an empty *out, turning each
// distinct (position, normal, uv) corner into one vertex in order of first use; normals (uvs)
// are taken only when `normals` (`uvs`) is true, and then every corner of `triangles` must have
// a valid one.
void deindex_obj(const ObjData& d, const std::vector<ObjTriangle>& triangles, bool normals, bool uvs,
                 DMesh* out);

// True when every normal of the mesh has a finite, non-zero length (so it can be renormalised).
bool obj_normals_usable(const DMesh& mesh);

}  // namespace scene_detail
}  // namespace aw
