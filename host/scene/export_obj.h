// The scene's triangles exactly as archwave builds them (world space, after every shape is
// tessellated and transformed), as a Wavefront OBJ: for tools that must see the same
// geometry, such as the bench's exporters to Cycles and Mitsuba 3 (bench/race_scene.py).
#ifndef AW_HOST_SCENE_EXPORT_OBJ_H
#define AW_HOST_SCENE_EXPORT_OBJ_H

#include <string>

#include "host/scene/scene.h"

namespace aw {

// One `o` group per mesh (Scene::meshes order; the name is the mesh's, e.g. "objects[3]
// (box)"), then one per analytic sphere (Scene::spheres), tessellated as the loader would; each
// with `usemtl` its material's name, positions, per-vertex normals where the mesh has them
// (`f a//a ...`, else flat `f a b c`), counter-clockwise seen from the side the geometric
// normal points to, as archwave winds them. Floats are printed with 9 significant
// digits, so they read back bit for bit. Written to "<path>.tmp" and renamed; throws
// OutputError (host/film/image_io.h) naming the file on failure.
// Returns the number of triangles written (analytic spheres tessellated included).
size_t write_geometry_obj(const Scene& scene, const std::string& path);

}  // namespace aw

#endif
