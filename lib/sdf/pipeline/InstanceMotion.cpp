#include "sdf/pipeline/InstanceMotion.h"

#include "scene/SceneGeometry.h"

#include <cmath>
#include <limits>

namespace rtsdf {

std::vector<gpu::shared::MovedBox> movedInstanceBoxes(const Scene& scene, const std::vector<Bounds>& meshBounds,
                                                      double before, double after, const glm::dvec3& origin,
                                                      const Bounds& reach) {
  std::vector<gpu::shared::MovedBox> boxes;
  for (const Instance& inst : scene.instances) {
    const glm::dmat4 m0 = inst.matrixAt(before), m1 = inst.matrixAt(after);
    const Bounds& local = meshBounds.at(inst.mesh);
    if (m0 == m1 || local.empty()) continue;
    Bounds swept;
    for (int corner = 0; corner < 8; ++corner) {
      const glm::dvec4 p((corner & 1 ? local.max : local.min).x, (corner & 2 ? local.max : local.min).y,
                         (corner & 4 ? local.max : local.min).z, 1.0);
      swept.add(glm::dvec3(m0 * p));
      swept.add(glm::dvec3(m1 * p));
    }
    if (!reach.empty() && !swept.meets(reach)) continue;
    swept.min -= origin;
    swept.max -= origin;
    gpu::shared::MovedBox box{};
    for (int a = 0; a < 3; ++a) {
      box.lo[a] = std::nextafter(float(swept.min[a]), -INFINITY);
      box.hi[a] = std::nextafter(float(swept.max[a]), INFINITY);
    }
    if (boxes.size() < RTSDF_MAX_MOVED_BOXES) {
      boxes.push_back(box);
    } else { // the shader reads a bounded list: the rest share the last box
      boxes.back().lo = glm::min(boxes.back().lo, box.lo);
      boxes.back().hi = glm::max(boxes.back().hi, box.hi);
    }
  }
  return boxes;
}

InstanceMotion::InstanceMotion(const gpu::VulkanContext& ctx, const Scene& scene, const Bounds& reach)
    : mScene(&scene), mReach(reach),
      mBuffer(ctx, RTSDF_MAX_MOVED_BOXES * sizeof(gpu::shared::MovedBox),
              VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::Buffer::Memory::Device,
              "moved instance boxes") {
  setScene(scene);
}

void InstanceMotion::setScene(const Scene& scene) {
  mScene = &scene;
  mMeshBounds.clear();
  for (const Mesh& mesh : scene.meshes) mMeshBounds.push_back(positionBounds(mesh));
}

void InstanceMotion::recordClear(VkCommandBuffer cmd) const {
  vkCmdFillBuffer(cmd, mBuffer.handle(), 0, VK_WHOLE_SIZE, 0u);
}

void InstanceMotion::checkPlacement(double time) const { checkInstancePlacement(*mScene, mMeshBounds, time); }

const std::vector<gpu::shared::MovedBox>& InstanceMotion::advance(std::uint32_t frame, double time,
                                                                  const glm::dvec3& origin) {
  mLast = frame > 1 ? movedInstanceBoxes(*mScene, mMeshBounds, mPreviousTime, time, origin, mReach)
                    : std::vector<gpu::shared::MovedBox>{};
  mPreviousTime = time;
  return mLast;
}

void InstanceMotion::recordUpload(VkCommandBuffer cmd) const {
  gpu::recordUpload(cmd, mBuffer, mLast.data(), mLast.size() * sizeof(mLast[0]));
}

namespace {

/// The coarse voxels whose cells come within @a reach of the boxes' union, grown by @a margin voxels, clamped.
CoarseVoxelBox coarseCellsNear(const std::vector<gpu::shared::MovedBox>& boxes, const GridSpec& coarse, double reach,
                               double margin) {
  CoarseVoxelBox box;
  if (boxes.empty()) return box;
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const gpu::shared::MovedBox& b : boxes) {
    lo = glm::min(lo, glm::dvec3(glm::vec3(b.lo)));
    hi = glm::max(hi, glm::dvec3(glm::vec3(b.hi)));
  }
  const glm::dvec3 first = glm::floor((lo - reach - coarse.origin) / coarse.voxelSize) - margin;
  const glm::dvec3 last = glm::floor((hi + reach - coarse.origin) / coarse.voxelSize) + margin;
  // Clamped in double: a box far off the grid stays empty instead of wrapping an int.
  box.lo = glm::ivec3(glm::max(first, glm::dvec3(0.0)));
  box.hi = glm::ivec3(glm::min(last, glm::dvec3(coarse.dims - 1)));
  if (glm::any(glm::lessThan(last, glm::dvec3(0.0))) || glm::any(glm::greaterThan(first, glm::dvec3(coarse.dims - 1))))
    return CoarseVoxelBox{};
  return box;
}

} // namespace

CoarseVoxelBox movedSeedBox(const std::vector<gpu::shared::MovedBox>& boxes, const GridSpec& coarse) {
  return coarseCellsNear(boxes, coarse, 0.0, 2.0);
}

CoarseVoxelBox movedReachBox(const std::vector<gpu::shared::MovedBox>& boxes, const GridSpec& coarse, double reach) {
  return coarseCellsNear(boxes, coarse, reach, 1.0);
}

} // namespace rtsdf
