#pragma once
/// @file CascadeSamplerCpu.h
/// @brief The rule by which shading samples cascade levels, on the CPU: the finest level holding a point, blended
///        into the next coarser level across a band at the finer level's border, so no seam appears where the levels
///        meet. The SDF march on the GPU does not sample levels yet; this is the reference it is to match.
#include "sdf/cascade/CascadeLayout.h"

#include <glm/glm.hpp>

#include <vector>

namespace rtsdf {

/// @brief Samples a field given per level (dense, on each level's fine grid, x fastest) at world points.
class CascadeSamplerCpu {
public:
  /// @param layout the levels
  /// @param fields one dense field per level, on its fine grid
  /// @param blendVoxels the width of the band at a level's border over which it fades into the next coarser level,
  ///        in that level's fine voxels (0: a hard switch, with the seam that makes)
  /// @throw Error when a field's size is not its level's fine voxel count or blendVoxels is negative.
  CascadeSamplerCpu(CascadeLayout layout, std::vector<std::vector<float>> fields, double blendVoxels);
  /// @brief The field at @a p: trilinear in the finest level whose box holds @a p more than one fine voxel inside its
  ///        faces (so the whole stencil lies in it); within blendVoxels of that margin, mixed linearly with the next
  ///        coarser level (weight 0 on the margin itself); the outermost level, clamped, beyond every level.
  float sample(const glm::dvec3& p) const;
  /// @brief Trilinear value of level @a level's field at @a p (clamped to its grid).
  float sampleLevel(int level, const glm::dvec3& p) const;
  /// @brief How far inside level @a level's faces @a p is (negative outside), in world units.
  double insideDistance(int level, const glm::dvec3& p) const;

private:
  CascadeLayout mLayout;
  std::vector<std::vector<float>> mFields;
  double mBlendVoxels;
};

} // namespace rtsdf
