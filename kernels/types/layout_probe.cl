// Writes sizeof/offsetof of every shared struct as the device compiler lays them out, so a
// test can compare them with the host's (tests/types). A float3 slipped into a shared struct
// shows up here as a size mismatch.
#include "types/bvh.h"
#include "types/scene.h"

#define AW_PROBE(n, expr) out[n] = (uint)(expr)

__kernel void layout_probe(__global uint* out) {
  if (get_global_id(0) != 0) return;
#define AW_LAYOUT_ENTRY(i, type, member) AW_PROBE(i, __builtin_offsetof(type, member));
#define AW_LAYOUT_SIZE(i, type) AW_PROBE(i, sizeof(type));
#include "types/layout_list.h"  // NOLINT: X-macro list, included once per expansion
#undef AW_LAYOUT_ENTRY
#undef AW_LAYOUT_SIZE
}
