#include "bvh/Bvh.h"

#include "util/Error.h"

#include <embree3/rtcore.h>
#include <fmt/format.h>

#include <cmath>
#include <cstring>

namespace rtsdf {
using gpu::shared::BvhInstance;
using gpu::shared::BvhNode;

namespace {

// Embree's builder calls back to make a pointer tree in its thread-local memory; we flatten it afterwards.
struct BuildNode {
  bool leaf;
  glm::vec3 lo[2], hi[2];  // inner: children's boxes
  BuildNode* child[2];     // inner
  std::uint32_t first = 0; // leaf: offset into the leaf-order list
  std::uint32_t count = 0;
  std::uint32_t prims[RTC_BUILD_MAX_PRIMITIVES_PER_LEAF];
};

void* createNode(RTCThreadLocalAllocator alloc, unsigned int childCount, void*) {
  auto* n = static_cast<BuildNode*>(rtcThreadLocalAlloc(alloc, sizeof(BuildNode), 16));
  new (n) BuildNode();
  n->leaf = false;
  return n;
}

void setChildren(void* node, void** children, unsigned int childCount, void*) {
  auto* n = static_cast<BuildNode*>(node);
  for (unsigned i = 0; i < childCount; ++i) n->child[i] = static_cast<BuildNode*>(children[i]);
}

void setBounds(void* node, const RTCBounds** bounds, unsigned int childCount, void*) {
  auto* n = static_cast<BuildNode*>(node);
  for (unsigned i = 0; i < childCount; ++i) {
    n->lo[i] = {bounds[i]->lower_x, bounds[i]->lower_y, bounds[i]->lower_z};
    n->hi[i] = {bounds[i]->upper_x, bounds[i]->upper_y, bounds[i]->upper_z};
  }
}

void* createLeaf(RTCThreadLocalAllocator alloc, const RTCBuildPrimitive* prims, size_t count, void*) {
  auto* n = static_cast<BuildNode*>(rtcThreadLocalAlloc(alloc, sizeof(BuildNode), 16));
  new (n) BuildNode();
  n->leaf = true;
  n->count = std::uint32_t(count);
  for (size_t i = 0; i < count; ++i) n->prims[i] = prims[i].primID;
  return n;
}

float asFloat(std::uint32_t u) {
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}

BvhNode makeNode(const glm::vec3& lo, const glm::vec3& hi, std::uint32_t first, std::uint32_t count) {
  return {glm::vec4(lo, asFloat(first)), glm::vec4(hi, asFloat(count))};
}

/// Smallest singular value of a 3x3 matrix: sqrt of the smallest eigenvalue of M^T M (cyclic Jacobi).
double smallestSingularValue(const glm::dmat3& m) {
  glm::dmat3 a = glm::transpose(m) * m;
  for (int sweep = 0; sweep < 32; ++sweep) {
    const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    if (off < 1e-30 * (a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2]) || off == 0.0) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        if (a[p][q] == 0.0) continue;
        const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
        const double t = (theta >= 0 ? 1.0 : -1.0) / (std::fabs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
        glm::dmat3 j(1.0);
        j[p][p] = c; j[q][q] = c; j[q][p] = s; j[p][q] = -s;
        a = glm::transpose(j) * a * j;
      }
  }
  const double e = std::min(a[0][0], std::min(a[1][1], a[2][2]));
  return std::sqrt(std::max(e, 0.0));
}

struct Device {
  RTCDevice d = rtcNewDevice(nullptr);
  ~Device() { if (d) rtcReleaseDevice(d); }
};

} // namespace

std::vector<BvhNode> buildBvh(const std::vector<glm::vec3>& lo, const std::vector<glm::vec3>& hi, int maxLeafSize,
                              std::vector<std::uint32_t>& order) {
  if (lo.size() != hi.size() || lo.empty()) throw Error("BVH: no primitives");
  if (maxLeafSize < 1 || maxLeafSize > RTC_BUILD_MAX_PRIMITIVES_PER_LEAF)
    throw Error(fmt::format("BVH: leaf size {} out of range [1, {}]", maxLeafSize, int(RTC_BUILD_MAX_PRIMITIVES_PER_LEAF)));
  static Device device; // one Embree device for all builds
  if (!device.d) throw Error("Embree: cannot create a device");
  std::vector<RTCBuildPrimitive> prims(lo.size());
  glm::vec3 rootLo(INFINITY), rootHi(-INFINITY);
  for (std::size_t i = 0; i < lo.size(); ++i) {
    prims[i] = {lo[i].x, lo[i].y, lo[i].z, 0u, hi[i].x, hi[i].y, hi[i].z, unsigned(i)};
    rootLo = glm::min(rootLo, lo[i]);
    rootHi = glm::max(rootHi, hi[i]);
  }
  RTCBVH bvh = rtcNewBVH(device.d);
  RTCBuildArguments args = rtcDefaultBuildArguments();
  args.buildQuality = RTC_BUILD_QUALITY_MEDIUM; // SAH without spatial splits (primitives stay whole)
  args.maxBranchingFactor = 2;
  args.maxDepth = 48; // the GPU traversal stacks hold 64 entries
  args.maxLeafSize = unsigned(maxLeafSize);
  args.bvh = bvh;
  args.primitives = prims.data();
  args.primitiveCount = prims.size();
  args.primitiveArrayCapacity = prims.size();
  args.createNode = createNode;
  args.setNodeChildren = setChildren;
  args.setNodeBounds = setBounds;
  args.createLeaf = createLeaf;
  auto* root = static_cast<BuildNode*>(rtcBuildBVH(&args));
  if (!root) {
    rtcReleaseBVH(bvh);
    throw Error(fmt::format("Embree: rtcBuildBVH failed (error {})", int(rtcGetDeviceError(device.d))));
  }
  // Flatten depth first; the two children of a node take adjacent slots.
  std::vector<BvhNode> nodes;
  order.clear();
  nodes.push_back({});
  struct Item { BuildNode* n; std::uint32_t slot; glm::vec3 lo, hi; };
  std::vector<Item> stack{{root, 0, rootLo, rootHi}};
  while (!stack.empty()) {
    const Item it = stack.back();
    stack.pop_back();
    if (it.n->leaf) {
      nodes[it.slot] = makeNode(it.lo, it.hi, std::uint32_t(order.size()), it.n->count);
      for (std::uint32_t i = 0; i < it.n->count; ++i) order.push_back(it.n->prims[i]);
      continue;
    }
    const auto left = std::uint32_t(nodes.size());
    nodes.push_back({});
    nodes.push_back({});
    nodes[it.slot] = makeNode(it.lo, it.hi, left, 0);
    stack.push_back({it.n->child[1], left + 1, it.n->lo[1], it.n->hi[1]});
    stack.push_back({it.n->child[0], left, it.n->lo[0], it.n->hi[0]});
  }
  rtcReleaseBVH(bvh); // frees the pointer tree
  return nodes;
}

