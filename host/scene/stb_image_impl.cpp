// stb_image's implementation (Debian's libstb-dev), in a translation unit of its own so that the
// sanitizer builds can exempt this third-party code from one check: with a zero-length PNG chunk
// stbi__getn calls memcpy(NULL, src, 0), undefined by the letter of C (a nonnull argument) and
// harmless, found by tests/fuzz (fuzz_image, 2026-12-02). CMakeLists.txt turns off only UBSan's
// nonnull-attribute check, only here; archwave's own code keeps every check.
//
// stb_image's allocations come zeroed. stb_image 2.27 decodes a JPEG scan with the Huffman tables
// its header names even when the file never defined them, reading them from its decoder's fresh
// allocation: whatever the heap held there. tests/fuzz (fuzz_image under UBSan, 2026-12-04) met
// this as a shift by 34 in stbi__grow_buffer_unsafe after an undefined table's garbage lengths
// had driven the bit count negative; it happened only after earlier inputs (libFuzzer runs them
// in one process; AddressSanitizer fills only a fresh allocation's first 4 KiB) and not for the
// input alone. Zeroed, an undefined table is empty and decodes the same whatever ran before.
#include <cstdlib>
#define STBI_MALLOC(size) std::calloc(1, (size))
#define STBI_REALLOC(p, size) std::realloc((p), (size))
#define STBI_FREE(p) std::free(p)
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#define STBI_NO_STDIO  // host/scene/texture_image.cpp reads the files
#include <stb/stb_image.h>
