#pragma once
/// @file PipelineMemory.h
/// @brief What an SdfPipeline would allocate, estimated before anything is (PipelineMemory,
///        estimatePipelineMemory), the limits of a device and host (MemoryLimits, memoryLimits), and the check
///        that refuses an estimate beyond them (checkPipelineMemory). Owns no state.
#include "gpu/VulkanContext.h"
#include "grid/GridSpec.h"
#include "scene/Scene.h"
#include "sdf/PipelineSettings.h"
#include "util/Bounds.h"

#include <cstdint>
#include <string>
#include <utility>

namespace rtsdf {

/// @brief What SdfPipeline would allocate for some settings and bounds, computed without allocating.
///
/// Device buffers: per coarse voxel 24 bytes (seeds, jump-flood scratch, coarse SDF, the refinement state, the list
/// of voxels to refine: the GPU appends to it, so it is sized for every voxel); per brick 8 bytes (stamp, slot);
/// per fine voxel 4 bytes with FineStorage::Dense (the dense fine SDF); the scene (SceneGpuSize): 188 bytes per mesh
/// triangle (the bottom levels), 52 per instance triangle (placed corners, VoxelizePass's list of large triangles),
/// 284 per instance (the top level, its transforms, its closed pieces). Not counted: the brick pool (8 bytes per fine voxel of a brick under
/// the band: values and sign votes), which the first frame sizes from the band and checks against the same
/// limits (SdfPipeline::poolBricks()). Host memory at its peak, when the results are read back (a frame itself
/// reads back a few words): per coarse voxel 25 bytes (coarseField() and its staging copy; rayMask()'s copy of
/// the coarse SDF, its staging copy, its copy in voxel units for tiny scenes and the OpenVDB mirror), per fine voxel 16 bytes (rayMask()'s list and fineField(),
/// each with its staging copy).
struct PipelineMemory {
  GridSpec coarse, fine;          ///< the grids (pipelineGrids)
  std::uint64_t largestBuffer = 0;///< bytes of the largest single storage buffer
  std::string largestBufferName;  ///< which one ("fine SDF" or "coarse refinement state")
  std::uint64_t deviceBytes = 0;  ///< every device buffer together
  std::uint64_t hostBytes = 0;    ///< host copies and staging buffers (peak of one frame)
  std::string describe() const;
};

/// @brief What of a scene a pipeline holds on the device: each mesh's triangles once (the BVH's bottom levels, shared by
///        its instances), every instance's triangles placed in the grid's frame (VoxelizePass), and per instance
///        its top-level entries.
struct SceneGpuSize {
  std::uint64_t meshTriangles = 0, instanceTriangles = 0, instances = 0;
};

/// @brief The counts of @a scene's meshes that some instance places (SceneGpuSize).
SceneGpuSize sceneGpuSize(const Scene& scene);

/// @brief Estimate the memory of a pipeline (see PipelineMemory) on @a scene's geometry.
/// @throw Error as pipelineGrids does.
PipelineMemory estimatePipelineMemory(const Bounds& bounds, const PipelineSettings& s, const SceneGpuSize& scene = {});

/// @brief Estimate the memory of a pipeline on the given (coarse, fine) @a grids (a cascade level's).
PipelineMemory estimatePipelineMemory(const std::pair<GridSpec, GridSpec>& grids, const PipelineSettings& s,
                                      const SceneGpuSize& scene = {});

/// @brief The scratch buffer a scroll of a pipeline on the grids @a coarse and @a fine needs (SdfPipeline::scroll): the
///        largest buffer it shifts through it, of the dense fine SDF (with FineStorage::Dense), the coarse refinement
///        state (8 bytes per coarse voxel) and the bricks' stamps or slots (4 bytes per brick).
std::uint64_t scrollScratchBytesFor(const GridSpec& coarse, const GridSpec& fine, FineStorage storage);

/// @brief Limits an estimate is checked against.
struct MemoryLimits {
  std::uint64_t maxStorageBufferRange = 0; ///< largest storage buffer (VkPhysicalDeviceLimits)
  std::uint64_t deviceBytes = 0;           ///< the largest device-local heap; 0: unknown (not checked)
  std::uint64_t hostBytes = 0;             ///< host memory available (MemAvailable); 0: unknown (not checked)
  bool unifiedMemory = false;              ///< device memory is host memory (a CPU device such as lavapipe)
  std::string deviceName;
};

/// @brief The limits of @a device on this machine: its buffer range and heap, and /proc/meminfo's
///        MemAvailable (0 where unknown).
MemoryLimits memoryLimits(const gpu::DeviceInfo& device);

/// @brief Refuse an estimate that does not fit: the largest buffer against maxStorageBufferRange, the
///        device buffers against the device heap, host copies (plus device buffers on a unified-memory
///        device) against the host memory available.
/// @throw SettingError stating the grid, the bytes needed, the limit, and the setting to lower (the fine or
///        the coarse resolution).
void checkPipelineMemory(const PipelineMemory& need, const MemoryLimits& limits);

/// @brief @a bytes in MiB with one decimal ("12.5 MiB"), as the memory errors state them.
std::string formatMiB(std::uint64_t bytes);

} // namespace rtsdf
