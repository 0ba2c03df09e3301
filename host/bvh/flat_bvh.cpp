#include "host/bvh/flat_bvh.h"
#include "kernels/bvh/intersect_triangle.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

namespace aw {

namespace {

void embree_error(void*, RTCError code, const char* str) {
  // Reported through rtcGetDeviceError at the call sites; keep a message on stderr too since
  // Embree's own text is the most specific description of the problem.
  fprintf(stderr, "archwave: Embree error %d: %s\n", int(code), str ? str : "");
}

// Tree as Embree's builder hands it to us (allocated in Embree's thread-local arenas, freed
// with the RTCBVH).
struct BuildNode {
  bool leaf;
  unsigned num;  // inner: children in use (2..AW_BVH_WIDTH)
  BuildNode* child[AW_BVH_WIDTH];
  RTCBounds bounds[AW_BVH_WIDTH];
  uint32_t count;
  const uint32_t* prims;  // leaf: primIDs (in Embree's allocator memory)
};

void* create_node(RTCThreadLocalAllocator alloc, unsigned num_children, void*) {
  if (num_children < 1 || num_children > AW_BVH_WIDTH) return nullptr;  // maxBranchingFactor
  auto* n = static_cast<BuildNode*>(rtcThreadLocalAlloc(alloc, sizeof(BuildNode), 16));
  n->leaf = false;
  n->num = num_children;
  for (BuildNode*& c : n->child) c = nullptr;
  n->count = 0;
  n->prims = nullptr;
  return n;
}

void set_children(void* node, void** children, unsigned num, void*) {
  auto* n = static_cast<BuildNode*>(node);
  n->num = std::min<unsigned>(num, AW_BVH_WIDTH);
  for (unsigned i = 0; i < n->num; ++i) n->child[i] = static_cast<BuildNode*>(children[i]);
}

void set_bounds(void* node, const RTCBounds** bounds, unsigned num, void*) {
  auto* n = static_cast<BuildNode*>(node);
  for (unsigned i = 0; i < num && i < AW_BVH_WIDTH; ++i) n->bounds[i] = *bounds[i];
}

void* create_leaf(RTCThreadLocalAllocator alloc, const RTCBuildPrimitive* prims, size_t num, void*) {
  auto* n = static_cast<BuildNode*>(rtcThreadLocalAlloc(alloc, sizeof(BuildNode), 16));
  auto* ids = static_cast<uint32_t*>(rtcThreadLocalAlloc(alloc, sizeof(uint32_t) * std::max<size_t>(num, 1), 16));
  for (size_t i = 0; i < num; ++i) ids[i] = prims[i].primID;
  // Embree hands a leaf's primitives in build order; sort so the leaf content does not depend
  // on how the parallel builder partitioned its work.
  std::sort(ids, ids + num);
  n->leaf = true;
  n->child[0] = n->child[1] = nullptr;
  n->count = uint32_t(num);
  n->prims = ids;
  return n;
}

struct Flattener {
  const TriangleSoup& soup;
  FlatBvh& out;
  const std::vector<RTCBounds>& inst_bounds;  // world bounds per instance (ids after the spheres)

