#include "host/scene/export_obj.h"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "host/film/image_io.h"
#include "host/scene/loader_parts.h"

namespace aw {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& why) {
  throw OutputError("cannot write geometry to " + path + ": " + why);
}

}  // namespace

size_t write_geometry_obj(const Scene& scene, const std::string& path) {
  // Analytic spheres are written tessellated as the loader would have tessellated them (an
  // OBJ has no spheres), in the sphere's own frame so their UVs agree.
  std::vector<TriangleMesh> spheres;
  for (const SphereDesc& sd : scene.spheres) {
    glm::dmat4 m(1.0);
    m[0] = glm::dvec4(glm::dvec3(sd.axis_x) * double(sd.radius), 0.0);
    m[1] = glm::dvec4(glm::dvec3(sd.axis_y) * double(sd.radius), 0.0);
    m[2] = glm::dvec4(glm::cross(glm::dvec3(sd.axis_x), glm::dvec3(sd.axis_y)) * double(sd.radius), 0.0);
    m[3] = glm::dvec4(glm::dvec3(sd.center), 1.0);
    TriangleMesh t;
    scene_detail::finalize_mesh(scene_detail::make_sphere(glm::dvec3(0.0), 1.0, scene_detail::kSphereSegmentsU,
                                                          scene_detail::kSphereSegmentsV),
                                m, &t);
    t.material = sd.material;
    t.name = sd.name;
    spheres.push_back(std::move(t));
  }
  size_t triangles = scene.rendered_triangle_count();
  for (const TriangleMesh& t : spheres) triangles += t.indices.size();
  // Instances are written expanded: each placement's copy of its mesh in world space (an OBJ
  // has no instancing), made one at a time as it is written.
  auto placed = [&](const MeshInstance& mi, const TriangleMesh& part) {
    TriangleMesh t = scene_detail::place_mesh(part, mi.transform);
    t.name = mi.name + ", " + part.name;
    return t;
  };
  size_t mesh_count = scene.meshes.size() + spheres.size();
  for (const MeshInstance& mi : scene.instances) mesh_count += scene.prototypes[mi.prototype].parts.size();
  const std::string tmp = path + ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) fail(path, std::strerror(errno));
  std::fprintf(f, "# archwave geometry of %s: %zu meshes, %zu triangles, world space\n", scene.path.c_str(),
               mesh_count, triangles);
  size_t base = 1, nbase = 1;  // OBJ indices are 1-based and global, per kind (v, vn)
  std::vector<const TriangleMesh*> all;
  for (const TriangleMesh& m : scene.meshes) all.push_back(&m);
  for (const TriangleMesh& m : spheres) all.push_back(&m);
  auto write_mesh = [&](const TriangleMesh& m) {
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
  };
  for (const TriangleMesh* mp : all) write_mesh(*mp);
  for (const MeshInstance& mi : scene.instances)
    for (const TriangleMesh& part : scene.prototypes[mi.prototype].parts) write_mesh(placed(mi, part));
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
  return triangles;
}

}  // namespace aw
