#include "sdf/mask/MaskPasses.h"

#include "sdf/coarse/CoarseParams.h"
#include "util/Error.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace rtsdf {
using namespace gpu::shared;

std::vector<glm::ivec2> maskFineRanges(const GridSpec& coarse, const GridSpec& fine) {
  const double ratio = coarse.voxelSize / fine.voxelSize;
  std::vector<glm::ivec2> ranges;
  ranges.reserve(std::size_t(coarse.dims.x) + coarse.dims.y + coarse.dims.z);
  for (int a = 0; a < 3; ++a)
    for (int i = 0; i < coarse.dims[a]; ++i)
      ranges.emplace_back(std::max(0, int(std::ceil(i * ratio - 0.5))),
                          std::min(fine.dims[a] - 1, int(std::ceil((i + 1) * ratio - 0.5)) - 1));
  return ranges;
}

void appendFineVoxelsUnder(const std::vector<glm::ivec2>& ranges, const glm::ivec3& coarseDims, const glm::ivec3& c,
                           std::uint32_t flags, std::vector<std::uint32_t>& out) {
  const glm::ivec2 rx = ranges[c.x], ry = ranges[coarseDims.x + c.y], rz = ranges[coarseDims.x + coarseDims.y + c.z];
  for (int z = rz.x; z <= rz.y; ++z)
    for (int y = ry.x; y <= ry.y; ++y)
      for (int x = rx.x; x <= rx.y; ++x)
        out.push_back(std::uint32_t(x) | (std::uint32_t(y) << 10) | (std::uint32_t(z) << 20) | flags);
}

glm::ivec3 longestFineRuns(const GridSpec& coarse, const GridSpec& fine) {
  const std::vector<glm::ivec2> ranges = maskFineRanges(coarse, fine);
  glm::ivec3 longest(0);
  std::size_t offset = 0;
  for (int a = 0; a < 3; ++a) {
    for (int i = 0; i < coarse.dims[a]; ++i)
      longest[a] = std::max(longest[a], ranges[offset + i].y - ranges[offset + i].x + 1);
    offset += coarse.dims[a];
  }
  return longest;
}

std::vector<int> maskCoarseOfFine(const GridSpec& coarse, const GridSpec& fine) {
  const std::vector<glm::ivec2> ranges = maskFineRanges(coarse, fine);
  std::vector<int> table(std::size_t(fine.dims.x) + fine.dims.y + fine.dims.z, -1);
  std::size_t coarseOffset = 0, fineOffset = 0;
  for (int a = 0; a < 3; ++a) {
    for (int i = 0; i < coarse.dims[a]; ++i)
      for (int j = ranges[coarseOffset + i].x; j <= ranges[coarseOffset + i].y; ++j) table[fineOffset + j] = i;
    coarseOffset += coarse.dims[a];
    fineOffset += fine.dims[a];
  }
  return table;
}

void MaskCompactPass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                              const Params& params) const {
  gpu::ProfileScope scope(profiler, cmd, kName);
  std::array<gpu::Binding, kMaskBindingCount> b;
  b[kMaskBindingCounts] = &out.counts;
  b[kMaskBindingCoarse] = &in.coarse;
  b[kMaskBindingFineRanges] = &in.fineRanges;
  b[kMaskBindingRefineList] = &out.refineList;
  b[kMaskBindingBrickNeeded] = &out.brickNeeded;
  b[kMaskBindingCoarseState] = &out.coarseState;
  b[kMaskBindingMovedBoxes] = &in.movedBoxes;
  b[kMaskBindingChangedBox] = &in.changedBox;
  b[kMaskBindingRegion] = &out.region;
  const bool listed = (params.coarseDims.w & kMaskBlockList) != 0;
  if (listed && !in.blockList)
    throw Error("MaskCompactPass: a run over listed blocks (kMaskBlockList) needs the list");
  b[kMaskBindingBlockList] = in.blockList ? in.blockList : &in.coarse; // unread without kMaskBlockList
  if (listed) mBlocks.dispatchIndirect(cmd, b, &params, *in.blockList);
  else mPipeline.dispatchIndirect(cmd, b, &params, out.region, offsetof(MaskRegion, groups));
  gpu::computeBarrier(cmd);
}

void MaskLeavePass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                            const Params& params) const {
  gpu::ProfileScope scope(profiler, cmd, kName);
  std::array<gpu::Binding, kMaskLeaveBindingCount> b;
  b[kMaskLeaveBindingCounts] = &out.counts;
  b[kMaskLeaveBindingCoarseState] = &in.coarseState;
  b[kMaskLeaveBindingFineRanges] = &in.fineRanges;
  const glm::uvec3 d(params.dims);
  const std::uint32_t groups = gpu::groupsFor(d.x * d.y * d.z, 64);
  mPipeline.dispatch(cmd, b, &params,
                     {std::min(groups, kCoarseRegionGroupsX), gpu::groupsFor(groups, kCoarseRegionGroupsX), 1u});
  gpu::computeBarrier(cmd);
}

void MaskRegionPass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                             const Params& params) const {
  gpu::ProfileScope scope(profiler, cmd, kName);
  std::array<gpu::Binding, kMaskRegionBindingCount> b;
  b[kMaskRegionBindingChangedBox] = &in.changedBox;
  b[kMaskRegionBindingRegion] = &out.region;
  mPipeline.dispatch(cmd, b, &params, {1, 1, 1});
  gpu::computeBarrier(cmd); // read as an indirect command
}

void MaskDispatchPass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs&, const Outputs& out,
                               const Params& params) const {
  gpu::ProfileScope scope(profiler, cmd, kName);
  mPipeline.dispatch(cmd, {&out.counts}, &params, {1, 1, 1});
  gpu::computeBarrier(cmd);
}

void BrickAllocPass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                             const Params& params) const {
  gpu::ProfileScope scope(profiler, cmd, kName);
  std::array<gpu::Binding, kBrickBindingCount> b;
  b[kBrickBindingCounts] = &out.counts;
  b[kBrickBindingNeeded] = &in.needed;
  b[kBrickBindingSlots] = &out.slots;
  b[kBrickBindingFree] = &out.freeStack;
  // Pushes and pops in separate dispatches, each finished before the next reads the stack.
  for (std::uint32_t phase : {RTSDF_BRICK_FREE, RTSDF_BRICK_TAKE, RTSDF_BRICK_SETTLE}) {
    Params p = params;
    p.phase = phase;
    mPipeline.dispatch(cmd, b, &p, {phase == RTSDF_BRICK_SETTLE ? 1u : gpu::groupsFor(p.bricks, RTSDF_BRICK_GROUP),
                                    1, 1});
    gpu::computeBarrier(cmd);
  }
}

} // namespace rtsdf
