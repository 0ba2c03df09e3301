// Shared helpers for the scene loader tests.
#pragma once

#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "host/scene/scene.h"

namespace aw_test {

// Absolute path of a fixture under tests/scene/data.
inline std::string data_path(const std::string& name) {
  return std::string(ARCHWAVE_TEST_DATA) + "/scene/data/" + name;
}

// The SceneError message of loading `path`, or "<loaded>" when it loaded.
inline std::string load_error(const std::string& path,
                              const std::vector<std::string>& overrides = {}) {
  try {
    aw::load_scene(path, overrides);
  } catch (const aw::SceneError& e) {
    return e.what();
  }
  return "<loaded>";
}

struct Bounds {
  glm::vec3 lo{1e30f};
  glm::vec3 hi{-1e30f};
};

inline Bounds bounds_of(const aw::TriangleMesh& m) {
  Bounds b;
  for (const glm::vec3& p : m.positions) {
    b.lo = glm::min(b.lo, p);
    b.hi = glm::max(b.hi, p);
  }
  return b;
}

// Geometric normal of triangle t (from its winding), not normalised.
inline glm::vec3 face_normal(const aw::TriangleMesh& m, size_t t) {
  const glm::uvec3 i = m.indices[t];
  return glm::cross(m.positions[i.y] - m.positions[i.x], m.positions[i.z] - m.positions[i.x]);
}

inline glm::vec3 centroid(const aw::TriangleMesh& m, size_t t) {
  const glm::uvec3 i = m.indices[t];
  return (m.positions[i.x] + m.positions[i.y] + m.positions[i.z]) / 3.0f;
}

}  // namespace aw_test