  RTCBounds tri_bounds(const uint32_t* ids, uint32_t n) const {
    RTCBounds b;
    b.lower_x = b.lower_y = b.lower_z = std::numeric_limits<float>::infinity();
    b.upper_x = b.upper_y = b.upper_z = -std::numeric_limits<float>::infinity();
    for (uint32_t i = 0; i < n; ++i) {
      if (ids[i] >= soup.primitive_count()) {  // an instance
        const RTCBounds& ib = inst_bounds[ids[i] - soup.primitive_count()];
        b.lower_x = std::min(b.lower_x, ib.lower_x); b.upper_x = std::max(b.upper_x, ib.upper_x);
        b.lower_y = std::min(b.lower_y, ib.lower_y); b.upper_y = std::max(b.upper_y, ib.upper_y);
        b.lower_z = std::min(b.lower_z, ib.lower_z); b.upper_z = std::max(b.upper_z, ib.upper_z);
        continue;
      }
      if (ids[i] >= soup.indices.size()) {  // an analytic sphere
        const glm::vec4& s = soup.spheres[ids[i] - soup.indices.size()];
        b.lower_x = std::min(b.lower_x, s.x - s.w); b.upper_x = std::max(b.upper_x, s.x + s.w);
        b.lower_y = std::min(b.lower_y, s.y - s.w); b.upper_y = std::max(b.upper_y, s.y + s.w);
        b.lower_z = std::min(b.lower_z, s.z - s.w); b.upper_z = std::max(b.upper_z, s.z + s.w);
        continue;
      }
      const glm::uvec3& t = soup.indices[ids[i]];
      for (int k = 0; k < 3; ++k) {
        const glm::vec3& p = soup.positions[t[k]];
        b.lower_x = std::min(b.lower_x, p.x); b.upper_x = std::max(b.upper_x, p.x);
        b.lower_y = std::min(b.lower_y, p.y); b.upper_y = std::max(b.upper_y, p.y);
        b.lower_z = std::min(b.lower_z, p.z); b.upper_z = std::max(b.upper_z, p.z);
      }
    }
    return b;
  }

  int emit_leaf(const uint32_t* ids, uint32_t n) {
    int first = int(out.leaf_tris.size());
    for (uint32_t i = 0; i < n; ++i) {
      if (ids[i] >= soup.primitive_count()) {  // an instance (kernels/types/bvh.h)
        LeafTriangle lt;
        std::memset(&lt, 0, sizeof(lt));
        const uint32_t k = uint32_t(ids[i] - soup.primitive_count()), mark = AW_LEAF_INSTANCE;
        std::memcpy(&lt.v0[3], &k, 4);
        std::memcpy(&lt.v1[3], &mark, 4);
        out.leaf_tris.push_back(lt);
        continue;
      }
      if (ids[i] >= soup.indices.size()) {  // an analytic sphere (kernels/types/bvh.h)
        const glm::vec4& s = soup.spheres[ids[i] - soup.indices.size()];
        LeafTriangle lt;
        std::memset(&lt, 0, sizeof(lt));
        lt.v0[0] = s.x; lt.v0[1] = s.y; lt.v0[2] = s.z;
        std::memcpy(&lt.v0[3], &ids[i], 4);
        lt.v1[0] = s.w;
        const uint32_t mark = AW_LEAF_SPHERE;
        std::memcpy(&lt.v1[3], &mark, 4);
        out.leaf_tris.push_back(lt);
        continue;
      }
      const glm::uvec3& t = soup.indices[ids[i]];
      LeafTriangle lt;
      const glm::vec3 &a = soup.positions[t.x], &b = soup.positions[t.y], &c = soup.positions[t.z];
      lt.v0[0] = a.x; lt.v0[1] = a.y; lt.v0[2] = a.z;
      uint32_t id = ids[i];
      std::memcpy(&lt.v0[3], &id, 4);
      lt.v1[0] = b.x; lt.v1[1] = b.y; lt.v1[2] = b.z; lt.v1[3] = 0.0f;
      lt.v2[0] = c.x; lt.v2[1] = c.y; lt.v2[2] = c.z; lt.v2[3] = 0.0f;
      // The plane intersect_triangle measures t from, once per triangle (the kernels' function).
      float3 n;
      const uint32_t corner = triangle_plane(a, b, c, &n);
      lt.plane[0] = n.x; lt.plane[1] = n.y; lt.plane[2] = n.z;
      std::memcpy(&lt.plane[3], &corner, 4);
      out.leaf_tris.push_back(lt);
    }
    ++out.leaf_count;
    return ~((first << 3) | int(n - 1));
  }

