// Host-vs-device probe for texture lookups (tests/texture): texture_eval of one of the given
// textures at (u, v) with footprint f. The C++ test includes this file and runs the same
// per-item function on the host (the __kernel wrapper is OpenCL only).
#include "common/compat.h"
#include "texture/texture.h"

// Floats per item: in 4 (texture index, u, v, footprint), out 4 (RGBA).
#define AW_PROBE_TEXTURE_IN 4
#define AW_PROBE_TEXTURE_OUT 4

AW_FN void probe_texture_item(const AW_GLOBAL TextureGpu* textures, const AW_GLOBAL uchar* texels,
                              const AW_GLOBAL float* in, AW_GLOBAL float* out) {
  float4 c = texture_eval(&textures[(uint)in[0]], texels, in[1], in[2], in[3]);
  out[0] = c.x;
  out[1] = c.y;
  out[2] = c.z;
  out[3] = c.w;
}

#ifdef __OPENCL_C_VERSION__
__kernel void probe_texture(uint n, const __global float* in, __global float* out,
                            const __global TextureGpu* textures, const __global uchar* texels) {
  uint i = get_global_id(0);
  if (i >= n) return;
  probe_texture_item(textures, texels, in + i * AW_PROBE_TEXTURE_IN, out + i * AW_PROBE_TEXTURE_OUT);
}
#endif
