#include "sdf/pipeline/FieldPasses.h"

#include "sdf/coarse/CoarseScroll.h"
#include "sdf/pipeline/FramePlan.h"
#include "sdf/pipeline/GridShift.h"
#include "util/Error.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <utility>

namespace rtsdf {
using gpu::Buffer;
using gpu::shared::RefineParams;

FieldPasses::FieldPasses(const gpu::VulkanContext& ctx, const GridSpec& coarse, const GridSpec& fine,
                         const PipelineSettings& settings, const RefineParts& parts,
                         const ClosestRefinePass::Variant& closest)
    : mCtx(ctx), mCoarseSpec(coarse), mFineSpec(fine), mSettings(settings), mParts(parts), mCoarse(ctx),
      mUpsample(ctx), mUpsampleBlocks(ctx), mUpsampleByBlocks(ctx),
      mRefine(settings.mode == RefineMode::Rays ? std::unique_ptr<RefinePass>(std::make_unique<RayRefinePass>(ctx))
                                                : std::make_unique<ClosestRefinePass>(ctx, closest)) {
  if (settings.mode == RefineMode::Closest) {
    mWindingExact = std::make_unique<WindingExactPass>(ctx);
    mWindingDoubts = Buffer(ctx, (1 + gpu::shared::kWindingExactCapacity) * sizeof(glm::uvec4),
                            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                                VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                            Buffer::Memory::Device, "winding numbers near 1/2");
  }
  if (settings.fineStorage == FineStorage::Dense)
    mFine = Buffer(ctx, fine.voxelCount() * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, Buffer::Memory::Device,
                   "fine SDF");
  if (mFine) {
    mUpsampleBoxes = Buffer(ctx, sizeof(gpu::shared::UpsampleBoxes), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                            Buffer::Memory::Host, "upsample boxes");
    mBlockList = Buffer(ctx, UpsampleBlocksPass::listBytes(coarse.dims),
                        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                            VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                        Buffer::Memory::Device, "upsample block list");
    mBlockListHeader = Buffer(ctx, sizeof(gpu::shared::UpsampleBlockListHeader), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                              Buffer::Memory::Host, "upsample block list header");
    mFineBegins = upsampleBlockFineBegins(coarse.inFrame(fine.origin), fine.inFrame(fine.origin));
    gpu::reserveAndUpload(ctx, mBlockFineBegins, mFineBegins.data(), mFineBegins.size() * 4, gpu::kStorage,
                          "upsample blocks' fine voxels");
  }
  mSamplingParams = Buffer(ctx, sizeof(RefineParams),
                           VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                           Buffer::Memory::Device, "brick sampling parameters");
}

void FieldPasses::recordClear(VkCommandBuffer cmd) const {
  if (mFine) vkCmdFillBuffer(cmd, mFine.handle(), 0, VK_WHOLE_SIZE, 0u);
}

void FieldPasses::recordCoarse(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const GpuSceneBvh& bvh,
                               const CoarseVoxelBox* change) {
  CoarseSdfSettings cs;
  cs.method = mSettings.coarseMethod;
  cs.beta = mSettings.beta;
  cs.keepTransform = coarseBuiltOverChanges(mSettings);
  // Every GPU pass measures from the fine grid's corner (SdfPipeline::frameOrigin()), but the voxelization of a grid
  // on the world's seed lattice from the world's origin (SdfPipeline::placeSeedsOnLattice).
  const glm::dvec3 seedOrigin = bvh.seedOrigin();
  if (seedOrigin == glm::dvec3(0.0)) cs.seedLatticeCell = seedLatticeCell(mCoarseSpec);
  mScrollFrame = std::exchange(mScrollPending, ScrollUpsample{});
  mCoarse.record(cmd, profiler, bvh.instancedTriangles(), mCoarseSpec.inFrame(seedOrigin), cs, change);
  // The ChangedBox holds what differs from the moved values only where this build ran over what the scroll changed.
  if (!mCoarse.lastBuiltOverChange()) mScrollFrame.coarseMoved = false;
}

void FieldPasses::recordScroll(VkCommandBuffer cmd, const std::pair<GridSpec, GridSpec>& grids,
                               const glm::ivec3& shift, const gpu::Buffer& scratch, bool sceneChanged,
                               const GridShiftPass* gridShift) {
  const glm::ivec3 fineShift = shift * (grids.second.dims / grids.first.dims);
  mCoarseSpec = grids.first;
  mFineSpec = grids.second;
  mCoarse.recordScroll(cmd, shift, scratch, sceneChanged, gridShift);
  // Loose: the voxels that entered are refined (new to the band) or upsampled by the next frame, whatever they hold.
  if (mFine) recordGridShift(cmd, mFine, scratch, gridShiftPlanLoose(mFineSpec.dims, 4, fineShift), 0u);
  // A second scroll before a build moves no distances (CoarseSdfBuilder::recordScroll): then every voxel.
  mScrollPending.scrolled = true;
  mScrollPending.coarseMoved = mCoarse.scrollMovedDistances();
  mScrollPending.boxes = mScrollPending.coarseMoved ? scrollUpsampleBoxes(mCoarseSpec.dims, shift)
                                                    : std::vector<CoarseVoxelBox>{};
  if (mScrollPending.boxes.size() > RTSDF_UPSAMPLE_MAX_BOXES)
    throw Error(fmt::format("FieldPasses: a scroll left {} boxes to upsample, at most {} expected",
                            mScrollPending.boxes.size(), RTSDF_UPSAMPLE_MAX_BOXES));
  // The blocks' fine voxels move with the grids (whole coarse voxels): the table changes only if their offset did.
  if (mFine) {
    std::vector<int> begins = upsampleBlockFineBegins(mCoarseSpec.inFrame(mFineSpec.origin),
                                                      mFineSpec.inFrame(mFineSpec.origin));
    if (begins != mFineBegins) {
      mFineBegins = std::move(begins);
      gpu::recordUpload(cmd, mBlockFineBegins, mFineBegins.data(), mFineBegins.size() * 4);
    }
  }
}

RefineParams FieldPasses::refineParams(std::uint32_t frame, const BrickPool& pool, std::uint32_t movedBoxes) const {
  const glm::dvec3& origin = mFineSpec.origin;
  RefineParams p = refineGridParams(mCoarseSpec.inFrame(origin), mFineSpec.inFrame(origin));
  p.alpha = float(mSettings.alpha);
  p.rays = std::uint32_t(mSettings.rays);
  p.frame = frame;
  p.seed = mSettings.seed;
  p.beta = float(mSettings.beta >= 0.0 ? mSettings.beta : 0.5 * mCoarseSpec.voxelSize);
  p.band = float(mSettings.band);
  p.pageBricks = std::uint32_t(std::max<std::uint64_t>(pool.pageBricks(), 1));
  p.refineParts = mParts.total();
  p.brickDims = glm::ivec4(pool.brickDims(), mParts.count.x);
  p.partBox = glm::ivec4(mParts.box, mParts.count.y);
  p.fineDims.w = int(pool.capacity());
  p.coarseDims.w = (mFine ? gpu::shared::kRefineWriteDense : 0) |
                   (mSettings.mode == RefineMode::Closest && mSettings.closestSearch == ClosestSearch::Cell
                        ? gpu::shared::kRefineCellSearch
                        : 0) |
                   (mSettings.shaderTarget == ShaderTarget::Cpu ? gpu::shared::kRefineSpreadGroups : 0);
  const auto boxes = int(std::min<std::uint32_t>(movedBoxes, RTSDF_MAX_MOVED_BOXES));
  p.coarseDims.w |= boxes << gpu::shared::kRefineMovedBoxesShift;
  return p;
}

void FieldPasses::recordFine(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const RefineParams& p,
                             const GpuSceneBvh& bvh, const GpuRayMask& mask, const BrickPool& pool,
                             const Buffer& movedBoxes, bool refine, bool upsample, bool upsampleChanged) {
  const BrickPages pages = pool.pages();
  const Buffer& coarse = mCoarse.distanceBuffer();
  const Buffer& dense = mFine ? mFine : pool.placeholder();
  if (refine && mSettings.band > 0.0) {
    // An empty list of voxels for the exact winding number: no work groups (x = 0, y = z = 1).
    static const glm::uvec4 kEmptyList(0u, 1u, 1u, 0u);
    if (mWindingDoubts) {
      gpu::recordUpload(cmd, mWindingDoubts, &kEmptyList, sizeof(kEmptyList));
      gpu::computeBarrier(cmd);
    }
    mRefine->execute(cmd, profiler, {bvh, mask.refineList(), mask.countsBuffer(), coarse, mask.fineRanges(),
                                     pool.slots(), movedBoxes},
                     {pages, dense, mask.refineStats(), mWindingDoubts ? mWindingDoubts : pool.placeholder()}, p);
    if (mWindingExact && bvh.openPieces().any())
      mWindingExact->execute(cmd, profiler, {bvh, mWindingDoubts}, {pages, dense, mask.refineStats()}, p);
  }
  mLastUpsample = Upsampled::None;
  mLastParams = p;
  if (upsample && mFine) recordUpsample(cmd, profiler, p, mask, pool, upsampleChanged);
  // Shading that samples the bricks finds the grids here.
  gpu::recordUpload(cmd, mSamplingParams, &p, sizeof(p));
}

void FieldPasses::recordUpsample(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const RefineParams& p,
                                 const GpuRayMask& mask, const BrickPool& pool, bool changedOnly) {
  const UpsamplePass::Inputs in{mCoarse.distanceBuffer(), mask.fineToCoarse(), pool.slots()};
  // After a scroll the coarse SDF's changes are of use only where the build ran over what the scroll moved.
  if (!changedOnly || (mScrollFrame.scrolled && !mScrollFrame.coarseMoved)) {
    mUpsample.execute(cmd, profiler, in, {mFine}, p);
    mLastUpsample = Upsampled::Whole;
    return;
  }
  // The boxes a scroll invalidated whatever the coarse values there, written by the host (the frame before is
  // finished); then the blocks the changes and the boxes reach, and their fine voxels.
  gpu::shared::UpsampleBoxes boxes{};
  boxes.count.x = int(mScrollFrame.boxes.size());
  for (std::size_t i = 0; i < mScrollFrame.boxes.size(); ++i) {
    boxes.lo[i] = glm::ivec4(mScrollFrame.boxes[i].lo, 0);
    boxes.hi[i] = glm::ivec4(mScrollFrame.boxes[i].hi, 0);
  }
  std::memcpy(mUpsampleBoxes.mapped(), &boxes, sizeof(boxes));
  mUpsampleBlocks.execute(cmd, profiler, {mCoarse.changedBlocksBuffer(), mUpsampleBoxes, mBlockFineBegins},
                          {mBlockList}, mCoarseSpec.dims);
  mUpsampleByBlocks.execute(cmd, profiler, {in, mBlockList, mBlockFineBegins}, {mFine}, p);
  mLastUpsample = Upsampled::Blocks;
  // The list's header is read on the host after the frame (lastUpsampledVoxels).
  const VkBufferCopy header{0, 0, sizeof(gpu::shared::UpsampleBlockListHeader)};
  vkCmdCopyBuffer(cmd, mBlockList.handle(), mBlockListHeader.handle(), 1, &header);
  gpu::transferToHostBarrier(cmd);
}

DenseFineWrites FieldPasses::denseWrites(const GpuRayMask& mask, bool refined, bool whole) const {
  DenseFineWrites w;
  w.params = mLastParams;
  refined = refined && mSettings.band > 0.0;
  if (!mFine || (!whole && mLastUpsample == Upsampled::None && !refined)) {
    w.extent = DenseFineWrites::Extent::None;
  } else if (!whole && mLastUpsample != Upsampled::Whole) {
    w.extent = DenseFineWrites::Extent::Listed;
    if (mLastUpsample == Upsampled::Blocks) {
      w.blockList = &mBlockList;
      w.blockFineBegins = &mBlockFineBegins;
    }
    if (refined) {
      w.refineList = &mask.refineList();
      w.maskCounts = &mask.countsBuffer();
      w.fineRanges = &mask.fineRanges();
    }
  }
  return w;
}

std::uint64_t FieldPasses::lastUpsampledVoxels() const {
  switch (mLastUpsample) {
  case Upsampled::None: return 0;
  case Upsampled::Whole: return mFineSpec.voxelCount();
  case Upsampled::Blocks: break;
  }
  gpu::shared::UpsampleBlockListHeader h;
  std::memcpy(&h, mBlockListHeader.mapped(), sizeof(h));
  return h.totals.x;
}

std::vector<std::uint32_t> FieldPasses::readUpsampledBlocks() const {
  if (mLastUpsample != Upsampled::Blocks) return {};
  gpu::shared::UpsampleBlockListHeader h;
  std::memcpy(&h, mBlockListHeader.mapped(), sizeof(h));
  std::vector<std::uint32_t> words(gpu::shared::kUpsampleBlockListHeaderWords + h.groups.w);
  gpu::download(mCtx, mBlockList, words.data(), words.size() * 4);
  std::vector<std::uint32_t> blocks(words.begin() + gpu::shared::kUpsampleBlockListHeaderWords, words.end());
  std::sort(blocks.begin(), blocks.end());
  return blocks;
}

const gpu::Buffer& FieldPasses::changedBoxBuffer() const { return mCoarse.changedBoxBuffer(); }

gpu::shared::ChangedBox FieldPasses::readChangedBox() const {
  gpu::shared::ChangedBox box;
  download(mCtx, mCoarse.changedBoxBuffer(), &box, sizeof(box));
  return box;
}

std::vector<float> FieldPasses::readCoarse() const {
  std::vector<float> out(mCoarseSpec.voxelCount());
  download(mCtx, mCoarse.distanceBuffer(), out.data(), out.size() * 4);
  return out;
}

std::vector<float> FieldPasses::readDenseFine() const {
  std::vector<float> out(mFineSpec.voxelCount());
  download(mCtx, mFine, out.data(), out.size() * 4);
  return out;
}

} // namespace rtsdf
