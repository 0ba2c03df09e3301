// OBJ meshes through tinyobjloader: load_obj, and the reading steps it shares with
// load_obj_with_materials (obj_read.h, obj_materials.cpp).
#include "host/scene/obj_read.h"

#include <tiny_obj_loader.h>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unordered_map>

namespace aw {
namespace scene_detail {
namespace {

struct VertexKey {
  int position, normal, uv;
  bool operator==(const VertexKey& o) const {
    return position == o.position && normal == o.normal && uv == o.uv;
  }
};

struct VertexKeyHash {
  size_t operator()(const VertexKey& k) const {
    // Only used for lookups; vertex order comes from first use, so the hash never affects
    // the output.
    uint64_t h = static_cast<uint32_t>(k.position);
    h = h * 0x9E3779B97F4A7C15ull ^ static_cast<uint32_t>(k.normal);
    h = h * 0x9E3779B97F4A7C15ull ^ static_cast<uint32_t>(k.uv);
    return static_cast<size_t>(h ^ (h >> 29));
  }
};

// Every value of the vertex data lines (v, vn, vt) is a finite decimal number; otherwise
// names the line, the statement and the value. Values that overflow float (1e999) are
// refused here too, with their line.
bool check_obj_numbers(const std::string& text, std::string* error) {
  std::istringstream lines(text);
  size_t line_no = 0;
  for (std::string line; std::getline(lines, line);) {
    ++line_no;
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream words(line);
    std::string keyword;
    if (!(words >> keyword) || (keyword != "v" && keyword != "vn" && keyword != "vt")) continue;
    for (std::string value; words >> value;) {
      const bool number = is_decimal_number(value);
      if (!number || !std::isfinite(static_cast<float>(std::strtod(value.c_str(), nullptr)))) {
        *error = "line " + std::to_string(line_no) + ": '" + keyword + "' value \"" + value +
                 (number ? "\" is out of the range of float" : "\" is not a finite decimal number");
        return false;
      }
    }
  }
  return true;
}

}  // namespace

// A decimal number as OBJ writers emit it: [+-] digits [. digits] [e [+-] digits] (or a
// leading "."). tinyobjloader turns anything else, "nan", "inf", "1,5" or a word, silently
// into 0, so such a file would render with vertices moved to the origin.
bool is_decimal_number(const std::string& t) {
  size_t i = 0, n = t.size();
  if (i < n && (t[i] == '+' || t[i] == '-')) ++i;
  size_t digits = 0;
  while (i < n && std::isdigit(static_cast<unsigned char>(t[i]))) ++i, ++digits;
  if (i < n && t[i] == '.') {
    ++i;
    while (i < n && std::isdigit(static_cast<unsigned char>(t[i]))) ++i, ++digits;
  }
  if (digits == 0) return false;
  if (i < n && (t[i] == 'e' || t[i] == 'E')) {
    ++i;
    if (i < n && (t[i] == '+' || t[i] == '-')) ++i;
    size_t exp_digits = 0;
    while (i < n && std::isdigit(static_cast<unsigned char>(t[i]))) ++i, ++exp_digits;
    if (exp_digits == 0) return false;
  }
  return i == n;
}

// ---- the steps load_obj and load_obj_with_materials share (obj_read.h) ----------------------

bool read_obj_text(const std::string& resolved_path, std::string* text, std::string* error) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(resolved_path, ec);
  if (!fs::exists(status)) {
    *error = "no such file";
    return false;
  }
  if (fs::is_directory(status)) {
    *error = "is a directory, not a file";
    return false;
  }
  // Read the whole file ourselves: tinyobjloader reports an unreadable file only as a
  // generic message, and we want the OS reason (permission denied, ...).
  std::ifstream file(resolved_path, std::ios::binary);
  if (!file.is_open()) {
    *error = std::string("cannot open: ") + std::strerror(errno);
    return false;
  }
  std::ostringstream contents;
  contents << file.rdbuf();
  if (file.bad()) {
    *error = "read error";
    return false;
  }
  *text = contents.str();
  return check_obj_numbers(*text, error);
}

bool parse_obj_text(const std::string& text, tinyobj::MaterialReader* materials, ObjData* out,
                    std::string* error, std::vector<std::string>* warnings) {
  std::istringstream stream(text);
  std::string warn, err;
  // Polygons are triangulated as fans.
  const bool ok = tinyobj::LoadObj(&out->attrib, &out->shapes, &out->materials, &warn, &err, &stream,
                                   materials, /*triangulate=*/true,
                                   /*default_vcols_fallback=*/false);
  if (!ok || !err.empty()) {
    // tinyobjloader ends its messages with newlines; keep the message on one line.
    std::string message = err.empty() ? "unknown OBJ parse failure" : err;
    while (!message.empty() && (message.back() == '\n' || message.back() == '\r')) {
      message.pop_back();
    }
    *error = "OBJ parse error: " + message;
    return false;
  }
  if (!warn.empty()) {
    std::istringstream lines(warn);
    for (std::string line; std::getline(lines, line);) {
      if (!line.empty()) warnings->push_back(line);
    }
  }

  const size_t num_positions = out->attrib.vertices.size() / 3;
  const size_t num_normals = out->attrib.normals.size() / 3;
  const size_t num_uvs = out->attrib.texcoords.size() / 2;

  // Normals and UVs are kept only when every face corner has them; a partial set could not
  // be represented by per-vertex arrays of the mesh's full size.
  bool all_normals = true, all_uvs = true;
  size_t corner_count = 0;
  for (const tinyobj::shape_t& s : out->shapes) {
    for (const tinyobj::index_t& i : s.mesh.indices) {
      all_normals = all_normals && i.normal_index >= 0;
      all_uvs = all_uvs && i.texcoord_index >= 0;
      ++corner_count;
    }
  }
  if (corner_count == 0) all_normals = all_uvs = false;
  out->all_normals = all_normals;
  out->all_uvs = all_uvs;

  // Every triangle's indices, in file order, so that the first bad face is the one named.
  for (const tinyobj::shape_t& s : out->shapes) {
    size_t offset = 0;
    for (size_t f = 0; f < s.mesh.num_face_vertices.size(); ++f) {
      const size_t fv = s.mesh.num_face_vertices[f];
      if (fv == 3) {  // always, with triangulate = true; deindex_obj skips any other face too
        for (size_t k = 0; k < 3; ++k) {
          const tinyobj::index_t& i = s.mesh.indices[offset + k];
          if (i.vertex_index < 0 || static_cast<size_t>(i.vertex_index) >= num_positions ||
              (all_normals && static_cast<size_t>(i.normal_index) >= num_normals) ||
              (all_uvs && static_cast<size_t>(i.texcoord_index) >= num_uvs)) {
            *error = "face " + std::to_string(f + 1) + " of shape \"" + s.name +
                     "\" refers to a vertex, normal or texture coordinate that does not exist";
            return false;
          }
        }
      }
      offset += fv;
    }
  }
  return true;
}

std::vector<ObjTriangle> obj_triangles(const ObjData& d) {
  std::vector<ObjTriangle> out;
  for (size_t si = 0; si < d.shapes.size(); ++si) {
    const tinyobj::mesh_t& m = d.shapes[si].mesh;
    size_t offset = 0;
    for (size_t f = 0; f < m.num_face_vertices.size(); ++f) {
      const size_t fv = m.num_face_vertices[f];
      // Anything but a triangle cannot happen with triangulate = true; do not trust it blindly.
      if (fv == 3) out.push_back(ObjTriangle{static_cast<uint32_t>(si), static_cast<uint32_t>(f), offset});
      offset += fv;
    }
  }
  return out;
}

void deindex_obj(const ObjData& d, const std::vector<ObjTriangle>& triangles, bool normals, bool uvs,
                 DMesh* out) {
  const tinyobj::attrib_t& attrib = d.attrib;
  std::unordered_map<VertexKey, uint32_t, VertexKeyHash> vertex_of;
  for (const ObjTriangle& t : triangles) {
    const tinyobj::mesh_t& m = d.shapes[t.shape].mesh;
    uint32_t tri[3];
    for (size_t k = 0; k < 3; ++k) {
      const tinyobj::index_t& i = m.indices[t.offset + k];
      const VertexKey key{i.vertex_index, normals ? i.normal_index : -1, uvs ? i.texcoord_index : -1};
      const auto found = vertex_of.find(key);
      if (found != vertex_of.end()) {
        tri[k] = found->second;
        continue;
      }
      const uint32_t index = static_cast<uint32_t>(out->positions.size());
      vertex_of.emplace(key, index);
      const size_t p = static_cast<size_t>(key.position);
      out->positions.emplace_back(attrib.vertices[3 * p], attrib.vertices[3 * p + 1], attrib.vertices[3 * p + 2]);
      if (normals) {
        const size_t n = static_cast<size_t>(key.normal);
        out->normals.emplace_back(attrib.normals[3 * n], attrib.normals[3 * n + 1], attrib.normals[3 * n + 2]);
      }
      if (uvs) {
        const size_t u = static_cast<size_t>(key.uv);
        out->uvs.emplace_back(attrib.texcoords[2 * u], attrib.texcoords[2 * u + 1]);
      }
      tri[k] = index;
    }
    out->indices.emplace_back(tri[0], tri[1], tri[2]);
  }
}

bool obj_normals_usable(const DMesh& mesh) {
  for (const glm::dvec3& n : mesh.normals) {
    const double len2 = glm::dot(n, n);
    if (!(len2 > 0.0) || !std::isfinite(len2)) return false;
  }
  return true;
}

// ---- load_obj (loader_parts.h) ---------------------------------------------------------------

bool load_obj(const std::string& resolved_path, DMesh* out, std::string* error,
              std::vector<std::string>* warnings) {
  std::string text;
  if (!read_obj_text(resolved_path, &text, error)) return false;
  ObjData d;
  // No material reader: OBJ/MTL materials are ignored (the scene file assigns the material),
  // so a missing .mtl is not a problem. load_obj_with_materials (obj_materials.h) reads them.
  if (!parse_obj_text(text, /*materials=*/nullptr, &d, error, warnings)) return false;
  *out = DMesh();
  deindex_obj(d, obj_triangles(d), d.all_normals, d.all_uvs, out);

  // Zero-length normals (seen in exported files) cannot be renormalised; fall back to the
  // geometric normal for the whole mesh rather than feed the renderer NaNs.
  if (!obj_normals_usable(*out)) {
    warnings->push_back("a vertex normal is zero or not finite; ignoring the file's normals");
    out->normals.clear();
  }
  return true;
}

}  // namespace scene_detail
}  // namespace aw
