#include "sdf/scenebvh/ClosedPieces.h"

#include "scene/MeshRepair.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>

namespace rtsdf {
using namespace gpu::shared;

namespace {

float bitsAsFloat(std::uint32_t u) {
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}
std::uint32_t floatAsBits(float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}

/// A closed piece of one instance, placed: its world box.
struct PlacedPiece {
  std::uint32_t slot, box; // instance slot, index in closedBoxes[mesh]
  glm::vec3 lo, hi;
};

} // namespace

std::size_t SceneClosedPieces::instancedClosedPieces(const Scene& scene) const {
  std::size_t n = 0;
  for (const Instance& inst : scene.instances) n += closedBoxes.at(inst.mesh).size();
  return n;
}

SceneClosedPieces sceneClosedPieces(const Scene& scene, const MeshBvhs& meshes) {
  SceneClosedPieces out;
  out.pieceOfLeaf.assign(meshes.triangleIds.size(), kOpenPiece);
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    const MeshPieces pieces = meshPieces(mesh.triangles);
    std::vector<std::int64_t> slot(pieces.count(), -1);
    std::vector<SceneClosedPieces::Box> boxes;
    for (std::uint32_t p = 0; p < pieces.count(); ++p)
      if (pieces.closed[p]) {
        slot[p] = std::int64_t(boxes.size());
        boxes.push_back({p, glm::vec3(INFINITY), glm::vec3(-INFINITY)});
      }
    const std::uint32_t begin = meshes.firstTriangles.at(m);
    const std::uint32_t end = m + 1 < meshes.firstTriangles.size() ? meshes.firstTriangles[m + 1]
                                                                    : std::uint32_t(meshes.triangleIds.size());
    for (std::uint32_t leaf = begin; leaf < end; ++leaf) {
      const std::uint32_t t = meshes.triangleIds[leaf];
      const std::int64_t k = slot[pieces.pieceOf[t]];
      if (k < 0) continue;
      out.pieceOfLeaf[leaf] = pieces.pieceOf[t];
      SceneClosedPieces::Box& b = boxes[std::size_t(k)];
      for (int c = 0; c < 3; ++c) {
        b.lo = glm::min(b.lo, glm::vec3(meshes.corners[3 * leaf + c]));
        b.hi = glm::max(b.hi, glm::vec3(meshes.corners[3 * leaf + c]));
      }
    }
    out.closedBoxes.push_back(std::move(boxes));
    out.leafBegin.push_back(begin);
    out.leafEnd.push_back(end);
  }
  return out;
}

std::vector<UnionPiece> overlappingClosedPieces(const Scene& scene, const SceneClosedPieces& pieces,
                                                const InstanceBvh& top, const Bounds& reach) {
  std::vector<PlacedPiece> placed;
  for (std::uint32_t s = 0; s < top.instances.size(); ++s) {
    const BvhInstance& inst = top.instances[s];
    const auto& boxes = pieces.closedBoxes.at(scene.instances.at(s).mesh);
    for (std::uint32_t b = 0; b < boxes.size(); ++b) {
      PlacedPiece pp{s, b, glm::vec3(INFINITY), glm::vec3(-INFINITY)};
      for (int c = 0; c < 8; ++c) {
        const glm::vec3 corner((c & 1) ? boxes[b].hi.x : boxes[b].lo.x, (c & 2) ? boxes[b].hi.y : boxes[b].lo.y,
                               (c & 4) ? boxes[b].hi.z : boxes[b].lo.z);
        const glm::vec3 w = xformPoint(inst.objectToWorld, corner);
        pp.lo = glm::min(pp.lo, w);
        pp.hi = glm::max(pp.hi, w);
      }
      // Rounding of the placement: boxes that touch must be seen to touch.
      const glm::vec3 slack = 1e-5f * (pp.hi - pp.lo) + 1e-6f * glm::max(glm::abs(pp.lo), glm::abs(pp.hi));
      pp.lo -= slack;
      pp.hi += slack;
      placed.push_back(pp);
    }
  }
  // Sweep along x: each piece against the later ones that start before it ends.
  std::sort(placed.begin(), placed.end(), [](const PlacedPiece& a, const PlacedPiece& b) { return a.lo.x < b.lo.x; });
  std::vector<bool> overlaps(placed.size(), false);
  for (std::size_t a = 0; a < placed.size(); ++a)
    for (std::size_t b = a + 1; b < placed.size() && placed[b].lo.x <= placed[a].hi.x; ++b)
      if (glm::all(glm::lessThanEqual(placed[a].lo, placed[b].hi)) &&
          glm::all(glm::lessThanEqual(placed[b].lo, placed[a].hi)))
        overlaps[a] = overlaps[b] = true;
  std::vector<UnionPiece> out;
  for (std::size_t k = 0; k < placed.size(); ++k) {
    if (!overlaps[k]) continue;
    if (!reach.empty() && !Bounds{glm::dvec3(placed[k].lo), glm::dvec3(placed[k].hi)}.meets(reach)) continue;
    const SceneClosedPieces::Box& b = pieces.closedBoxes[scene.instances[placed[k].slot].mesh][placed[k].box];
    out.push_back({glm::vec4(b.lo, bitsAsFloat(placed[k].slot)), glm::vec4(b.hi, bitsAsFloat(b.piece))});
  }
  // In instance order, as built: the list (and so the GPU's work order) does not depend on the sort.
  std::sort(out.begin(), out.end(), [](const UnionPiece& a, const UnionPiece& b) {
    return std::make_pair(floatAsBits(a.lo.w), floatAsBits(a.hi.w)) <
           std::make_pair(floatAsBits(b.lo.w), floatAsBits(b.hi.w));
  });
  return out;
}