MeshBvhs buildMeshBvhs(const Scene& scene, int maxLeafSize) {
  MeshBvhs out;
  for (const Mesh& mesh : scene.meshes) {
    std::vector<glm::vec3> lo(mesh.triangles.size()), hi(mesh.triangles.size());
    glm::vec3 mlo(INFINITY), mhi(-INFINITY);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const glm::uvec3 tri = mesh.triangles[t];
      const glm::vec3 a = mesh.positions[tri.x], b = mesh.positions[tri.y], c = mesh.positions[tri.z];
      lo[t] = glm::min(a, glm::min(b, c));
      hi[t] = glm::max(a, glm::max(b, c));
      mlo = glm::min(mlo, lo[t]);
      mhi = glm::max(mhi, hi[t]);
    }
    std::vector<std::uint32_t> order;
    std::vector<BvhNode> nodes = buildBvh(lo, hi, maxLeafSize, order);
    const auto nodeBase = std::uint32_t(out.nodes.size());
    const auto triBase = std::uint32_t(out.triangleIds.size());
    for (BvhNode n : nodes) {
      std::uint32_t first, count;
      std::memcpy(&first, &n.lo.w, 4);
      std::memcpy(&count, &n.hi.w, 4);
      first += count ? triBase : nodeBase; // make indices absolute
      n.lo.w = asFloat(first);
      out.nodes.push_back(n);
    }
    for (std::uint32_t t : order) {
      const glm::uvec3 tri = mesh.triangles[t];
      for (int c = 0; c < 3; ++c) out.corners.emplace_back(mesh.positions[tri[c]], 1.0f);
      out.triangleIds.push_back(t);
    }
    out.roots.push_back(nodeBase);
    out.firstTriangles.push_back(triBase);
    out.meshLo.push_back(mlo);
    out.meshHi.push_back(mhi);
  }
  return out;
}

InstanceBvh buildInstanceBvh(const Scene& scene, const MeshBvhs& meshes, double time, const glm::dvec3& frameOrigin) {
  InstanceBvh out;
  const std::size_t n = scene.instances.size();
  std::vector<glm::vec3> lo(n), hi(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Instance& inst = scene.instances[i];
    glm::dmat4 m = inst.matrixAt(time);
    m[3] -= glm::dvec4(frameOrigin, 0.0);
    const glm::dmat4 inv = glm::inverse(m);
    BvhInstance gi{};
    for (int r = 0; r < 3; ++r) {
      gi.objectToWorld[r] = glm::vec4(m[0][r], m[1][r], m[2][r], m[3][r]);
      gi.worldToObject[r] = glm::vec4(inv[0][r], inv[1][r], inv[2][r], inv[3][r]);
    }
    gi.blasRoot = meshes.roots.at(inst.mesh);
    gi.mirrored = glm::determinant(glm::dmat3(m)) < 0.0 ? 1u : 0u;
    gi.instanceId = std::uint32_t(i);
    // World distances are at least the smallest singular value of M times object-space distances, so
    // object-space boxes can cull world-space closest-point queries.
    gi.minScale = float(smallestSingularValue(glm::dmat3(m)) * (1.0 - 1e-6));
    out.instances.push_back(gi);
    // World box of the transformed object box (Arvo): centre and half-extent through |M|.
    const glm::dvec3 c = 0.5 * glm::dvec3(meshes.meshLo[inst.mesh] + meshes.meshHi[inst.mesh]);
    const glm::dvec3 e = 0.5 * glm::dvec3(meshes.meshHi[inst.mesh] - meshes.meshLo[inst.mesh]);
    const glm::dvec3 wc = glm::dvec3(m * glm::dvec4(c, 1.0));
    glm::dvec3 we(0.0);
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) we[r] += std::abs(m[k][r]) * e[k];
    // Float rounding of the transformed corners must stay inside the box: pad by a few ulps.
    const glm::dvec3 pad = 1e-6 * (glm::abs(wc) + we) + 1e-12;
    lo[i] = glm::vec3(wc - we - pad);
    hi[i] = glm::vec3(wc + we + pad);
  }
  out.nodes = buildBvh(lo, hi, 1, out.slots);
  return out;
}

} // namespace rtsdf
