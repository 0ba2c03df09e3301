// OBJ meshes through tinyobjloader.
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

#include "host/scene/loader_parts.h"

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

bool load_obj(const std::string& resolved_path, DMesh* out, std::string* error,
              std::vector<std::string>* warnings) {
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
  if (!check_obj_numbers(contents.str(), error)) return false;
  std::istringstream stream(contents.str());

  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  // No material reader: OBJ/MTL materials are ignored (the scene file assigns the material),
  // so a missing .mtl is not a problem. Polygons are triangulated as fans.
  const bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &stream,
                                   /*readMatFn=*/nullptr, /*triangulate=*/true,
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

  const size_t num_positions = attrib.vertices.size() / 3;
  const size_t num_normals = attrib.normals.size() / 3;
  const size_t num_uvs = attrib.texcoords.size() / 2;

  // Normals and UVs are kept only when every face corner has them; a partial set could not
  // be represented by per-vertex arrays of the mesh's full size.
  bool all_normals = true, all_uvs = true;
  size_t corner_count = 0;
  for (const tinyobj::shape_t& s : shapes) {
    for (const tinyobj::index_t& i : s.mesh.indices) {
      all_normals = all_normals && i.normal_index >= 0;
      all_uvs = all_uvs && i.texcoord_index >= 0;
      ++corner_count;
    }
  }
  if (corner_count == 0) all_normals = all_uvs = false;

  *out = DMesh();
  std::unordered_map<VertexKey, uint32_t, VertexKeyHash> vertex_of;
  for (const tinyobj::shape_t& s : shapes) {
    size_t offset = 0;
    for (size_t f = 0; f < s.mesh.num_face_vertices.size(); ++f) {
      const size_t fv = s.mesh.num_face_vertices[f];
      if (fv != 3) {  // cannot happen with triangulate = true; do not trust it blindly
        offset += fv;
        continue;
      }
      uint32_t tri[3];
      for (size_t k = 0; k < 3; ++k) {
        const tinyobj::index_t& i = s.mesh.indices[offset + k];
        const VertexKey key{i.vertex_index, all_normals ? i.normal_index : -1,
                            all_uvs ? i.texcoord_index : -1};
        if (key.position < 0 || static_cast<size_t>(key.position) >= num_positions ||
            (all_normals && static_cast<size_t>(key.normal) >= num_normals) ||
            (all_uvs && static_cast<size_t>(key.uv) >= num_uvs)) {
          *error = "face " + std::to_string(f + 1) + " of shape \"" + s.name +
                   "\" refers to a vertex, normal or texture coordinate that does not exist";
          return false;
        }
        const auto found = vertex_of.find(key);
        if (found != vertex_of.end()) {
          tri[k] = found->second;
          continue;
        }
        const uint32_t index = static_cast<uint32_t>(out->positions.size());
        vertex_of.emplace(key, index);
        const size_t p = static_cast<size_t>(key.position);
        out->positions.emplace_back(attrib.vertices[3 * p], attrib.vertices[3 * p + 1],
                                    attrib.vertices[3 * p + 2]);
        if (all_normals) {
          const size_t n = static_cast<size_t>(key.normal);
          out->normals.emplace_back(attrib.normals[3 * n], attrib.normals[3 * n + 1],
                                    attrib.normals[3 * n + 2]);
        }
        if (all_uvs) {
          const size_t t = static_cast<size_t>(key.uv);
          out->uvs.emplace_back(attrib.texcoords[2 * t], attrib.texcoords[2 * t + 1]);
        }
        tri[k] = index;
      }
      out->indices.emplace_back(tri[0], tri[1], tri[2]);
      offset += fv;
    }
  }

  // Zero-length normals (seen in exported files) cannot be renormalised; fall back to the
  // geometric normal for the whole mesh rather than feed the renderer NaNs.
  for (size_t v = 0; v < out->normals.size(); ++v) {
    const double len2 = glm::dot(out->normals[v], out->normals[v]);
    if (!(len2 > 0.0) || !std::isfinite(len2)) {
      warnings->push_back("a vertex normal is zero or not finite; ignoring the file's normals");
      out->normals.clear();
      break;
    }
  }
  return true;
}

}  // namespace scene_detail
}  // namespace aw