  // Slot i of a node: its box in the structure-of-arrays rows and its child reference
  // (kernels/types/bvh.h).
  static void put_child(BvhNode& node, int i, const RTCBounds& b, int ref) {
    node.lo_x[i] = b.lower_x;
    node.hi_x[i] = b.upper_x;
    node.lo_y[i] = b.lower_y;
    node.hi_y[i] = b.upper_y;
    node.lo_z[i] = b.lower_z;
    node.hi_z[i] = b.upper_z;
    node.child[i] = ref;
  }

  // A node with no children yet: every slot empty (zero box, AW_BVH_EMPTY), padding zero.
  static BvhNode empty_node() {
    BvhNode node;
    std::memset(&node, 0, sizeof(node));
    for (int& c : node.child) c = AW_BVH_EMPTY;
    return node;
  }

  // A leaf larger than the kernel's limit (possible when Embree hits maxDepth) is split in
  // halves into a small subtree of its own.
  int child_ref(const uint32_t* ids, uint32_t n, int depth) {
    if (n <= AW_BVH_LEAF_MAX) return emit_leaf(ids, n);
    uint32_t h = n / 2;
    return emit_inner_from_list(ids, h, ids + h, n - h, depth);
  }

  int emit_inner_from_list(const uint32_t* a, uint32_t na, const uint32_t* b, uint32_t nb, int depth) {
    if (depth >= AW_BVH_MAX_DEPTH - 1) throw std::runtime_error("BVH deeper than the traversal stack");
    out.max_depth = std::max(out.max_depth, depth);
    int index = int(out.nodes.size());
    out.nodes.emplace_back();
    RTCBounds ba = tri_bounds(a, na), bb = tri_bounds(b, nb);
    int c0 = child_ref(a, na, depth + 1);
    int c1 = child_ref(b, nb, depth + 1);
    BvhNode node = empty_node();
    put_child(node, 0, ba, c0);
    put_child(node, 1, bb, c1);
    out.nodes[size_t(index)] = node;
    return index;
  }

