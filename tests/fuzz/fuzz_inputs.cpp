// libFuzzer targets for what archwave reads from users (issue 16): the scene loader, the OBJ
// reader (alone and with its .mtl), the glTF reader and the image decoders. One source, built
// once per target with ARCHWAVE_FUZZ_TARGET naming it (tests/fuzz/CMakeLists.txt); run by
// scripts/fuzz.sh (docs/testing.md#fuzzing). Every target asserts what the loaders promise:
// any input either loads or is refused with a message; none crashes, hangs, leaks or grows
// without bound (libFuzzer's -rss_limit_mb and -timeout, AddressSanitizer and UBSan catch the
// rest).
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "host/scene/gltf_mesh.h"
#include "host/scene/loader_parts.h"
#include "host/scene/obj_materials.h"
#include "host/scene/scene.h"
#include "host/scene/texture_desc.h"

namespace {

// The loaders take paths: each input goes to a file in this process's own directory (files
// that the input names relative to itself resolve there, and find nothing).
std::string write_input(const char* name, const uint8_t* data, size_t size) {
  static const std::string dir = [] {
    std::string d = std::filesystem::temp_directory_path().string() + "/archwave_fuzz_" + std::to_string(getpid());
    std::filesystem::create_directories(d);
    return d;
  }();
  const std::string path = dir + "/" + name;
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(data), std::streamsize(size));
  return path;
}

// A refusal must say why.
void expect_message(bool ok, const std::string& error) {
  if (!ok && error.empty()) {
    std::fprintf(stderr, "refused without a message\n");
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
#if ARCHWAVE_FUZZ_TARGET == 1  // the scene loader (JSON, with its own memory limit)
  const std::string path = write_input("scene.json", data, size);
  aw::LoadLimits limits;
  limits.max_bytes = uint64_t(256) << 20;
  limits.source = "the fuzzer's limit";
  try {
    aw::load_scene(path, {}, limits);
  } catch (const aw::SceneError& e) {
    expect_message(false, e.what());
  }
#elif ARCHWAVE_FUZZ_TARGET == 2  // OBJ, alone and with its materials
  const std::string path = write_input("mesh.obj", data, size);
  std::string error;
  std::vector<std::string> warnings;
  aw::scene_detail::DMesh mesh;
  expect_message(aw::scene_detail::load_obj(path, &mesh, &error, &warnings), error);
  aw::scene_detail::ObjImport imp;
  error.clear();
  expect_message(aw::scene_detail::load_obj_with_materials(path, &imp, &error, &warnings), error);
#elif ARCHWAVE_FUZZ_TARGET == 3  // glTF 2.0 (.gltf or .glb: told apart by content)
  const std::string path = write_input("model.gltf", data, size);
  std::string error;
  std::vector<std::string> warnings;
  aw::scene_detail::GltfImport imp;
  expect_message(aw::scene_detail::load_gltf(path, &imp, &error, &warnings), error);
#elif ARCHWAVE_FUZZ_TARGET == 4  // PNG, JPEG and EXR texture images from memory
  aw::TextureDesc t;
  std::string error;
  expect_message(aw::decode_texture_image(data, size, &t, &error), error);
#else
#error "ARCHWAVE_FUZZ_TARGET: 1 scene, 2 obj, 3 gltf, 4 image"
#endif
  return 0;
}
