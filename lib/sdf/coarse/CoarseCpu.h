#pragma once
/// @file CoarseCpu.h
/// @brief CPU copies of the coarse-SDF passes: the same voxelization, exact feature transform and jump
///        flooding as the GPU (the same shared functions and rules, so the outputs must be identical), and
///        Felzenszwalb-Huttenlocher's exact distance transform of the same seeds (the independent check).
#include "sdf/coarse/CoarseParams.h"
#include "grid/GridSpec.h"
#include "sdf/coarse/CoarseMethod.h"

#include <cstdint>
#include <optional>
#include <vector>

namespace rtsdf {

/// @brief The grid as the GPU sees it (float origin and 1/h). With @a latticeCell, the triangles are placed in the
///        cells of the lattice of the grid's voxel size whose cell @a latticeCell is the grid's voxel (0,0,0)
///        (CoarseSdfSettings::seedLatticeCell); without, the grid is its own lattice.
gpu::shared::VoxelizeParams voxelizeParams(const GridSpec& spec, std::uint32_t triangleCount,
                                           const std::optional<glm::ivec3>& latticeCell = std::nullopt);

/// @brief The triangles' corners in the instances' frame, each placed as the GPU places it (transformToFrame):
///        the CPU copy of VoxelizePass's input. @a corners: 3 per mesh triangle, in its mesh's space.
std::vector<glm::vec4> placeInstanceCorners(const std::vector<glm::vec4>& corners,
                                            const std::vector<gpu::shared::VoxelizeInstance>& instances);

/// @brief Seeds of the triangles (3 corners each in @a spec's frame, w ignored): kNoSeed or the voxel's packed
///        coordinate, x fastest, on the lattice voxelizeParams() places them in. @note Dims must be at most
///        kMaxSeedAxis per axis.
std::vector<std::uint32_t> voxelizeCpu(const std::vector<glm::vec4>& corners, const GridSpec& spec,
                                       const std::optional<glm::ivec3>& latticeCell = std::nullopt);

/// @brief The copy of SeedShiftPass: @a seeds (or nearest seeds) of a grid of @a dims after it scrolled by @a shift
///        voxels (voxel v takes v + shift's, a seed u becoming u - shift; kNoSeed where v + shift or u - shift lies
///        outside the grid).
std::vector<std::uint32_t> shiftSeedsCpu(const std::vector<std::uint32_t>& seeds, const glm::ivec3& dims,
                                         const glm::ivec3& shift);

/// @brief Jump flooding of @a seeds (TBB): the nearest seed found per voxel, or kNoSeed if there are none.
std::vector<std::uint32_t> jumpFloodCpu(const std::vector<std::uint32_t>& seeds, const glm::ivec3& dims,
                                        CoarseMethod variant);

/// @brief The exact nearest seed of every voxel (kNoSeed if there are none): the CPU copy of ExactEdtPass, the
///        same separable feature transform (Meijster et al.) line by line along x, y, then z (TBB). Ties go to the
///        smaller packed seed. Its distances equal exactEdtSquared()'s.
std::vector<std::uint32_t> exactEdtNearestCpu(const std::vector<std::uint32_t>& seeds, const glm::ivec3& dims);

/// @brief The nearest seeds by @a method: exactEdtNearestCpu() for CoarseMethod::Edt, else jumpFloodCpu().
std::vector<std::uint32_t> nearestSeedsCpu(const std::vector<std::uint32_t>& seeds, const glm::ivec3& dims,
                                           CoarseMethod method);

/// @brief c = |p - nearest| * h - beta, or @a emptyDistance where there is no seed.
std::vector<float> coarseDistanceCpu(const std::vector<std::uint32_t>& nearest, const glm::ivec3& dims,
                                     float voxelSize, float beta, float emptyDistance);

/// @brief Exact squared distance (in voxels^2) from every voxel to its nearest seed, by the separable
///        algorithm of Felzenszwalb and Huttenlocher (TBB); +inf where there are no seeds.
std::vector<float> exactEdtSquared(const std::vector<std::uint32_t>& seeds, const glm::ivec3& dims);

/// @brief How far a jump-flooding result is from the exact transform of the same seeds.
struct JfaAccuracy {
  std::uint64_t voxels = 0;
  std::uint64_t wrong = 0;   ///< voxels whose jump-flooding distance exceeds the exact one
  double maxError = 0.0;     ///< max (jfa - exact) distance, in voxels
  double wrongFraction() const { return voxels ? double(wrong) / double(voxels) : 0.0; }
};
JfaAccuracy compareWithExact(const std::vector<std::uint32_t>& nearest, const std::vector<float>& exactSquared,
                             const glm::ivec3& dims);

} // namespace rtsdf