  int emit(const BuildNode* n, int depth) {
    if (n->leaf) return child_ref(n->prims, n->count, depth);
    if (depth >= AW_BVH_MAX_DEPTH - 1) throw std::runtime_error("BVH deeper than the traversal stack");
    out.max_depth = std::max(out.max_depth, depth);
    int index = int(out.nodes.size());
    out.nodes.emplace_back();  // children are emitted after their parent: depth-first preorder
    int refs[AW_BVH_WIDTH];
    for (unsigned i = 0; i < n->num; ++i) refs[i] = emit(n->child[i], depth + 1);
    BvhNode node = empty_node();
    for (unsigned i = 0; i < n->num; ++i) put_child(node, int(i), n->bounds[i], refs[i]);
    out.nodes[size_t(index)] = node;
    return index;
  }
};

}  // namespace

EmbreeDevice::EmbreeDevice() {
  device_ = rtcNewDevice(nullptr);
  if (!device_) throw std::runtime_error("cannot create an Embree device (rtcNewDevice failed)");
  rtcSetDeviceErrorFunction(device_, embree_error, nullptr);
}

EmbreeDevice::~EmbreeDevice() { rtcReleaseDevice(device_); }

namespace {

// Builds one tree over `prims` with Embree and flattens it onto the end of out.nodes and
// out.leaf_tris (global indices, so several trees share the arrays); returns its root's index
// and the tree's depth. Adds the build and flattening times to `out`.
int build_tree(const EmbreeDevice& device, std::vector<RTCBuildPrimitive>& prims, Flattener& f, int* depth) {
  FlatBvh& out = f.out;
  const size_t n = prims.size();
  auto t0 = std::chrono::steady_clock::now();
  RTCBVH bvh = rtcNewBVH(device.get());
  RTCBuildArguments args = rtcDefaultBuildArguments();
  args.byteSize = sizeof(args);
  args.buildFlags = RTC_BUILD_FLAG_NONE;
  args.buildQuality = RTC_BUILD_QUALITY_MEDIUM;  // binned SAH; HIGH needs spatial-split callbacks
  args.maxBranchingFactor = AW_BVH_WIDTH;
  args.maxDepth = AW_BVH_MAX_DEPTH - 8;  // leave room for oversized-leaf subtrees
  args.sahBlockSize = 1;
  args.minLeafSize = 1;
  args.maxLeafSize = 4;
  // Relative costs for the SAH: a box pair test vs one watertight triangle test, roughly as
  // measured for our kernels (a node tests two boxes at once).
  args.traversalCost = 1.0f;
  args.intersectionCost = 1.0f;
  args.bvh = bvh;
  args.primitives = prims.data();
  args.primitiveCount = n;
  args.primitiveArrayCapacity = n;
  args.createNode = create_node;
  args.setNodeChildren = set_children;
  args.setNodeBounds = set_bounds;
  args.createLeaf = create_leaf;
  args.splitPrimitive = nullptr;
  args.buildProgress = nullptr;
  args.userPtr = nullptr;
  auto* root = static_cast<BuildNode*>(rtcBuildBVH(&args));
  if (!root) {
    rtcReleaseBVH(bvh);
    throw std::runtime_error("Embree BVH build failed (error " +
                             std::to_string(int(rtcGetDeviceError(device.get()))) + ")");
  }
  auto t1 = std::chrono::steady_clock::now();
  const int depth_before = out.max_depth;
  out.max_depth = 0;
  const int index = int(out.nodes.size());
  if (root->leaf) {
    // A one-leaf tree still needs an inner root: the leaf (or the subtree an oversized leaf
    // became) in slot 0, the other slots empty (see bvh.h).
    out.nodes.emplace_back();
    int leaf = f.child_ref(root->prims, root->count, 1);
    BvhNode node = Flattener::empty_node();
    Flattener::put_child(node, 0, f.tri_bounds(root->prims, root->count), leaf);
    out.nodes[size_t(index)] = node;
  } else {
    f.emit(root, 0);
  }
  *depth = out.max_depth;
  out.max_depth = depth_before;
  rtcReleaseBVH(bvh);
  auto t2 = std::chrono::steady_clock::now();
  out.build_seconds += std::chrono::duration<double>(t1 - t0).count();
  out.flatten_seconds += std::chrono::duration<double>(t2 - t1).count();
  return index;
}

RTCBuildPrimitive triangle_prim(const TriangleSoup& soup, size_t i) {
  const glm::uvec3& t = soup.indices[i];
  glm::vec3 a = soup.positions[t.x], b = soup.positions[t.y], c = soup.positions[t.z];
  glm::vec3 lo = glm::min(a, glm::min(b, c)), hi = glm::max(a, glm::max(b, c));
  RTCBuildPrimitive p;
  p.lower_x = lo.x; p.lower_y = lo.y; p.lower_z = lo.z; p.geomID = 0;
  p.upper_x = hi.x; p.upper_y = hi.y; p.upper_z = hi.z; p.primID = unsigned(i);
  return p;
}

}  // namespace

std::vector<std::pair<glm::vec3, glm::vec3>> prototype_bounds(const TriangleSoup& soup) {
  std::vector<std::pair<glm::vec3, glm::vec3>> out;
  for (const SoupPrototype& pr : soup.prototypes) {
    glm::vec3 plo(std::numeric_limits<float>::max()), phi(-std::numeric_limits<float>::max());
    for (uint32_t i = pr.first_tri; i < pr.first_tri + pr.tri_count; ++i)
      for (int k = 0; k < 3; ++k) {
        plo = glm::min(plo, soup.positions[soup.indices[i][k]]);
        phi = glm::max(phi, soup.positions[soup.indices[i][k]]);
      }
    out.emplace_back(plo, phi);
  }
  return out;
}

void instance_bounds(const TriangleSoup& soup, size_t instance, const std::vector<std::pair<glm::vec3, glm::vec3>>& protos,
                     glm::vec3* lo, glm::vec3* hi) {
  const InstanceGpu& in = soup.instances[instance];
  const glm::vec3 plo = protos[in.prototype].first, phi = protos[in.prototype].second;
  *lo = glm::vec3(std::numeric_limits<float>::max());
  *hi = glm::vec3(-std::numeric_limits<float>::max());
  for (int c = 0; c < 8; ++c) {
    const glm::vec3 p((c & 1) ? phi.x : plo.x, (c & 2) ? phi.y : plo.y, (c & 4) ? phi.z : plo.z);
    const float* m = in.o2w;
    // In double, then widened by a float ulp or so, so the box holds the triangles the
    // traversal transforms in float.
    glm::dvec3 q(double(m[0]) * p.x + double(m[1]) * p.y + double(m[2]) * p.z + m[3],
                 double(m[4]) * p.x + double(m[5]) * p.y + double(m[6]) * p.z + m[7],
                 double(m[8]) * p.x + double(m[9]) * p.y + double(m[10]) * p.z + m[11]);
    *lo = glm::min(*lo, glm::vec3(q));
    *hi = glm::max(*hi, glm::vec3(q));
  }
  const glm::vec3 pad = (glm::abs(*lo) + glm::abs(*hi)) * 1e-6f;
  *lo -= pad;
  *hi += pad;
}

FlatBvh build_flat_bvh(const EmbreeDevice& device, const TriangleSoup& soup) {
  FlatBvh out;
  const size_t n_top = soup.world_tris() + soup.spheres.size() + soup.instances.size();
  if (n_top == 0) return out;
  if (soup.primitive_count() + soup.instances.size() >= (size_t(1) << 28))
    throw std::runtime_error("too many primitives for the BVH leaf encoding (2^28)");

  // The top-level tree: world triangles, spheres and instances (ids after the spheres').
  std::vector<RTCBounds> inst_bounds(soup.instances.size());
  const auto protos = prototype_bounds(soup);
  for (size_t k = 0; k < soup.instances.size(); ++k) {
    glm::vec3 lo, hi;
    instance_bounds(soup, k, protos, &lo, &hi);
    inst_bounds[k] = RTCBounds{lo.x, lo.y, lo.z, 0.0f, hi.x, hi.y, hi.z, 0.0f};
  }
  std::vector<RTCBuildPrimitive> prims;
  prims.reserve(n_top);
  for (size_t i = 0; i < soup.world_tris(); ++i) prims.push_back(triangle_prim(soup, i));
  for (size_t i = 0; i < soup.spheres.size(); ++i) {
    const glm::vec4& s = soup.spheres[i];
    RTCBuildPrimitive p;
    p.lower_x = s.x - s.w; p.lower_y = s.y - s.w; p.lower_z = s.z - s.w; p.geomID = 0;
    p.upper_x = s.x + s.w; p.upper_y = s.y + s.w; p.upper_z = s.z + s.w; p.primID = unsigned(soup.indices.size() + i);
    prims.push_back(p);
  }
  for (size_t k = 0; k < soup.instances.size(); ++k) {
    const RTCBounds& b = inst_bounds[k];
    RTCBuildPrimitive p;
    p.lower_x = b.lower_x; p.lower_y = b.lower_y; p.lower_z = b.lower_z; p.geomID = 0;
    p.upper_x = b.upper_x; p.upper_y = b.upper_y; p.upper_z = b.upper_z; p.primID = unsigned(soup.primitive_count() + k);
    prims.push_back(p);
  }
  out.nodes.reserve(soup.primitive_count());
  out.leaf_tris.reserve(soup.primitive_count() + soup.instances.size());
  Flattener f{soup, out, inst_bounds};
  int top_depth = 0;
  build_tree(device, prims, f, &top_depth);
  out.max_depth = top_depth;

  // One tree per prototype, after it in the same arrays; each instance points at its root.
  std::vector<int> roots(soup.prototypes.size(), 0);
  for (size_t p = 0; p < soup.prototypes.size(); ++p) {
    const SoupPrototype& pr = soup.prototypes[p];
    if (pr.tri_count == 0) throw std::runtime_error("a shared mesh without triangles");
    prims.clear();
    for (uint32_t i = pr.first_tri; i < pr.first_tri + pr.tri_count; ++i) prims.push_back(triangle_prim(soup, i));
    int depth = 0;
    roots[p] = build_tree(device, prims, f, &depth);
    out.max_prototype_depth = std::max(out.max_prototype_depth, depth);
  }
  // The traversal's stack holds at most 3 entries per inner node on the way down plus the
  // rest of the leaf an instance sits in (kernels/bvh/traverse.h).
  if (!soup.instances.empty() && 3 * (top_depth + 1 + out.max_prototype_depth + 1) + 1 > AW_BVH_STACK_SIZE)
    throw std::runtime_error("the two-level BVH is deeper (" + std::to_string(top_depth + 1) + " + " +
                             std::to_string(out.max_prototype_depth + 1) + " levels) than the traversal stack allows");
  out.instances = soup.instances;
  for (InstanceGpu& in : out.instances) in.root = uint32_t(roots[in.prototype]);
  return out;
}

namespace {
// Embree's filter callback (Embree 3, rtcSetGeometryIntersectFilterFunction): a candidate hit
// in a cutout hole is rejected (valid = 0), and the traversal goes on as if the triangle were
// not there.
// Analytic spheres as an Embree user geometry whose callbacks run the kernels' own sphere test
// (kernels/bvh/intersect_sphere.h) and cutout test, so the scalar path meets the same spheres
// as the device's traversal; Embree's own BVH over them stays independent of ours.
void sphere_bounds(const RTCBoundsFunctionArguments* args) {
  const EmbreeScene* es = static_cast<const EmbreeScene*>(args->geometryUserPtr);
  const glm::vec4& s = es->soup().spheres[args->primID];
  RTCBounds* b = args->bounds_o;
  b->lower_x = s.x - s.w; b->lower_y = s.y - s.w; b->lower_z = s.z - s.w;
  b->upper_x = s.x + s.w; b->upper_y = s.y + s.w; b->upper_z = s.z + s.w;
}

// The sphere's hit in (tnear, tfar) of ray i of a packet, if it is there (cutouts).
bool sphere_ray_hit(const EmbreeScene* es, unsigned prim, RTCRayN* ray, unsigned N, unsigned i, float* t) {
  const glm::vec4& s = es->soup().spheres[prim];
  const float3 o(RTCRayN_org_x(ray, N, i), RTCRayN_org_y(ray, N, i), RTCRayN_org_z(ray, N, i));
  const float3 d(RTCRayN_dir_x(ray, N, i), RTCRayN_dir_y(ray, N, i), RTCRayN_dir_z(ray, N, i));
  // Embree's tnear is inclusive, the kernels' t_min exclusive (ray_cast_embree.cpp passes the
  // next float above a positive t_min): the test below is exclusive of exactly that.
  const float t_min = std::nextafter(RTCRayN_tnear(ray, N, i), -FLT_MAX);
  if (!intersect_sphere(o, d, float3(s.x, s.y, s.z), s.w, t_min, RTCRayN_tfar(ray, N, i), t)) return false;
  const TextureScene* cut = es->cutouts();
  return !cut || material_opaque_at_sphere(*cut, unsigned(es->soup().indices.size()) + prim, o + d * *t);
}

void sphere_intersect(const RTCIntersectFunctionNArguments* args) {
  const EmbreeScene* es = static_cast<const EmbreeScene*>(args->geometryUserPtr);
  RTCRayHitN* rh = args->rayhit;
  RTCRayN* ray = RTCRayHitN_RayN(rh, args->N);
  RTCHitN* hit = RTCRayHitN_HitN(rh, args->N);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    float t;
    if (!sphere_ray_hit(es, args->primID, ray, args->N, i, &t)) continue;
    RTCRayN_tfar(ray, args->N, i) = t;
    RTCHitN_u(hit, args->N, i) = 0.0f;
    RTCHitN_v(hit, args->N, i) = 0.0f;
    RTCHitN_Ng_x(hit, args->N, i) = 0.0f;
    RTCHitN_Ng_y(hit, args->N, i) = 0.0f;
    RTCHitN_Ng_z(hit, args->N, i) = 1.0f;
    RTCHitN_primID(hit, args->N, i) = args->primID;
    RTCHitN_geomID(hit, args->N, i) = args->geomID;
    RTCHitN_instID(hit, args->N, i, 0) = args->context->instID[0];
  }
}

void sphere_occluded(const RTCOccludedFunctionNArguments* args) {
  const EmbreeScene* es = static_cast<const EmbreeScene*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    float t;
    if (sphere_ray_hit(es, args->primID, args->ray, args->N, i, &t))
      RTCRayN_tfar(args->ray, args->N, i) = -std::numeric_limits<float>::infinity();
  }
}

