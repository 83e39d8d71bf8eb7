#pragma once
/// @file GridShift.h
/// @brief Moving a grid's buffer by whole cells on the GPU (a cascade level that scrolled keeps what it knows):
///        GridShiftPass (one dispatch, the entered cells filled), the copies and fills that do the same
///        (gridShiftPlan, pure: the pass's host reference through applyGridShift) and the recording of a plan through a
///        scratch buffer (recordGridShift: the loose plan's one copy).
#include "gpu/ComputePass.h"
#include "gpu/Profiler.h"
#include "gpu/Resources.h"
#include "grid/GridSpec.h"
#include "sdf/pipeline/GridShiftParams.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

namespace rtsdf {

/// @brief The transfers that shift a dense grid buffer (x fastest) of @a dims cells of @a elementBytes bytes by
///        @a shift cells: cell v afterwards holds what cell v + shift held before where that lies in the grid (a
///        copy from the scratch holding the old buffer), else the fill value (the cells that entered). Adjacent
///        copies and fills are merged, so a shift along z alone is one copy and one fill.
struct GridShiftPlan {
  struct Fill {
    VkDeviceSize offset = 0, size = 0;
  };
  std::vector<VkBufferCopy> copies; ///< from the scratch (the old buffer) into the buffer
  std::vector<Fill> fills;          ///< the entered cells
  VkDeviceSize bytes = 0;           ///< the whole buffer
};

/// @brief The plan for @a dims, @a elementBytes (a multiple of 4) and @a shift.
/// @throw Error when @a elementBytes is not a positive multiple of 4 or @a dims is not positive.
GridShiftPlan gridShiftPlan(const glm::ivec3& dims, std::uint32_t elementBytes, const glm::ivec3& shift);

/// @brief The same for a buffer whose entered cells may hold anything afterwards (the next frame writes them all):
///        one copy, of every byte a kept cell reads, moved by the shift's offset in cells (x fastest), and no fills.
///        A kept cell lies as many cells from its source as any other, so one range moves them all; the entered
///        cells receive their neighbours' rows. One region instead of a row each: a shift along x of a fine grid
///        would take 128^2 to 256^2 of them.
GridShiftPlan gridShiftPlanLoose(const glm::ivec3& dims, std::uint32_t elementBytes, const glm::ivec3& shift);

/// @brief The coarse voxels by which the (coarse, fine) grids @a to lie from @a from, when a pipeline can scroll from
///        one to the other keeping its buffers: the same counts and voxel sizes, a whole number of fine voxels per
///        coarse voxel (the same corner), the corner moved by whole coarse voxels that are whole bricks of the fine
///        grid, and by less than the grid along every axis. None otherwise (the pipeline is built anew).
std::optional<glm::ivec3> scrollShift(const std::pair<GridSpec, GridSpec>& from, const std::pair<GridSpec, GridSpec>& to);

/// @brief The plan applied to host memory: what recordGridShift leaves in the buffer (the tests' reference).
void applyGridShift(const GridShiftPlan& plan, std::vector<std::uint32_t>& words, std::uint32_t fillWord);

/// @brief GridShiftPass (grid_shift.comp): a dense grid moved by whole cells, cell v afterwards holding what cell
///        v + shift held where that lies in the grid, else the fill word (the cells that entered), in one dispatch.
///        The source is the old grid's copy: it must not alias the target.
class GridShiftPass : gpu::ComputePass {
public:
  static constexpr const char* kName = "GridShiftPass";
  struct Inputs { const gpu::Buffer& source; };
  struct Outputs { const gpu::Buffer& target; };
  using Params = gpu::shared::GridShiftParams;
  explicit GridShiftPass(const gpu::VulkanContext& ctx)
      : ComputePass(ctx, "grid_shift.comp", gpu::shared::kGridShiftBindingCount, sizeof(Params)) {}
  /// @throw Error when a buffer is smaller than the grid.
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;
};

/// @brief GridShiftPass's parameters for a grid of @a dims cells of @a elementBytes bytes (a multiple of 4) moved by
///        @a shift, entered cells set to @a fillWord.
/// @throw Error when @a elementBytes is not a positive multiple of 4 or @a dims is not positive.
gpu::shared::GridShiftParams gridShiftParams(const glm::ivec3& dims, std::uint32_t elementBytes,
                                              const glm::ivec3& shift, std::uint32_t fillWord);

/// @brief Record the shift of @a buffer by @a params through @a scratch: the buffer copied into the scratch, then
///        @a pass from the scratch back into the buffer, each after a barrier (the scratch may have served another
///        shift just before), and a barrier after (later passes and transfers see the shifted buffer).
/// @throw Error when @a scratch or @a buffer is smaller than the grid.
void recordGridShift(VkCommandBuffer cmd, const GridShiftPass& pass, const gpu::Buffer& buffer,
                     const gpu::Buffer& scratch, const gpu::shared::GridShiftParams& params);

/// @brief Record the shift of @a buffer, a grid of @a dims cells of @a elementBytes bytes, by @a shift through
///        @a scratch, the entered cells set to @a fillWord: by @a pass where given (a GPU), else by gridShiftPlan's
///        copies and fills (a CPU device, where they are memcpy calls: lavapipe scrolled the 1000 m town's levels at M
///        in 61-124 ms a frame so against 122-220 ms with the dispatch; an H200 spent 35 ms a level on the transfers).
/// @throw Error as gridShiftParams and when @a scratch or @a buffer is smaller than the grid.
void recordGridShift(VkCommandBuffer cmd, const GridShiftPass* pass, const gpu::Buffer& buffer,
                     const gpu::Buffer& scratch, const glm::ivec3& dims, std::uint32_t elementBytes,
                     const glm::ivec3& shift, std::uint32_t fillWord);

/// @brief Record @a plan on @a buffer: the buffer copied into @a scratch, then the plan's copies back and its fills
///        with @a fillWord, each step after a barrier (the scratch may have served another shift just before), and a
///        barrier after (computeBarrier: later passes and transfers see the shifted buffer).
/// @throw Error when @a scratch is smaller than the buffer.
void recordGridShift(VkCommandBuffer cmd, const gpu::Buffer& buffer, const gpu::Buffer& scratch,
                     const GridShiftPlan& plan, std::uint32_t fillWord);

} // namespace rtsdf
