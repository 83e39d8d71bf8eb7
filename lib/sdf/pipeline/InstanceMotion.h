#pragma once
/// @file InstanceMotion.h
/// @brief The instances' motion between frames, the incremental refinement's input: the boxes they swept
///        (movedInstanceBoxes) and InstanceMotion, which keeps the previous frame's time and the device buffer the
///        boxes travel in.
#include "gpu/Resources.h"
#include "grid/GridSpec.h"
#include "sdf/coarse/CoarseSdf.h"
#include "sdf/refine/RefineParams.h"
#include "scene/Scene.h"
#include "util/Bounds.h"

#include <cstdint>
#include <vector>

namespace rtsdf {

/// @brief The boxes the instances of @a scene swept between @a before and @a after seconds, one per instance whose
///        transform changed: the union of its world bounds in both poses (the corners of @a meshBounds[mesh]
///        transformed in double), measured from @a origin and rounded outwards to float. At most
///        RTSDF_MAX_MOVED_BOXES; further ones are merged into the last box. The incremental refinement's input.
/// @param reach where given and not empty (world space), only the boxes that meet it: an instance that moves
///        farther from a pipeline's grid than the band and the coarse bound reach changes none of its fields.
std::vector<gpu::shared::MovedBox> movedInstanceBoxes(const Scene& scene, const std::vector<Bounds>& meshBounds,
                                                      double before, double after, const glm::dvec3& origin,
                                                      const Bounds& reach = {});

/// @brief The coarse voxels of @a coarse (a grid in the boxes' frame) whose seeds the instances that swept @a boxes
///        can have changed: the voxels the boxes' union meets, grown by two voxels (VoxelizePass marks the voxels a
///        triangle touches, which may be the neighbour of the one holding it, and places corners in float), clamped to
///        the grid (empty where the boxes miss it).
CoarseVoxelBox movedSeedBox(const std::vector<gpu::shared::MovedBox>& boxes, const GridSpec& coarse);

/// @brief The coarse voxels of @a coarse whose cells come within @a reach (scene units) of the union of @a boxes, grown
///        by a voxel for rounding and clamped to the grid (empty where none): with the band plus MaskParams::reachPad,
///        every band voxel gpu::shared::movedWithinReach can find near a box.
CoarseVoxelBox movedReachBox(const std::vector<gpu::shared::MovedBox>& boxes, const GridSpec& coarse, double reach);

/// @brief The instances' motion from frame to frame of one pipeline. Owns the meshes' own bounds (positionBounds,
///        what placement checks and swept boxes start from), the previous frame's time, the last frame's boxes and
///        the device buffer MaskCompactPass reads them from (RTSDF_MAX_MOVED_BOXES MovedBox, "moved instance
///        boxes"). @a scene must outlive it.
class InstanceMotion {
public:
  /// @param reach the world box an instance's motion must meet to count (movedInstanceBoxes; empty: every motion).
  /// @throw VulkanError when the buffer cannot be allocated.
  InstanceMotion(const gpu::VulkanContext& ctx, const Scene& scene, const Bounds& reach = {});
  /// @brief Record: the buffer cleared (construction only).
  void recordClear(VkCommandBuffer cmd) const;
  /// @brief Refuse a frame at @a time whose instances leave the supported coordinates.
  /// @throw Error as checkInstancePlacement does.
  void checkPlacement(double time) const;
  /// @brief The boxes swept since the previous frame, for frame number @a frame at @a time seconds (none on the
  ///        first frame: every voxel is new to the mask), measured from @a origin; @a time becomes the previous.
  const std::vector<gpu::shared::MovedBox>& advance(std::uint32_t frame, double time, const glm::dvec3& origin);
  /// @brief Record the last boxes' upload into the buffer (vkCmdUpdateBuffer; the reader's barrier orders it).
  void recordUpload(VkCommandBuffer cmd) const;
  /// @brief From the next frame on, count motion that meets @a reach (world space; a pipeline whose grids scrolled).
  void setReach(const Bounds& reach) { mReach = reach; }
  /// @brief From the next frame on, follow the instances of @a scene (a cascade level's scene cut again around its
  ///        scrolled box; it must outlive this object). The previous frame's time stays: the next boxes are those
  ///        @a scene's instances swept since it.
  void setScene(const Scene& scene);
  /// @brief The last frame's boxes (advance()).
  const std::vector<gpu::shared::MovedBox>& lastBoxes() const { return mLast; }
  const gpu::Buffer& buffer() const { return mBuffer; }

private:
  const Scene* mScene;
  std::vector<Bounds> mMeshBounds; ///< per mesh, in its own space
  Bounds mReach;                   ///< world space (empty: every motion counts)
  double mPreviousTime = 0.0;
  std::vector<gpu::shared::MovedBox> mLast;
  gpu::Buffer mBuffer;
};

} // namespace rtsdf
