// Shared structs (kernels/types/) must have the same size and member offsets on the host and
// on the device: the host uploads arrays of them byte for byte. OpenCL's float3 is 16 bytes,
// so a float3 slipped into a shared struct compiles on both sides and silently shifts every
// later member on the device only. kernels/types/layout_list.h names the sizes and offsets
// to compare; kernels/types/layout_probe.cl writes the device's values, this test the host's.
#include <gtest/gtest.h>

#include <cstddef>
#include <sstream>
#include <string>
#include <vector>

#include "host/cl/cl_runtime.h"
#include "host/cl/kernel_source.h"
#include "kernels/common/compat.h"
#include "kernels/types/bvh.h"
#include "kernels/types/scene.h"

namespace aw {
namespace {

struct LayoutEntry {
  int index;
  const char* type;
  const char* member;  // "sizeof" for a size entry
  size_t host_value;
};

// The host's values, expanded from the same X-macro list the probe kernel uses.
#define AW_LAYOUT_SIZE(i, type) {i, #type, "sizeof", sizeof(type)},
#define AW_LAYOUT_ENTRY(i, type, member) {i, #type, #member, offsetof(type, member)},
const LayoutEntry kHostLayout[] = {
#include "kernels/types/layout_list.h"
};
#undef AW_LAYOUT_SIZE
#undef AW_LAYOUT_ENTRY

constexpr size_t kEntries = sizeof(kHostLayout) / sizeof(kHostLayout[0]);

// Fixed by the traversal, which indexes nodes as 8 float4 and leaf triangles as 3 float4
// (kernels/bvh/traverse.h): these sizes are part of the layout, not an accident of it.
static_assert(sizeof(BvhNode) == 128, "BvhNode is 8 float4 (kernels/bvh/traverse.h reads node * 8 + k)");
static_assert(sizeof(LeafTriangle) == 16 * AW_LEAF_FLOAT4S && AW_LEAF_FLOAT4S == 4,
              "LeafTriangle is 4 float4 (traverse.h reads i * AW_LEAF_FLOAT4S + k)");
static_assert(offsetof(BvhNode, lo_x) == 0 && offsetof(BvhNode, hi_x) == 16 && offsetof(BvhNode, lo_y) == 32 &&
                  offsetof(BvhNode, hi_y) == 48 && offsetof(BvhNode, lo_z) == 64 && offsetof(BvhNode, hi_z) == 80,
              "the box rows are the node's float4 0..5");
static_assert(offsetof(BvhNode, child) == 96, "the child indices are the node's 7th float4");
static_assert(offsetof(LeafTriangle, v1) == 16 && offsetof(LeafTriangle, v2) == 32 && offsetof(LeafTriangle, plane) == 48,
              "one vertex per float4, then the plane");
static_assert(sizeof(TriangleInfo) == 16, "TriangleInfo is one uint4");
static_assert(sizeof(VertexData) == 64, "VertexData: p, n, uv + pad, t as four float4");
static_assert(offsetof(VertexData, t) == 48, "the tangent is the 4th float4 of a vertex");

// Shared structs hold only 4-byte fields (docs/design.md, "Rules for shared code"): then
// alignment is 4 and no compiler can insert padding, so sizeof equals the sum of the declared
// fields on every side. A member with a larger alignment (a double, a 64-bit integer, a host
// vector type with forced alignment) breaks this and is caught here at compile time.
template <typename T>
constexpr bool plain_4byte_struct() {
  return alignof(T) == 4 && sizeof(T) % 4 == 0;
}
static_assert(plain_4byte_struct<BvhNode>(), "BvhNode: 4-byte fields only");
static_assert(plain_4byte_struct<LeafTriangle>(), "LeafTriangle: 4-byte fields only");
static_assert(plain_4byte_struct<TriangleInfo>(), "TriangleInfo: 4-byte fields only");
static_assert(plain_4byte_struct<VertexData>(), "VertexData: 4-byte fields only");
static_assert(plain_4byte_struct<MaterialGpu>(), "MaterialGpu: 4-byte fields only");
static_assert(plain_4byte_struct<LightGpu>(), "LightGpu: 4-byte fields only");
static_assert(plain_4byte_struct<RenderParams>(), "RenderParams: 4-byte fields only");

TEST(Layout, ListIsNumberedZeroToCountWithoutGaps) {
  // The probe writes out[index]; a duplicated or skipped index would leave a slot unchecked.
  ASSERT_EQ(kEntries, size_t(AW_LAYOUT_COUNT)) << "layout_list.h: AW_LAYOUT_COUNT does not match the entries";
  std::vector<int> seen(kEntries, 0);
  for (const LayoutEntry& e : kHostLayout) {
    ASSERT_GE(e.index, 0);
    ASSERT_LT(size_t(e.index), kEntries) << e.type << "::" << e.member;
    ++seen[size_t(e.index)];
  }
  for (size_t i = 0; i < kEntries; ++i) EXPECT_EQ(seen[i], 1) << "layout_list.h index " << i;
}

TEST(Layout, DeviceSizesAndOffsetsMatchHost) {
  ClRuntime rt(aw::kDefaultDevice);
  // default_kernel_dir() is "" (the embedded kernels) unless ARCHWAVE_KERNEL_DIR is set.
  cl::Program program = rt.build(assemble_kernel_source("types/layout_probe.cl", default_kernel_dir()), "-cl-std=CL1.2");
  cl::Kernel kernel(program, "layout_probe");
  // Filled with a marker so an entry the probe never writes cannot pass by accident.
  std::vector<cl_uint> device(AW_LAYOUT_COUNT, 0xdeadbeefu);
  cl::Buffer out = rt.buffer("layout probe output", device.size() * sizeof(cl_uint), CL_MEM_READ_WRITE, device.data());
  kernel.setArg(0, out);
  rt.queue().enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(1), cl::NDRange(1));
  rt.queue().enqueueReadBuffer(out, CL_TRUE, 0, device.size() * sizeof(cl_uint), device.data());

  std::ostringstream table;
  int mismatches = 0;
  for (const LayoutEntry& e : kHostLayout) {
    const cl_uint d = device[size_t(e.index)];
    const bool ok = d == e.host_value;
    mismatches += ok ? 0 : 1;
    table << (ok ? "  ok  " : "  BAD ") << e.type << (std::string(e.member) == "sizeof" ? " sizeof" : "::")
          << (std::string(e.member) == "sizeof" ? "" : e.member) << ": host " << e.host_value << ", device " << d
          << "\n";
  }
  EXPECT_EQ(mismatches, 0) << "host and device (" << rt.info().name
                           << ") lay out shared structs differently (a float3 member?):\n"
                           << table.str();
}

}  // namespace
}  // namespace aw
