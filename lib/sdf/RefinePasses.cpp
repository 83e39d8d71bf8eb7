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
  b[kMaskBindingFineList] = &out.fineList;
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
                               const Params&) const {
  gpu::ProfileScope scope(profiler, cmd, kName);
  mPipeline.dispatch(cmd, {&out.counts}, nullptr, {1, 1, 1});
  gpu::computeBarrier(cmd);
}

void UpsamplePass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                           const Params& params) const {
  gpu::ProfileScope scope(profiler, cmd, kName);
  std::array<gpu::Binding, kUpsampleBindingCount> b;
  b[kUpsampleBindingCoarse] = &in.coarse;
  b[kUpsampleBindingFine] = &out.fine;
  b[kUpsampleBindingFineToCoarse] = &in.fineToCoarse;
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
  b[kRefineBindingMask] = &in.mask;
  b[kRefineBindingFine] = &out.fine;
  b[kRefineBindingVotes] = &out.votes;
  b[kRefineBindingMaskCounts] = &in.counts;
  b[kRefineBindingCoarse] = &in.coarse;
  mPipeline.dispatchIndirect(cmd, b, &params, in.counts);
  gpu::computeBarrier(cmd);
}

} // namespace rtsdf
