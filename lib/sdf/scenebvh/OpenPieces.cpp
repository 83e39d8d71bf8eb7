#include "sdf/scenebvh/OpenPieces.h"

#include "reference/VertexTriangles.h"
#include "reference/WindingRegions.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace rtsdf {
using namespace gpu::shared;

namespace {

constexpr float kFourPi = 12.566370614359172f;

std::uint32_t nodeFirstOf(const BvhNode& n) {
  std::uint32_t u;
  std::memcpy(&u, &n.lo.w, 4);
  return u;
}
std::uint32_t nodeCountOf(const BvhNode& n) {
  std::uint32_t u;
  std::memcpy(&u, &n.hi.w, 4);
  return u;
}

/// A node's cluster while the dipoles are built: area-weighted centroid sum, total area, summed vector area.
struct Cluster {
  glm::dvec3 weighted{0.0}, areaNormal{0.0};
  double area = 0.0;
  std::uint32_t begin = 0, end = 0; ///< its leaf-ordered triangles (a subtree's are contiguous)
};

Cluster buildCluster(const MeshBvhs& meshes, std::uint32_t index, std::vector<WindingNode>& out) {
  const BvhNode& n = meshes.nodes[index];
  Cluster c;
  const std::uint32_t first = nodeFirstOf(n), count = nodeCountOf(n);
  if (count == 0) {
    const Cluster l = buildCluster(meshes, first, out), r = buildCluster(meshes, first + 1, out);
    c = {l.weighted + r.weighted, l.areaNormal + r.areaNormal, l.area + r.area, std::min(l.begin, r.begin),
         std::max(l.end, r.end)};
  } else {
    c.begin = first;
    c.end = first + count;
    for (std::uint32_t t = first; t < first + count; ++t) {
      const glm::dvec3 a(meshes.corners[3 * t]), b(meshes.corners[3 * t + 1]), d(meshes.corners[3 * t + 2]);
      const glm::dvec3 v = 0.5 * glm::cross(b - a, d - a);
      const double area = glm::length(v);
      c.areaNormal += v;
      c.weighted += area * (a + b + d) / 3.0;
      c.area += area;
    }
  }
  const glm::dvec3 lo(n.lo), hi(n.hi);
  const glm::dvec3 centre = c.area > 0.0 ? c.weighted / c.area : 0.5 * (lo + hi);
  double r2 = 0.0; // the farthest corner of its triangles: the ball holds every one (a tighter ball than the box's
                   // lets more clusters count by their dipoles)
  for (std::uint32_t k = 3 * c.begin; k < 3 * c.end; ++k) {
    const glm::dvec3 q(meshes.corners[k]);
    r2 = std::max(r2, glm::dot(q - centre, q - centre));
  }
  // Rounded up so the float test never calls a nearer cluster far.
  out[index] = {glm::vec4(glm::vec3(centre), float(std::sqrt(r2) * (1.0 + 1e-6))), glm::vec4(glm::vec3(c.areaNormal), 0.0f)};
  return c;
}

} // namespace

bool SceneOpenPieces::any() const {
  return std::any_of(flagsOfLeaf.begin(), flagsOfLeaf.end(), [](std::uint32_t f) { return f != 0u; });
}

std::vector<WindingNode> windingNodes(const MeshBvhs& meshes) {
  std::vector<WindingNode> out(meshes.nodes.size());
  for (std::size_t m = 0; m < meshes.roots.size(); ++m)
    if (meshes.firstTriangles.size() > m &&
        (m + 1 < meshes.firstTriangles.size() ? meshes.firstTriangles[m + 1] : meshes.triangleIds.size()) >
            meshes.firstTriangles[m])
      buildCluster(meshes, meshes.roots[m], out);
  return out;
}

SceneOpenPieces sceneOpenPieces(const Scene& scene, const MeshBvhs& meshes) {
  SceneOpenPieces out;
  out.flagsOfLeaf.assign(meshes.triangleIds.size(), 0u);
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    if (scene.meshReports.at(m).watertight()) continue;
    // The rim and pieces as the exact field finds them on each instance of the mesh (its world copy has the same
    // edges and corners).
    WorldMesh wm;
    wm.positions = scene.meshes[m].positions;
    wm.triangles = scene.meshes[m].triangles;
    const VertexTriangles around(wm.positions.size(), wm.triangles);
    const WindingRegions regions(wm, around, connectedPieces(wm, around));
    const std::uint32_t several = regions.pieceCount() > 1 ? kOpenSeveralPieces : 0u;
    const std::uint32_t begin = meshes.firstTriangles.at(m);
    const std::uint32_t end = m + 1 < meshes.firstTriangles.size() ? meshes.firstTriangles[m + 1]
                                                                    : std::uint32_t(meshes.triangleIds.size());
    for (std::uint32_t leaf = begin; leaf < end; ++leaf) {
      const unsigned t = meshes.triangleIds[leaf];
      std::uint32_t f = kOpenMesh | several;
      for (int k = 0; k < 3; ++k) {
        if (regions.onRim(t, TriangleFeature(int(TriangleFeature::EdgeAB) + k))) f |= kOpenRimEdgeAB << k;
        if (regions.onRim(t, TriangleFeature(int(TriangleFeature::VertexA) + k))) f |= kOpenRimVertexA << k;
      }
      out.flagsOfLeaf[leaf] = f;
    }
  }
  out.windingNodes = windingNodes(meshes);
  return out;
}

