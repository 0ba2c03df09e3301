#include "host/scene/export_obj.h"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "host/film/image_io.h"

namespace aw {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& why) {
  throw OutputError("cannot write geometry to " + path + ": " + why);
}

}  // namespace

void write_geometry_obj(const Scene& scene, const std::string& path) {
  const std::string tmp = path + ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) fail(path, std::strerror(errno));
  std::fprintf(f, "# archwave geometry of %s: %zu meshes, %zu triangles, world space\n", scene.path.c_str(),
               scene.meshes.size(), scene.triangle_count());
  size_t base = 1, nbase = 1;  // OBJ indices are 1-based and global, per kind (v, vn)
  for (const TriangleMesh& m : scene.meshes) {
    std::fprintf(f, "o %s\nusemtl %s\n", m.name.c_str(), scene.material_names.at(m.material).c_str());
    for (const auto& p : m.positions) std::fprintf(f, "v %.9g %.9g %.9g\n", p.x, p.y, p.z);
    const bool smooth = !m.normals.empty();
    for (const auto& n : m.normals) std::fprintf(f, "vn %.9g %.9g %.9g\n", n.x, n.y, n.z);
    for (const auto& t : m.indices) {
      size_t a = base + t.x, b = base + t.y, c = base + t.z;
      if (smooth)
        std::fprintf(f, "f %zu//%zu %zu//%zu %zu//%zu\n", a, nbase + t.x, b, nbase + t.y, c, nbase + t.z);
      else
        std::fprintf(f, "f %zu %zu %zu\n", a, b, c);
    }
    base += m.positions.size();
    nbase += m.normals.size();
  }
  const bool ok = !std::ferror(f);
  if (std::fclose(f) != 0 || !ok) {
    std::remove(tmp.c_str());
    fail(path, "write error");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    int e = errno;
    std::remove(tmp.c_str());
    fail(path, std::strerror(e));
  }
}

}  // namespace aw
