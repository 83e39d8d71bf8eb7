#pragma once
/// @file SingleBoxCheck.h
/// @brief Whether one box fitted to the whole scene is too coarse for it (singleBoxAdvice): the case cascades are for.
#include "grid/GridSpec.h"
#include "scene/Scene.h"

#include <string>

namespace rtsdf {

/// @brief What makes one box too coarse, measured on a scene and its grids.
struct SingleBoxFit {
  double typicalFeature = 0.0;  ///< the median over instances of their box's thinnest side (world units)
  double fineVoxel = 0.0;
  int coarseVoxelsAcross = 0;   ///< the coarse grid's voxels along its shortest axis
  int coarseVoxelsAlong = 0;    ///< the coarse grid's voxels along its longest axis
  /// @brief The fine voxel over the typical feature.
  double fineOverFeature() const { return typicalFeature > 0.0 ? fineVoxel / typicalFeature : 0.0; }
};

/// @brief The fine voxel may be at most this fraction of a typical feature (a wall, a table top).
constexpr double kMaxFineOverFeature = 0.25;
/// @brief The coarse grid needs at least this many voxels along its shortest axis where its longest has 4 times as
///        many (a flat world: a deliberately tiny grid is not warned about).
constexpr int kMinCoarseVoxelsAcross = 8;

/// @brief The fit of @a scene (at time 0) in the grids @a coarse and @a fine.
SingleBoxFit singleBoxFit(const Scene& scene, const GridSpec& coarse, const GridSpec& fine);

/// @brief "" when one box suits @a scene; else one line saying why it is too coarse (a fine voxel over
///        kMaxFineOverFeature of the typical feature, or fewer than kMinCoarseVoxelsAcross coarse voxels along an
///        axis of a flat grid) and naming the cascades (--cascades), which keep the voxels near the camera fine in any
///        world.
std::string singleBoxAdvice(const Scene& scene, const GridSpec& coarse, const GridSpec& fine);

} // namespace rtsdf
