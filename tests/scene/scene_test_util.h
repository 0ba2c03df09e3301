// Shared helpers for the scene loader tests.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "host/scene/scene.h"

namespace aw_test {

// RFC 4648 base64, for the data URIs of the glTF files tests write.
inline std::string base64(const std::vector<uint8_t>& b) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < b.size(); i += 3) {
    const uint32_t n = (uint32_t(b[i]) << 16) | (i + 1 < b.size() ? uint32_t(b[i + 1]) << 8 : 0) |
                       (i + 2 < b.size() ? uint32_t(b[i + 2]) : 0);
    out += t[(n >> 18) & 63];
    out += t[(n >> 12) & 63];
    out += i + 1 < b.size() ? t[(n >> 6) & 63] : '=';
    out += i + 2 < b.size() ? t[n & 63] : '=';
  }
  return out;
}

// A fresh directory per test process and `tag` for the files a test writes, removed at exit.
inline std::string scratch_dir(const std::string& tag) {
  struct Dir {
    std::string path;
    explicit Dir(std::string p) : path(std::move(p)) { std::filesystem::create_directories(path); }
    ~Dir() {
      std::error_code ec;
      std::filesystem::remove_all(path, ec);
    }
  };
  static std::vector<std::unique_ptr<Dir>> dirs;  // destroyed (and removed) at exit
  const std::string path = ::testing::TempDir() + "archwave_" + tag + "_" + std::to_string(::getpid()) + "/";
  for (const auto& d : dirs)
    if (d->path == path) return path;
  dirs.push_back(std::make_unique<Dir>(path));
  return path;
}

// Writes `bytes` to `dir` + `name` (creating its folders) and returns the path.
inline std::string write_scratch_file(const std::string& dir, const std::string& name, const std::string& bytes) {
  const std::string path = dir + name;
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream f(path, std::ios::binary);
  f.write(bytes.data(), std::streamsize(bytes.size()));
  return path;
}

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
