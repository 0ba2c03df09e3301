// stb_image's implementation (Debian's libstb-dev), in a translation unit of its own so that the
// sanitizer builds can exempt this third-party code from one check: with a zero-length PNG chunk
// stbi__getn calls memcpy(NULL, src, 0), undefined by the letter of C (a nonnull argument) and
// harmless, found by tests/fuzz (fuzz_image, 2026-12-02). CMakeLists.txt turns off only UBSan's
// nonnull-attribute check, only here; archwave's own code keeps every check.
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#define STBI_NO_STDIO  // host/scene/texture_image.cpp reads the files
#include <stb/stb_image.h>
