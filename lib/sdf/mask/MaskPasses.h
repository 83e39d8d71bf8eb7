#pragma once
/// @file MaskPasses.h
/// @brief The ray mask and the brick pool on the GPU: MaskCompactPass (the coarse voxels within the band and the
///        fine voxels under them), MaskDispatchPass (the refinement's indirect dispatch), BrickAllocPass (the pool's
///        slots), and the per-axis tables that map the two grids onto each other. Same shape as every pass:
///        execute(cmd, profiler, inputs, outputs, params), bindings named in sdf/mask/MaskParams.h; the CPU copies
///        are MaskCpu.h.
#include "gpu/ComputePass.h"
#include "gpu/Profiler.h"
#include "gpu/Resources.h"
#include "grid/GridSpec.h"
#include "sdf/mask/MaskParams.h"

#include <vector>

namespace rtsdf {

/// @brief The fine voxels under each coarse slab, per axis: entry a-offset + i (x entries, then y, then z) is the
///        range [lo, hi] of fine indices j along axis a whose centres lie in coarse voxel i, i <= (j + 0.5) / ratio
///        < i + 1, clamped to the fine grid (lo > hi: none, where the coarse grid overhangs the fine one). The
///        grids share their corner (coarseGridOver). The CPU mirror (buildRayMask) and MaskCompactPass use these
///        very tables, so both give the same fine voxels.
std::vector<glm::ivec2> maskFineRanges(const GridSpec& coarse, const GridSpec& fine);

/// @brief Append the fine voxels under coarse voxel @a c (maskFineRanges @a ranges of a coarse grid of @a coarseDims),
///        packed x | y << 10 | z << 20, each or-ed with @a flags.
void appendFineVoxelsUnder(const std::vector<glm::ivec2>& ranges, const glm::ivec3& coarseDims, const glm::ivec3& c,
                           std::uint32_t flags, std::vector<std::uint32_t>& out);

/// @brief The inverse of maskFineRanges: entry a-offset + j (x entries, then y, then z) is the coarse index along
///        axis a whose slab holds fine index j (-1 where none does). UpsamplePass finds the ray mask's voxels with it.
std::vector<int> maskCoarseOfFine(const GridSpec& coarse, const GridSpec& fine);

/// @brief The longest run of fine voxels under one coarse voxel along each axis (maskFineRanges of the grids).
glm::ivec3 longestFineRuns(const GridSpec& coarse, const GridSpec& fine);

/// @brief MaskCompactPass (mask_compact.comp): the ray mask on the GPU, over the coarse voxels of the MaskRegion
///        (MaskRegionPass; dispatched indirectly from it). Counts every coarse voxel with |c| <= d in the bricks
///        holding the fine voxels under it (gpu::shared::brickBandDelta) and, when they are to be refined this frame
///        (gpu::shared::refinesThisFrame, which advances the voxel's state), appends the voxel (kMaskFineFresh when new
///        to the band) to the refine list, in no order; counts the list, the fine voxels refined, and the band's coarse
///        and fine voxels in the counts buffer (sdf/mask/MaskParams.h's kMaskCount* words, which must be zero before,
///        but for the band's two with kMaskRegionOnly: the last run's, changed by what it visits; so the bricks'
///        counts, zero before a run over every voxel), and grows the box of the voxels it leaves settling.
class MaskCompactPass : gpu::ComputePass {
public:
  static constexpr const char* kName = "MaskCompactPass";
  struct Inputs {
    const gpu::Buffer& coarse;     ///< c_t, dense, x fastest
    const gpu::Buffer& fineRanges; ///< maskFineRanges() of the two grids
    const gpu::Buffer& movedBoxes; ///< MovedBox per instance that moved (params.movedBoxes of them)
    const gpu::Buffer& changedBox; ///< the coarse SDF's ChangedBox (read with kMaskCoarseRebuilt in params)
    /// With kMaskBlockList in params: the coarse blocks to visit (UpsampleBlocksPass's list: its dispatch at offset
    /// 0, a work group a block) instead of the MaskRegion's box.
    const gpu::Buffer* blockList = nullptr;
  };
  /// @a coarseState: (the run that last visited it in the band or kNotInBand, refinements in a row) per coarse voxel,
  /// read and advanced; @a brickNeeded: per brick, the band voxels in view over it; @a region: the MaskRegion.
  struct Outputs { const gpu::Buffer &counts, &refineList, &coarseState, &brickNeeded, &region; };
  using Params = gpu::shared::MaskParams; ///< refineCapacity: entries the refine list holds
  explicit MaskCompactPass(const gpu::VulkanContext& ctx)
      : ComputePass(ctx, "mask_compact.comp", gpu::shared::kMaskBindingCount, sizeof(Params)),
        mBlocks(ctx, "mask_compact_blocks.comp", gpu::shared::kMaskBindingCount, sizeof(Params)) {}
  /// @throw Error with kMaskBlockList in params and no Inputs::blockList.
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;

private:
  gpu::ComputePipeline mBlocks; ///< the variant over listed blocks (kMaskBlockList)
};

/// @brief MaskLeavePass (mask_leave.comp): before a scroll shifts the coarse refinement state, the band's two counts
///        (kMaskCountCoarse, kMaskCountMaskedFine) lose the band voxels that leave the grid, so that a run over what
///        changed after it (kMaskRegionOnly) counts from those that stayed.
class MaskLeavePass : gpu::ComputePass {
public:
  static constexpr const char* kName = "MaskLeavePass";
  struct Inputs { const gpu::Buffer &coarseState, &fineRanges; }; ///< the state before the shift
  struct Outputs { const gpu::Buffer& counts; };
  using Params = gpu::shared::MaskLeaveParams; ///< the coarse dims, the shift (voxel v takes v + shift's)
  explicit MaskLeavePass(const gpu::VulkanContext& ctx)
      : ComputePass(ctx, "mask_leave.comp", gpu::shared::kMaskLeaveBindingCount, sizeof(Params)) {}
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;
};

/// @brief MaskRegionPass (mask_region.comp): one invocation writes the MaskRegion of a run of MaskCompactPass (every
///        voxel, or with kMaskRegionOnly in params.dims.w the box of the coarse SDF's ChangedBox where
///        kMaskCoarseRebuilt, the voxels near a moving box and the last run's settling box) and its dispatch, and
///        resets this run's settling box.
class MaskRegionPass : gpu::ComputePass {
public:
  static constexpr const char* kName = "MaskRegionPass";
  struct Inputs { const gpu::Buffer& changedBox; };
  struct Outputs { const gpu::Buffer& region; };
  using Params = gpu::shared::MaskRegionParams;
  explicit MaskRegionPass(const gpu::VulkanContext& ctx)
      : ComputePass(ctx, "mask_region.comp", gpu::shared::kMaskRegionBindingCount, sizeof(Params)) {}
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;
};

/// @brief MaskDispatchPass (mask_dispatch.comp): one invocation writes the refinement's indirect dispatch
///        (gpu::shared::refineDispatch of params.brickDims.w invocations per coarse voxel of the refine list), at
///        offset 0 of the counts buffer, which therefore needs VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT.
class MaskDispatchPass : gpu::ComputePass {
public:
  static constexpr const char* kName = "MaskDispatchPass";
  struct Inputs {};
  struct Outputs { const gpu::Buffer& counts; };
  using Params = gpu::shared::MaskParams;
  explicit MaskDispatchPass(const gpu::VulkanContext& ctx)
      : ComputePass(ctx, "mask_dispatch.comp", 1, sizeof(Params)) {}
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;
};

/// @brief BrickAllocPass (brick_alloc.comp): the brick pool's slots follow the ray mask on the GPU. A brick that
///        MaskCompactPass counts a band voxel in view in keeps its slot or takes one off the free stack; a brick
///        without gives its slot back. Slots are assigned in no particular order; a needed brick finds none only when
///        the stack is empty (kBrickCountOverflow counts those). The counts' per-frame words
///        (kBrickCountActive, kBrickCountAllocated, kBrickCountOverflow) must be zero before.
class BrickAllocPass : gpu::ComputePass {
public:
  static constexpr const char* kName = "BrickAllocPass";
  struct Inputs { const gpu::Buffer& needed; };  ///< per brick: the band voxels in view over it (0: not needed)
  /// kBrickCount* words; per brick its slot (kNoBrick: none); the free stack (kBrickCountFreeTop entries).
  struct Outputs { const gpu::Buffer &counts, &slots, &freeStack; };
  using Params = gpu::shared::BrickParams;       ///< bricks (phase: set by execute)
  explicit BrickAllocPass(const gpu::VulkanContext& ctx)
      : ComputePass(ctx, "brick_alloc.comp", gpu::shared::kBrickBindingCount, sizeof(Params)) {}
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;
};

/// @brief The brick pool's storage: RTSDF_BRICK_PAGES pages of values (float) and of sign votes (two halves),
///        each of pageBricks bricks; pages beyond the pool's capacity are bound to a small placeholder.
struct BrickPages {
  const gpu::Buffer* values[RTSDF_BRICK_PAGES];
  const gpu::Buffer* votes[RTSDF_BRICK_PAGES];
};

} // namespace rtsdf