bool insideAnotherPieceCpu(const Scene& scene, const MeshBvhs& meshes, const SceneClosedPieces& pieces,
                           const InstanceBvh& top, const std::vector<UnionPiece>& list, const glm::vec3& p,
                           std::uint32_t skipSlot, std::uint32_t skipPiece) {
  for (const UnionPiece& u : list) {
    const std::uint32_t slot = floatAsBits(u.lo.w), piece = floatAsBits(u.hi.w);
    if (slot == skipSlot && piece == skipPiece) continue;
    const glm::vec3 po = xformPoint(top.instances.at(slot).worldToObject, p);
    if (glm::any(glm::lessThan(po, glm::vec3(u.lo))) || glm::any(glm::greaterThan(po, glm::vec3(u.hi)))) continue;
    const std::size_t m = scene.instances.at(slot).mesh;
    auto odd = [&](std::uint32_t k) {
      const glm::vec3 d = unionRayDirection(k);
      bool parity = false;
      for (std::uint32_t leaf = pieces.leafBegin[m]; leaf < pieces.leafEnd[m]; ++leaf)
        if (pieces.pieceOfLeaf[leaf] == piece &&
            rayCrossesTriangle(po, d, glm::vec3(meshes.corners[3 * leaf]), glm::vec3(meshes.corners[3 * leaf + 1]),
                               glm::vec3(meshes.corners[3 * leaf + 2])))
          parity = !parity;
      return parity;
    };
    const bool first = odd(0), second = odd(1);
    if (first == second ? first : odd(2)) return true;
  }
  return false;
}

ClosedPieceUnionCpu::ClosedPieceUnionCpu(const Scene& scene, double time, const glm::dvec3& frameOrigin)
    : mScene(scene), mMeshes(buildMeshBvhs(scene)), mPieces(sceneClosedPieces(scene, mMeshes)),
      mTop(buildInstanceBvh(scene, mMeshes, time, frameOrigin)), mList(overlappingClosedPieces(scene, mPieces, mTop)) {
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    std::vector<std::uint32_t> of(scene.meshes[m].triangles.size(), kOpenPiece);
    for (std::uint32_t leaf = mPieces.leafBegin[m]; leaf < mPieces.leafEnd[m]; ++leaf)
      of[mMeshes.triangleIds[leaf]] = mPieces.pieceOfLeaf[leaf];
    mPieceOfTriangle.push_back(std::move(of));
  }
}

bool ClosedPieceUnionCpu::insideAnother(const glm::vec3& p, std::uint32_t instance, std::uint32_t triangle) const {
  if (mList.empty()) return false;
  const std::uint32_t piece =
      instance == kNoInstance ? kOpenPiece : mPieceOfTriangle.at(mScene.instances.at(instance).mesh).at(triangle);
  return insideAnotherPieceCpu(mScene, mMeshes, mPieces, mTop, mList, p, instance, piece);
}

} // namespace rtsdf
