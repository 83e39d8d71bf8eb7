#pragma once
/// @file CascadeMemory.h
/// @brief What a CascadeSet would allocate (estimateCascadeMemory): per level a pipeline on the level's grids over
///        the instances near it (levelScene), estimated before anything is allocated. Pure: no GPU.
#include "scene/Scene.h"
#include "sdf/cascade/CascadeLayout.h"
#include "sdf/pipeline/PipelineMemory.h"

#include <cstdint>
#include <string>
#include <vector>

namespace rtsdf {

/// @brief The memory of every level and of all together.
struct CascadeMemory {
  std::vector<PipelineMemory> levels;    ///< per level: its grids and the instance triangles near it
  std::vector<std::uint64_t> triangles;  ///< per level: the triangles of the instances it places (levelScene)
  std::uint64_t scrollScratchBytes = 0;  ///< the scratch the levels share to scroll (0: levels cannot scroll)
  std::uint64_t deviceBytes = 0;         ///< every level's device buffers together, and the scratch
  std::uint64_t hostBytes = 0;           ///< the largest level's host peak (levels are read back one at a time)
  /// @brief All levels as one estimate (the largest buffer of any level, the sums), for checkPipelineMemory.
  PipelineMemory total() const;
  std::string describe() const;
};

/// @brief Level @a level's settings in a cascade under @a s: one box (cascades 1), padding 0 (a level's box is its
///        grid), and the band d 2^level: the same number of voxels in every level's band, as each level's voxel is
///        2^level times level 0's (a band of level 0's width would be under a voxel a few levels up). A band given in
///        voxels is kept in voxels (of each level's own fine grid), which is the same.
PipelineSettings levelSettings(const PipelineSettings& s, int level);

/// @brief The scratch buffer the levels of @a layout share to scroll (SdfPipeline::scrollScratchBytes of a level
///        under @a s; 0 when fine voxels straddle coarse ones and the levels cannot scroll).
std::uint64_t cascadeScrollScratchBytes(const CascadeLayout& layout, const PipelineSettings& s);

/// @brief Estimate the memory of the cascade @a layout over @a scene under @a s (see PipelineMemory for what one
///        level counts). The grids' part is the same for every scene; what grows with the world is only the triangles
///        of the instances near each level.
CascadeMemory estimateCascadeMemory(const Scene& scene, const CascadeLayout& layout, const PipelineSettings& s);

} // namespace rtsdf