struct CutoutUser {
  const TextureScene* ts;
  uint32_t base;  // the geometry's first triangle id (a prototype's primIDs count from 0)
};

void cutout_filter(const RTCFilterFunctionNArguments* args) {
  const auto* cu = static_cast<const CutoutUser*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const unsigned prim = cu->base + RTCHitN_primID(args->hit, args->N, i);
    if (!material_opaque_at(*cu->ts, prim, RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i)))
      args->valid[i] = 0;
  }
}

// A triangle geometry over triangles [first, first + count) of the soup, their vertices
// copied into Embree's own (padded) buffer and renumbered from 0.
RTCGeometry triangle_geometry(RTCDevice device, const TriangleSoup& soup, size_t first, size_t count) {
  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  uint32_t vlo = std::numeric_limits<uint32_t>::max(), vhi = 0;
  for (size_t i = first; i < first + count; ++i)
    for (int k = 0; k < 3; ++k) {
      vlo = std::min(vlo, soup.indices[i][k]);
      vhi = std::max(vhi, soup.indices[i][k]);
    }
  const size_t nv = size_t(vhi - vlo) + 1;
  // Embree reads 16 bytes per vertex with SSE: allocate through Embree (which pads).
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                        3 * sizeof(float), nv));
  for (size_t i = 0; i < nv; ++i) {
    v[3 * i + 0] = soup.positions[vlo + i].x;
    v[3 * i + 1] = soup.positions[vlo + i].y;
    v[3 * i + 2] = soup.positions[vlo + i].z;
  }
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                             3 * sizeof(unsigned), count));
  for (size_t i = 0; i < count; ++i)
    for (int k = 0; k < 3; ++k) idx[3 * i + k] = soup.indices[first + i][k] - vlo;
  return geom;
}
}  // namespace

