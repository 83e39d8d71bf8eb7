#include "sdf/refine/RefinePasses.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

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

namespace {
static_assert(RTSDF_BRICK_PAGES == 4, "brick_pool.glsl declares four pages");
template <std::size_t N> void bindPages(std::array<gpu::Binding, N>& b, std::uint32_t first,
                                        const gpu::Buffer* const (&pages)[RTSDF_BRICK_PAGES]) {
  for (std::uint32_t k = 0; k < RTSDF_BRICK_PAGES; ++k) b[first + k] = pages[k];
}
} // namespace

UpsamplePass::UpsamplePass(const gpu::VulkanContext& ctx, Kernel kernel)
    : ComputePass(ctx, kernel == Kernel::Runs ? "refine_upsample.comp" : "refine_upsample_voxel.comp",
                  gpu::shared::kUpsampleBindingCount, sizeof(Params)),
      mRun(kernel == Kernel::Runs ? RTSDF_UPSAMPLE_RUN_LENGTH : 1) {
  const UpsampleRegion whole{glm::uvec4(0u), glm::ivec4(0), glm::ivec4(std::numeric_limits<int>::max())};
  gpu::reserveAndUpload(ctx, mWholeGrid, &whole, sizeof(whole), gpu::kStorage, "upsample whole grid");
}

void UpsamplePass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                           const Params& params) const {
  gpu::ProfileScope scope(profiler, cmd, kName);
  std::array<gpu::Binding, kUpsampleBindingCount> b;
  b[kUpsampleBindingCoarse] = &in.coarse;
  b[kUpsampleBindingFine] = &out.fine;
  b[kUpsampleBindingFineToCoarse] = &in.fineToCoarse;
  b[kUpsampleBindingBrickSlots] = &in.brickSlots;
  b[kUpsampleBindingRegion] = &mWholeGrid;
  const glm::ivec3 d = params.fineDims;
  mPipeline.dispatch(cmd, b, &params,
                     {gpu::groupsFor(d.x, RTSDF_UPSAMPLE_GROUP_X), gpu::groupsFor(d.y, RTSDF_UPSAMPLE_GROUP_Y),
                      gpu::groupsFor(d.z, std::uint32_t(mRun))});
  gpu::computeBarrier(cmd);
}

std::vector<int> upsampleBlockFineBegins(const GridSpec& coarse, const GridSpec& fine) {
  const glm::ivec3 bd = coarseBlockDims(coarse.dims);
  std::vector<int> begins(upsampleBlockFineBeginWords(coarse.dims));
  for (int a = 0; a < 3; ++a) {
    int* axis = begins.data() + upsampleBlockFineAt(bd, a);
    // Fine voxel x's block: that of the coarse voxel holding its centre (clamped); blocks only grow with x.
    int block = 0;
    axis[0] = 0;
    for (int x = 0; x < fine.dims[a]; ++x) {
      const double centre = fine.origin[a] + (x + 0.5) * fine.voxelSize;
      const int cell = std::clamp(int(std::floor((centre - coarse.origin[a]) / coarse.voxelSize)), 0, coarse.dims[a] - 1);
      for (; block < cell / RTSDF_COARSE_BLOCK; ++block) axis[block + 1] = x;
    }
    for (; block < bd[a]; ++block) axis[block + 1] = fine.dims[a];
  }
  return begins;
}

std::uint64_t UpsampleBlocksPass::listBytes(const glm::ivec3& coarseDims) {
  const glm::u64vec3 bd(coarseBlockDims(coarseDims));
  return (kUpsampleBlockListHeaderWords + bd.x * bd.y * bd.z) * 4;
}

void UpsampleBlocksPass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in,
                                 const Outputs& out, const glm::ivec3& coarseDims) const {
  gpu::ProfileScope scope(profiler, cmd, UpsamplePass::kName); // the upsampling's cost, its listing included
  static const UpsampleBlockListHeader kEmpty{glm::uvec4(0u, 1u, 1u, 0u), glm::uvec4(0u)};
  gpu::recordUpload(cmd, out.list, &kEmpty, sizeof(kEmpty));
  gpu::computeBarrier(cmd);
  std::array<gpu::Binding, kUpsampleBlocksBindingCount> b;
  b[kUpsampleBlocksBindingMarks] = &in.marks;
  b[kUpsampleBlocksBindingBoxes] = &in.boxes;
  b[kUpsampleBlocksBindingFineBegins] = &in.fineBegins;
  b[kUpsampleBlocksBindingList] = &out.list;
  const glm::uvec3 bd(coarseBlockDims(coarseDims));
  const std::uint32_t groups = gpu::groupsFor(bd.x * bd.y * bd.z, RTSDF_UPSAMPLE_BLOCKS_GROUP);
  UpsampleBlocksParams p{glm::ivec4(coarseDims, RTSDF_UPSAMPLE_BLOCKS_LIST)};
  mPipeline.dispatch(cmd, b, &p,
                     {std::min(groups, kCoarseRegionGroupsX), gpu::groupsFor(groups, kCoarseRegionGroupsX), 1u});
  gpu::computeBarrier(cmd);
  p.coarseDims.w = RTSDF_UPSAMPLE_BLOCKS_DISPATCH;
  mPipeline.dispatch(cmd, b, &p, {1u, 1u, 1u});
  gpu::computeBarrier(cmd);
}

void UpsampleByBlocksPass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in,
                                   const Outputs& out, const Params& params) const {
  gpu::ProfileScope scope(profiler, cmd, kName);
  std::array<gpu::Binding, kUpsampleBlocksKernelBindingCount> b;
  b[kUpsampleBindingCoarse] = &in.upsample.coarse;
  b[kUpsampleBindingFine] = &out.fine;
  b[kUpsampleBindingFineToCoarse] = &in.upsample.fineToCoarse;
  b[kUpsampleBindingBrickSlots] = &in.upsample.brickSlots;
  b[kUpsampleBindingBlockList] = &in.list;
  b[kUpsampleBindingFineBegins] = &in.fineBegins;
  mPipeline.dispatchIndirect(cmd, b, &params, in.list);
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
  b[kRefineBindingPieceOf] = &in.bvh.pieceOf();
  b[kRefineBindingUnionPieces] = &in.bvh.unionPieces();
  b[kRefineBindingOpenFlags] = &in.bvh.openFlags();
  b[kRefineBindingWindingNodes] = &in.bvh.windingNodes();
  b[kRefineBindingStats] = &out.stats;
  b[kRefineBindingWindingDoubts] = &out.doubts;
  b[kRefineBindingMovedBoxes] = &in.movedBoxes;
  mPipeline.dispatchIndirect(cmd, b, &params, in.counts);
  gpu::computeBarrier(cmd);
}

void WindingExactPass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                               const Params& params) const {
  gpu::ProfileScope scope(profiler, cmd, kName);
  std::array<gpu::Binding, kWindingExactBindingCount> b;
  in.bvh.bindTo(b);
  b[kWindingExactBindingDoubts] = &in.doubts;
  b[kWindingExactBindingDense] = &out.dense;
  b[kWindingExactBindingTriangles] = &in.bvh.instanceTriangles();
  b[kWindingExactBindingStats] = &out.stats;
  bindPages(b, kWindingExactBindingValuePages, out.pool.values);
  mPipeline.dispatchIndirect(cmd, b, &params, in.doubts);
  gpu::computeBarrier(cmd);
}

} // namespace rtsdf
