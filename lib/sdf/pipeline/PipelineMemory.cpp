#include "sdf/pipeline/PipelineMemory.h"

#include "sdf/coarse/CoarseParams.h"
#include "sdf/pipeline/BrickPool.h"
#include "sdf/pipeline/FramePlan.h"
#include "sdf/refine/RefineParams.h"
#include "util/Error.h"
#include "util/Memory.h"

#include <fmt/format.h>

#include <algorithm>
#include <tuple>

namespace rtsdf {

std::string formatMiB(std::uint64_t bytes) { return fmt::format("{:.1f} MiB", double(bytes) / (1024.0 * 1024.0)); }

std::string PipelineMemory::describe() const {
  return fmt::format("coarse {}x{}x{}, fine {}x{}x{}: largest buffer '{}' {}, device {}, host {}", coarse.dims.x,
                     coarse.dims.y, coarse.dims.z, fine.dims.x, fine.dims.y, fine.dims.z, largestBufferName,
                     formatMiB(largestBuffer), formatMiB(deviceBytes), formatMiB(hostBytes));
}

SceneGpuSize sceneGpuSize(const Scene& scene) {
  SceneGpuSize n;
  std::vector<bool> placed(scene.meshes.size(), false);
  for (const Instance& inst : scene.instances) {
    const std::uint64_t triangles = scene.meshes.at(inst.mesh).triangles.size();
    n.instanceTriangles += triangles;
    ++n.instances;
    if (!placed[inst.mesh]) n.meshTriangles += triangles;
    placed[inst.mesh] = true;
  }
  return n;
}

PipelineMemory estimatePipelineMemory(const Bounds& bounds, const PipelineSettings& s, const SceneGpuSize& scene) {
  return estimatePipelineMemory(pipelineGrids(bounds, s), s, scene);
}

PipelineMemory estimatePipelineMemory(const std::pair<GridSpec, GridSpec>& grids, const PipelineSettings& s,
                                      const SceneGpuSize& scene) {
  PipelineMemory m;
  std::tie(m.coarse, m.fine) = grids;
  const std::uint64_t nc = m.coarse.voxelCount(), nf = m.fine.voxelCount();
  const bool dense = s.fineStorage == FineStorage::Dense;
  const std::uint64_t coarseBuf = nc * 4, fineBuf = dense ? nf * 4 : 0;
  if (fineBuf >= 2 * coarseBuf) { m.largestBuffer = fineBuf; m.largestBufferName = "fine SDF"; }
  else { m.largestBuffer = 2 * coarseBuf; m.largestBufferName = "coarse refinement state"; }
  const glm::uvec3 bricks(brickDimsOf(m.fine));
  // Seeds A/B, the coarse SDF, the refinement state (8 bytes per voxel) and the refine list; the dense fine SDF; per brick its stamp and slot. The scene: per mesh triangle its bottom level
  // (nodes of 32 bytes and as many winding dipoles, at most two of each per triangle; corners 48 bytes; id, closed
  // piece and open-mesh flags 4 bytes each); per instance triangle its corners placed by VoxelizePass (48 bytes) and
  // a place in its list of large triangles (4); per instance two top-level nodes (64), its slot (4), its transforms
  // for the BVH (112) and for VoxelizePass (64), its triangle range (8) and a closed piece in the overlap list (32).
  // Closest mode: the list of voxels for the exact winding number (1 MiB).
  const std::uint64_t nearHalfList =
      s.mode == RefineMode::Closest ? (1 + std::uint64_t(gpu::shared::kWindingExactCapacity)) * 16 : 0;
  // A pipeline that builds the coarse SDF over what changed keeps the transform's planes and nearest seeds; every
  // one keeps a bound per block of 64 coarse voxels, and the lists of a region (a word per block, two per column).
  const std::uint64_t keptTransform = coarseBuiltOverChanges(s) ? 2 * coarseBuf : 0;
  const std::uint64_t regionLists = std::uint64_t(gpu::shared::coarseRegionListWords(glm::ivec3(m.coarse.dims))) * 4;
  // Per block a mark of its changed voxels, and with a dense fine SDF the list of the blocks to upsample and their
  // fine voxels' table (UpsampleBlocksPass).
  const glm::ivec3 coarseDims(m.coarse.dims);
  const std::uint64_t upsampleBlocks =
      fineBuf ? (gpu::shared::kUpsampleBlockListHeaderWords + coarseBuf / 256 +
                 gpu::shared::upsampleBlockFineBeginWords(coarseDims)) * 4
              : 0;
  // The mask's own list of blocks (a run over what changed after a scroll) and their coarse voxels' table.
  const std::uint64_t maskBlocks = s.band > 0.0 ? (gpu::shared::kUpsampleBlockListHeaderWords + coarseBuf / 256 +
                                                   gpu::shared::upsampleBlockFineBeginWords(coarseDims)) * 4
                                                : 0;
  m.deviceBytes = 6 * coarseBuf + keptTransform + 2 * (coarseBuf / 64) + regionLists + upsampleBlocks + maskBlocks +
                  fineBuf +
                  std::uint64_t(bricks.x) * bricks.y * bricks.z * 8 +
                  scene.meshTriangles * (64 + 64 + 48 + 3 * 4) + scene.instanceTriangles * (48 + 4) +
                  scene.instances * (64 + 4 + 112 + 64 + 8 + 32) + nearHalfList + 4096;
  // Read-backs with their staging copies: the coarse SDF (coarseField(), and again for rayMask()), rayMask()'s copy
  // of it in voxel units (tiny scenes) and its OpenVDB mirror (4 bytes and a mask bit at worst); the fine mask list
  // and the fine SDF.
  m.hostBytes = nc * 25 + nf * 16;
  return m;
}

std::uint64_t scrollScratchBytesFor(const GridSpec& coarse, const GridSpec& fine, FineStorage storage) {
  const glm::u64vec3 bricks(brickDimsOf(fine));
  const std::uint64_t dense = storage == FineStorage::Dense ? fine.voxelCount() * 4 : 0;
  return std::max<std::uint64_t>({dense, coarse.voxelCount() * 8, bricks.x * bricks.y * bricks.z * 4});
}

MemoryLimits memoryLimits(const gpu::DeviceInfo& device) {
  MemoryLimits l;
  l.maxStorageBufferRange = device.maxStorageBufferRange;
  l.deviceBytes = device.deviceLocalBytes;
  l.hostBytes = availableHostMemory();
  l.unifiedMemory = device.type == VK_PHYSICAL_DEVICE_TYPE_CPU;
  l.deviceName = device.name;
  return l;
}

void checkPipelineMemory(const PipelineMemory& need, const MemoryLimits& limits) {
  const std::string grids = fmt::format("coarse grid {}x{}x{}, fine grid {}x{}x{}", need.coarse.dims.x,
                                        need.coarse.dims.y, need.coarse.dims.z, need.fine.dims.x, need.fine.dims.y,
                                        need.fine.dims.z);
  const bool fine = need.largestBufferName == "fine SDF";
  const char* lower = fine ? "fine resolution" : "coarse resolution";
  if (limits.maxStorageBufferRange && need.largestBuffer > limits.maxStorageBufferRange)
    throw SettingError(lower, fmt::format("SdfPipeline: {}: buffer '{}' needs {}, more than {}'s "
                                          "maxStorageBufferRange of {}: lower the {}{}", grids, need.largestBufferName,
                                          formatMiB(need.largestBuffer), limits.deviceName,
                                          formatMiB(limits.maxStorageBufferRange), lower,
                                          fine ? ", or keep the fine SDF sparse (fine storage 'sparse')" : ""));
  if (limits.deviceBytes && need.deviceBytes > limits.deviceBytes)
    throw SettingError("fine resolution", fmt::format("SdfPipeline: {}: the device buffers need {}, more than {}'s "
                                                      "{} heap: lower the fine (and coarse) resolution", grids,
                                                      formatMiB(need.deviceBytes), limits.deviceName,
                                                      formatMiB(limits.deviceBytes)));
  const std::uint64_t host = need.hostBytes + (limits.unifiedMemory ? need.deviceBytes : 0);
  if (limits.hostBytes && host > limits.hostBytes)
    throw SettingError("fine resolution", fmt::format("SdfPipeline: {}: needs {} of host memory{}, more than the {} "
                                                      "available: lower the fine (and coarse) resolution", grids,
                                                      formatMiB(host), limits.unifiedMemory
                                                                           ? " (device buffers included)" : "",
                                                      formatMiB(limits.hostBytes)));
}

} // namespace rtsdf