OpenWindingCpu::OpenWindingCpu(const Scene& scene, double time, const glm::dvec3& frameOrigin)
    : mScene(scene), mMeshes(buildMeshBvhs(scene)), mPieces(sceneOpenPieces(scene, mMeshes)),
      mTop(buildInstanceBvh(scene, mMeshes, time, frameOrigin)) {
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    std::vector<std::uint32_t> leafOf(scene.meshes[m].triangles.size(), 0u);
    const std::uint32_t begin = mMeshes.firstTriangles[m];
    for (std::uint32_t k = 0; k < leafOf.size(); ++k) leafOf[mMeshes.triangleIds[begin + k]] = begin + k;
    mLeafOfTriangle.push_back(std::move(leafOf));
  }
}

bool OpenWindingCpu::windingSigns(const glm::vec3& p, std::uint32_t instance, std::uint32_t triangle) const {
  const std::uint32_t leaf = mLeafOfTriangle.at(mScene.instances.at(instance).mesh).at(triangle);
  const std::uint32_t flags = mPieces.flagsOfLeaf[leaf];
  if ((flags & kOpenMesh) == 0u) return false;
  const BvhInstance& inst = mTop.instances.at(instance);
  const glm::vec3 a = xformPoint(inst.objectToWorld, glm::vec3(mMeshes.corners[3 * leaf]));
  const glm::vec3 b = xformPoint(inst.objectToWorld, glm::vec3(mMeshes.corners[3 * leaf + 1]));
  const glm::vec3 c = xformPoint(inst.objectToWorld, glm::vec3(mMeshes.corners[3 * leaf + 2]));
  return gpu::shared::windingSigns(flags, nearestFeature(p, a, b, c));
}

float OpenWindingCpu::windingNumber(const glm::vec3& p, std::uint32_t instance) const {
  const glm::vec3 po = xformPoint(mTop.instances.at(instance).worldToObject, p);
  float w = windingWalk(po, instance, kWindingFarRatio);
  if (std::fabs(w - 0.5f) < kWindingRecheckBand) w = windingWalk(po, instance, kWindingRecheckFarRatio);
  return std::fabs(w - 0.5f) < kWindingExactBand ? windingNumberExact(p, instance) : w; // WindingExactPass
}

float OpenWindingCpu::windingWalk(const glm::vec3& po, std::uint32_t instance, float ratio) const {
  const BvhInstance& inst = mTop.instances.at(instance);
  float sum = 0.0f;
  std::vector<std::uint32_t> stack{inst.blasRoot};
  while (!stack.empty()) {
    const std::uint32_t i = stack.back();
    stack.pop_back();
    const WindingNode& wn = mPieces.windingNodes[i];
    if (windingFar(po, wn, ratio)) {
      sum += dipoleSolidAngle(po, wn);
      continue;
    }
    const BvhNode& n = mMeshes.nodes[i];
    const std::uint32_t first = nodeFirstOf(n), count = nodeCountOf(n);
    if (count == 0) {
      stack.push_back(first + 1);
      stack.push_back(first);
      continue;
    }
    for (std::uint32_t t = first; t < first + count; ++t)
      sum += triangleSolidAngle(po, glm::vec3(mMeshes.corners[3 * t]), glm::vec3(mMeshes.corners[3 * t + 1]),
                                glm::vec3(mMeshes.corners[3 * t + 2]));
  }
  return sum / kFourPi;
}

float OpenWindingCpu::windingNumberExact(const glm::vec3& p, std::uint32_t instance) const {
  const BvhInstance& inst = mTop.instances.at(instance);
  const glm::vec3 po = xformPoint(inst.worldToObject, p);
  const std::size_t m = mScene.instances.at(instance).mesh;
  double sum = 0.0;
  for (std::uint32_t k = 0; k < mScene.meshes[m].triangles.size(); ++k) {
    const std::uint32_t t = mMeshes.firstTriangles[m] + k;
    sum += triangleSolidAngle(po, glm::vec3(mMeshes.corners[3 * t]), glm::vec3(mMeshes.corners[3 * t + 1]),
                              glm::vec3(mMeshes.corners[3 * t + 2]));
  }
  return float(sum / double(kFourPi));
}

} // namespace rtsdf
