#include "sdf/RefinePasses.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace rtsdf {
using namespace gpu::shared;

RefineParams refineGridParams(const GridSpec& coarse, const GridSpec& fine) {
  RefineParams p{};
  p.fineOriginH = glm::vec4(glm::vec3(fine.origin), float(fine.voxelSize));
  p.fineDims = glm::ivec4(fine.dims, 0);
  p.coarseOriginInvH = glm::vec4(glm::vec3(coarse.origin), float(1.0 / coarse.voxelSize));
  p.coarseDims = glm::ivec4(coarse.dims, 0);
  return p;
}

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

const char* ClosestRefinePass::shaderFor(const Variant& v) {
  static const char* const kShaders[8] = {"refine_closest_side.comp",          "refine_closest.comp",
                                          "refine_closest_cell_side.comp",     "refine_closest_cell.comp",
                                          "refine_closest_side_cpu.comp",      "refine_closest_cpu.comp",
                                          "refine_closest_cell_side_cpu.comp", "refine_closest_cell_cpu.comp"};
  return kShaders[(v.signRays ? 1 : 0) + (v.cellSearch ? 2 : 0) + (v.cpu ? 4 : 0)];
}

RefineParts refinePartsFor(const glm::ivec3& longestRuns, bool cellSearch) {
  RefineParts parts;
  if (!cellSearch) {
    parts.box = glm::ivec3(1, 1, longestRuns.z);
    parts.count = glm::ivec3(longestRuns.x, longestRuns.y, 1);
    return parts;
  }
  for (int a = 0; a < 3; ++a) {
    parts.count[a] = (longestRuns[a] + RTSDF_CELL_BOX - 1) / RTSDF_CELL_BOX;
    parts.box[a] = (longestRuns[a] + parts.count[a] - 1) / parts.count[a];
  }
  return parts;
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
  b[kMaskBindingCoarseList] = &out.coarseList;
  b[kMaskBindingCoarseState] = &out.coarseState;
  b[kMaskBindingMovedBoxes] = &in.movedBoxes;
  const glm::ivec3 d = params.coarseDims;
  mPipeline.dispatch(cmd, b, &params,
                     {gpu::groupsFor(d.x, RTSDF_MASK_GROUP), gpu::groupsFor(d.y, RTSDF_MASK_GROUP),
                      gpu::groupsFor(d.z, RTSDF_MASK_GROUP)});
  gpu::computeBarrier(cmd);
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

namespace {
static_assert(RTSDF_BRICK_PAGES == 4, "brick_pool.glsl declares four pages");
template <std::size_t N> void bindPages(std::array<gpu::Binding, N>& b, std::uint32_t first,
                                        const gpu::Buffer* const (&pages)[RTSDF_BRICK_PAGES]) {
  for (std::uint32_t k = 0; k < RTSDF_BRICK_PAGES; ++k) b[first + k] = pages[k];
}
} // namespace

void UpsamplePass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                           const Params& params) const {
  gpu::ProfileScope scope(profiler, cmd, kName);
  std::array<gpu::Binding, kUpsampleBindingCount> b;
  b[kUpsampleBindingCoarse] = &in.coarse;
  b[kUpsampleBindingFine] = &out.fine;
  b[kUpsampleBindingFineToCoarse] = &in.fineToCoarse;
  b[kUpsampleBindingBrickSlots] = &in.brickSlots;
  const glm::ivec3 d = params.fineDims;
  mPipeline.dispatch(cmd, b, &params,
                     {gpu::groupsFor(d.x, RTSDF_UPSAMPLE_GROUP_X), gpu::groupsFor(d.y, RTSDF_UPSAMPLE_GROUP_Y),
                      gpu::groupsFor(d.z, std::uint32_t(mRun))});
  gpu::computeBarrier(cmd);
}

void RefinePass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                         const Params& params) const {
  gpu::ProfileScope scope(profiler, cmd, mName);
  std::array<gpu::Binding, kRefineBindingCount> b;
  in.bvh.bindTo(b);
  b[kRefineBindingRefineList] = &in.refineList;
  b[kRefineBindingMaskCounts] = &in.counts;
  b[kRefineBindingCoarse] = &in.coarse;
  b[kRefineBindingFineRanges] = &in.fineRanges;
  b[kRefineBindingBrickSlots] = &in.brickSlots;
  b[kRefineBindingDense] = &out.dense;
  bindPages(b, kRefineBindingValuePages, out.pool.values);
  bindPages(b, kRefineBindingVotePages, out.pool.votes);
  mPipeline.dispatchIndirect(cmd, b, &params, in.counts);
  gpu::computeBarrier(cmd);
}

} // namespace rtsdf