EmbreeScene::EmbreeScene(const EmbreeDevice& device, const TriangleSoup& soup, const TextureScene* cutouts) {
  soup_ = &soup;
  if (cutouts) {
    cutouts_ = *cutouts;
    has_cutouts_ = true;
  }
  // Stable addresses for the filter's user data: one per triangle geometry.
  cutout_geoms_.reserve(soup.prototypes.size() + 1);
  auto add_triangles = [&](RTCScene scene, size_t first, size_t count) {
    RTCGeometry geom = triangle_geometry(device.get(), soup, first, count);
    if (cutouts) {
      cutout_geoms_.push_back(CutoutGeom{&cutouts_, uint32_t(first)});
      rtcSetGeometryUserData(geom, &cutout_geoms_.back());
      rtcSetGeometryIntersectFilterFunction(geom, cutout_filter);
      rtcSetGeometryOccludedFilterFunction(geom, cutout_filter);
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene, geom);
    rtcReleaseGeometry(geom);
  };
  static_assert(sizeof(CutoutGeom) == sizeof(CutoutUser), "the filter reads CutoutGeom as CutoutUser");
  scene_ = rtcNewScene(device.get());
  rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
  if (soup.world_tris() > 0) add_triangles(scene_, 0, soup.world_tris());
  if (!soup.spheres.empty()) {
    RTCGeometry geom = rtcNewGeometry(device.get(), RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(geom, unsigned(soup.spheres.size()));
    rtcSetGeometryUserData(geom, this);
    rtcSetGeometryBoundsFunction(geom, sphere_bounds, nullptr);
    rtcSetGeometryIntersectFunction(geom, sphere_intersect);
    rtcSetGeometryOccludedFunction(geom, sphere_occluded);
    rtcCommitGeometry(geom);
    sphere_geom_ = rtcAttachGeometry(scene_, geom);
    rtcReleaseGeometry(geom);
  }
  // Instancing (Embree's own two-level scenes): a scene per prototype, in object space, and an
  // instance geometry per placement with its object-to-world transform.
  for (const SoupPrototype& pr : soup.prototypes) {
    RTCScene ps = rtcNewScene(device.get());
    rtcSetSceneFlags(ps, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(ps, RTC_BUILD_QUALITY_HIGH);
    add_triangles(ps, pr.first_tri, pr.tri_count);
    rtcCommitScene(ps);
    prototype_scenes_.push_back(ps);
  }
  for (size_t k = 0; k < soup.instances.size(); ++k) {
    const InstanceGpu& in = soup.instances[k];
    RTCGeometry geom = rtcNewGeometry(device.get(), RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(geom, prototype_scenes_[in.prototype]);
    rtcSetGeometryTransform(geom, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, in.o2w);
    rtcCommitGeometry(geom);
    const unsigned id = rtcAttachGeometry(scene_, geom);
    rtcReleaseGeometry(geom);
    if (instance_of_geom_.size() <= id) instance_of_geom_.resize(size_t(id) + 1, AW_NONE);
    instance_of_geom_[id] = uint32_t(k);
  }
  rtcCommitScene(scene_);
}

EmbreeScene::~EmbreeScene() {
  if (scene_) rtcReleaseScene(scene_);
  for (RTCScene ps : prototype_scenes_) rtcReleaseScene(ps);
}

EmbreeScene::Hit EmbreeScene::intersect(glm::vec3 org, glm::vec3 dir, float t_min, float t_max) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh;
  rh.ray.org_x = org.x; rh.ray.org_y = org.y; rh.ray.org_z = org.z;
  rh.ray.dir_x = dir.x; rh.ray.dir_y = dir.y; rh.ray.dir_z = dir.z;
  rh.ray.tnear = t_min;
  rh.ray.tfar = t_max;
  rh.ray.time = 0.0f;
  rh.ray.mask = 0xffffffffu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_, &ctx, &rh);
  Hit h;
  h.inst = AW_NONE;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
    h.t = t_max;
    h.u = h.v = 0.0f;
    h.prim = -1;
  } else {
    h.t = rh.ray.tfar;
    h.u = rh.hit.u;
    h.v = rh.hit.v;
    if (rh.hit.instID[0] != RTC_INVALID_GEOMETRY_ID) {
      // A prototype's triangle: its primID counts from the prototype's first triangle.
      h.inst = instance_of_geom_[rh.hit.instID[0]];
      h.prim = int(soup_->prototypes[soup_->instances[h.inst].prototype].first_tri + rh.hit.primID);
    } else {
      // Spheres' ids follow the triangles' (TriangleSoup).
      h.prim = int(rh.hit.primID) + (rh.hit.geomID == sphere_geom_ ? int(soup_->indices.size()) : 0);
    }
  }
  return h;
}

bool EmbreeScene::occluded(glm::vec3 org, glm::vec3 dir, float t_min, float t_max) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRay r;
  r.org_x = org.x; r.org_y = org.y; r.org_z = org.z;
  r.dir_x = dir.x; r.dir_y = dir.y; r.dir_z = dir.z;
  r.tnear = t_min;
  r.tfar = t_max;
  r.time = 0.0f;
  r.mask = 0xffffffffu;
  r.id = 0;
  r.flags = 0;
  rtcOccluded1(scene_, &ctx, &r);
  return r.tfar < 0.0f;  // Embree sets tfar = -inf on a hit
}

}  // namespace aw
