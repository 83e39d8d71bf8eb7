#include "sdf/pipeline/GpuRayMask.h"

#include "sdf/coarse/CoarseScroll.h"
#include "sdf/pipeline/GridShift.h"

#include "util/Error.h"

#include <fmt/format.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

namespace rtsdf {
using gpu::Buffer;
using gpu::kStorage;
using gpu::kStorageFilled;
using gpu::kStorageRead;

namespace {
constexpr std::uint32_t kStatsAt = gpu::shared::kMaskCountWords + gpu::shared::kBrickCountWords;
constexpr std::uint32_t kReadbackWords = kStatsAt + gpu::shared::kRefineStatWords;

/// Per axis each coarse block's first coarse voxel and the end (upsampleBlockFineBegins' layout), so that the block
/// lister's total counts the listed blocks' coarse voxels.
std::vector<int> coarseBlockBegins(const glm::ivec3& dims) {
  std::vector<int> begins;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b * RTSDF_COARSE_BLOCK < dims[a]; ++b) begins.push_back(b * RTSDF_COARSE_BLOCK);
    begins.push_back(dims[a]);
  }
  return begins;
}

/// Whether every coarse voxel's fine voxels lie in one brick that a scroll by whole bricks moves with it.
bool exactCover(const GridSpec& coarse, const GridSpec& fine) {
  const glm::ivec3 c = coarse.dims, f = fine.dims;
  const int r = f.x / std::max(c.x, 1);
  return r >= 1 && f == c * r && RTSDF_BRICK % r == 0;
}

} // namespace

gpu::shared::MaskRegion settlingMovedWith(gpu::shared::MaskRegion r, const glm::ivec3& dims, const glm::ivec3& shift) {
  for (int k = 0; k < 2; ++k) {
    if (glm::any(glm::greaterThan(glm::uvec3(r.settlingLo[k]), glm::uvec3(r.settlingHi[k])))) continue; // empty
    const glm::ivec3 lo = glm::max(glm::ivec3(glm::uvec3(r.settlingLo[k])) - shift, glm::ivec3(0));
    const glm::ivec3 hi = glm::min(glm::ivec3(glm::uvec3(r.settlingHi[k])) - shift, dims - 1);
    const bool left = glm::any(glm::greaterThan(lo, hi)); // all of it
    r.settlingLo[k] = left ? glm::uvec4(0xFFFFFFFFu) : glm::uvec4(glm::uvec3(lo), 0u);
    r.settlingHi[k] = left ? glm::uvec4(0u) : glm::uvec4(glm::uvec3(hi), 0u);
  }
  return r;
}

GpuRayMask::GpuRayMask(const gpu::VulkanContext& ctx, const GridSpec& coarse, const GridSpec& fine,
                       const PipelineSettings& settings, std::uint32_t refineParts)
    : mCtx(ctx), mCoarseSpec(coarse), mFineSpec(fine), mBand(settings.band),
      mBeta(settings.beta >= 0.0 ? settings.beta : 0.5 * coarse.voxelSize),
      mSettleFrames(std::uint32_t(settleFramesFor(settings))), mRefreshPeriod(std::uint32_t(refreshPeriodFor(settings))),
      mRefineParts(refineParts), mBrickDims(brickDimsOf(fine)), mCompact(ctx), mDispatch(ctx), mRegionPass(ctx),
      mLeave(ctx), mLister(ctx), mExactCover(exactCover(coarse, fine)) {
  mCoarseState = Buffer(ctx, coarse.voxelCount() * 8, kStorageFilled, Buffer::Memory::Device,
                        "coarse refinement state");
  const std::vector<int> fineToCoarse = maskCoarseOfFine(coarse, fine);
  gpu::reserveAndUpload(ctx, mFineToCoarse, fineToCoarse.data(), fineToCoarse.size() * sizeof(int), kStorage,
                        "ray mask fine-to-coarse table");
  const std::vector<glm::ivec2> ranges = maskFineRanges(coarse, fine);
  gpu::reserveAndUpload(ctx, mFineRanges, ranges.data(), ranges.size() * sizeof(glm::ivec2), kStorage,
                        "ray mask fine ranges");
  mCounts = Buffer(ctx, gpu::shared::kMaskCountWords * 4, kStorageRead | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
                   Buffer::Memory::Device, "ray mask counts");
  mRefineStats = Buffer(ctx, gpu::shared::kRefineStatWords * 4, kStorageRead, Buffer::Memory::Device,
                        "refinement statistics");
  mCountsReadback = Buffer(ctx, kReadbackWords * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT, Buffer::Memory::Host,
                           "ray mask counts (readback)");
  mRegion = Buffer(ctx, sizeof(gpu::shared::MaskRegion), kStorage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
                   Buffer::Memory::Host, "ray mask region");
  gpu::shared::MaskRegion empty{};
  for (int k = 0; k < 2; ++k) empty.settlingLo[k] = glm::uvec4(0xFFFFFFFFu); // no voxel left settling yet
  std::memcpy(mRegion.mapped(), &empty, sizeof(empty));
  if (mBand > 0.0) {
    // Each coarse voxel is appended at most once.
    mRefineList = Buffer(ctx, coarse.voxelCount() * 4, kStorageRead, Buffer::Memory::Device,
                         "refine list (coarse voxels)");
    mListBoxes = Buffer(ctx, sizeof(gpu::shared::UpsampleBoxes), kStorage, Buffer::Memory::Host, "mask list boxes");
    mBlockList = Buffer(ctx, UpsampleBlocksPass::listBytes(coarse.dims),
                        kStorage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                            VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                        Buffer::Memory::Device, "mask block list");
    mBlockListHeader = Buffer(ctx, sizeof(gpu::shared::UpsampleBlockListHeader), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                              Buffer::Memory::Host, "mask block list header");
    const std::vector<int> begins = coarseBlockBegins(coarse.dims);
    gpu::reserveAndUpload(ctx, mCoarseBegins, begins.data(), begins.size() * 4, kStorage, "mask blocks' voxels");
  }
}

void GpuRayMask::recordClear(VkCommandBuffer cmd) const {
  // No voxel has been in the band: last frame + 1 must differ from the first frame number (1).
  vkCmdFillBuffer(cmd, mCoarseState.handle(), 0, VK_WHOLE_SIZE, 0xFFFFFFFFu);
}

void GpuRayMask::recordScroll(VkCommandBuffer cmd, const GridSpec& coarse, const GridSpec& fine,
                              const glm::ivec3& coarseShift, const gpu::Buffer& scratch,
                              const GridShiftPass* shiftPass) {
  // The band's counts lose the voxels that leave, read from the state before it moves.
  mLeave.execute(cmd, nullptr, {mCoarseState, mFineRanges}, {mCounts},
                 {glm::ivec4(mCoarseSpec.dims, 0), glm::ivec4(coarseShift, 0)});
  mCoarseSpec = coarse;
  mFineSpec = fine;
  // 0xFFFFFFFF: no frame in the band (as BrickPool::allocate resets it), so an entered voxel in the band is fresh.
  recordGridShift(cmd, shiftPass, mCoarseState, scratch, coarse.dims, 8, coarseShift, 0xFFFFFFFFu);
  // The settling boxes move with their voxels (the last frame is finished: the region is the host's to write).
  const gpu::shared::MaskRegion r = settlingMovedWith(lastRegion(), coarse.dims, coarseShift);
  std::memcpy(mRegion.mapped(), &r, sizeof(r));
  mEnteredBoxes = boxesOutside(coarse.dims, keptByShift(coarse.dims, coarseShift));
  ++mScrollsSinceRun;
}

gpu::shared::MaskParams GpuRayMask::params(std::uint32_t frame, std::uint32_t movedBoxes, int flags) const {
  gpu::shared::MaskParams p{};
  // outOfViewRewritten's growth of the changed box: a coarse voxel for the upsampling's stencil, and a brick's width.
  const int brickCells = int(std::ceil(RTSDF_BRICK * mFineSpec.voxelSize / mCoarseSpec.voxelSize));
  p.coarseDims = glm::ivec4(mCoarseSpec.dims, flags | ((1 + brickCells) << 8));
  p.band = float(mBand);
  p.refineCapacity = std::uint32_t(mRefineList.size() / 4);
  p.frame = frame;
  // The grids measure from the fine grid's corner (SdfPipeline::frameOrigin()).
  const GridSpec coarse = mCoarseSpec.inFrame(mFineSpec.origin);
  p.coarseOriginH = glm::vec4(glm::vec3(coarse.origin), float(coarse.voxelSize));
  // movedWithinReach: the coarse bound of the distance (beta, half a coarse diagonal to the seed's surface and
  // half one to a fine centre of the cell), and a fine voxel for rounding.
  p.reachPad = float(reachPad());
  p.settleFrames = mSettleFrames;
  p.refreshPeriod = mRefreshPeriod;
  p.movedBoxes = movedBoxes;
  p.brickDims = glm::ivec4(mBrickDims, mRefineParts);
  p.viewApex = glm::vec4(0.0f, 0.0f, 0.0f, -1.0f);
  p.viewAxis = glm::vec4(0.0f);
  if (mViewLimited) {
    // withinViewReach: R / cos a with R half a coarse diagonal (the cell's sphere) and the margin, and tan a.
    const double reach = 0.5 * std::sqrt(3.0) * mCoarseSpec.voxelSize + mView.margin;
    p.viewApex = glm::vec4(glm::vec3(mView.apex - mFineSpec.origin), float(reach / std::cos(mView.halfAngle)));
    p.viewAxis = glm::vec4(glm::vec3(mView.axis), float(std::tan(mView.halfAngle)));
  }
  return p;
}

void GpuRayMask::setViewReach(const ViewReach* reach) {
  mViewLimited = reach != nullptr;
  if (reach) mView = *reach;
}

void GpuRayMask::writeListBoxes(std::uint32_t frame, const CoarseVoxelBox& near) const {
  gpu::shared::UpsampleBoxes boxes{};
  const auto add = [&](const glm::ivec3& lo, const glm::ivec3& hi) {
    if (glm::any(glm::greaterThan(lo, hi))) return;
    if (boxes.count.x == RTSDF_UPSAMPLE_MAX_BOXES) throw Error("GpuRayMask: more boxes than a block listing takes");
    boxes.lo[boxes.count.x] = glm::ivec4(lo, 0);
    boxes.hi[boxes.count.x++] = glm::ivec4(hi, 0);
  };
  for (const CoarseVoxelBox& b : mEnteredBoxes) add(b.lo, b.hi);
  const gpu::shared::MaskRegion r = lastRegion();
  const std::uint32_t last = (frame + 1u) & 1u;
  if (glm::all(glm::lessThanEqual(glm::uvec3(r.settlingLo[last]), glm::uvec3(r.settlingHi[last]))))
    add(glm::ivec3(glm::uvec3(r.settlingLo[last])), glm::ivec3(glm::uvec3(r.settlingHi[last])));
  add(near.lo, near.hi);
  std::memcpy(mListBoxes.mapped(), &boxes, sizeof(boxes));
}

void GpuRayMask::recordMask(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, std::uint32_t frame,
                            std::uint32_t movedCount, const gpu::Buffer& coarse, const gpu::Buffer& movedBoxes,
                            const gpu::Buffer& changedBox, int flags, const BrickPool& pool,
                            const CoarseVoxelBox& near, const gpu::Buffer* changedBlocks) {
  using namespace gpu::shared;
  if ((flags & kMaskBlockList) != 0 && (!carriesOverScroll() || !changedBlocks || !(flags & kMaskRegionOnly)))
    throw Error("GpuRayMask: a run over listed blocks needs one scroll the mask carried over, the changed blocks' "
                "marks and a run over what changed");
  mLastParams = params(frame, movedCount, flags);
  mLastListed = (flags & kMaskBlockList) != 0 && mBand > 0.0;
  mScrollsSinceRun = 0;
  const bool regionOnly = (flags & kMaskRegionOnly) != 0;
  if (regionOnly) { // the band's counts are the last run's, changed where a visited voxel changed
    vkCmdFillBuffer(cmd, mCounts.handle(), 0, kMaskCountCoarse * 4, 0u);
    vkCmdFillBuffer(cmd, mCounts.handle(), kMaskCountRefineList * 4, (kMaskCountWords - kMaskCountRefineList) * 4, 0u);
    static_assert(kMaskCountMaskedFine + 1 == kMaskCountRefineList && kMaskCountCoarse + 1 == kMaskCountMaskedFine);
  } else {
    vkCmdFillBuffer(cmd, mCounts.handle(), 0, VK_WHOLE_SIZE, 0u);
  }
  vkCmdFillBuffer(cmd, mRefineStats.handle(), 0, VK_WHOLE_SIZE, 0u);
  pool.recordResetCounts(cmd, !regionOnly);
  gpu::computeBarrier(cmd);
  // d = 0 refines nothing (not even voxels with c = 0): the counts stay zero, and so does the dispatch.
  if (mBand > 0.0) {
    MaskRegionParams rp{};
    rp.dims = glm::ivec4(mCoarseSpec.dims, flags & (kMaskRegionOnly | kMaskCoarseRebuilt | kMaskBlockList));
    rp.nearLo = glm::ivec4(near.lo, 0);
    rp.nearHi = glm::ivec4(near.hi, 0);
    rp.frame = frame;
    if (mLastListed) { // the blocks what changed, entered, settles or is near a moving box reaches
      gpu::ProfileScope scope(profiler, cmd, MaskCompactPass::kName);
      writeListBoxes(frame, near);
      mLister.execute(cmd, nullptr, {*changedBlocks, mListBoxes, mCoarseBegins}, {mBlockList}, mCoarseSpec.dims);
      const VkBufferCopy header{0, 0, sizeof(UpsampleBlockListHeader)};
      vkCmdCopyBuffer(cmd, mBlockList.handle(), mBlockListHeader.handle(), 1, &header);
      gpu::transferToHostBarrier(cmd);
    }
    mRegionPass.execute(cmd, nullptr, {changedBox}, {mRegion}, rp);
    MaskCompactPass::Inputs in{coarse, mFineRanges, movedBoxes, changedBox, mLastListed ? &mBlockList : nullptr};
    mCompact.execute(cmd, profiler, in, {mCounts, mRefineList, mCoarseState, pool.bandCounts(), mRegion},
                     mLastParams);
    pool.recordAlloc(cmd, profiler);
  }
  mDispatch.execute(cmd, profiler, {}, {mCounts}, mLastParams);
}

void GpuRayMask::recordCountsReadback(VkCommandBuffer cmd, const BrickPool& pool) const {
  const VkBufferCopy mask{0, 0, gpu::shared::kMaskCountWords * 4};
  vkCmdCopyBuffer(cmd, mCounts.handle(), mCountsReadback.handle(), 1, &mask);
  const VkBufferCopy bricks{0, gpu::shared::kMaskCountWords * 4, gpu::shared::kBrickCountWords * 4};
  vkCmdCopyBuffer(cmd, pool.counts().handle(), mCountsReadback.handle(), 1, &bricks);
  const VkBufferCopy stats{0, kStatsAt * 4, gpu::shared::kRefineStatWords * 4};
  vkCmdCopyBuffer(cmd, mRefineStats.handle(), mCountsReadback.handle(), 1, &stats);
  gpu::transferToHostBarrier(cmd);
}

double GpuRayMask::reachPad() const {
  return mBeta + std::sqrt(3.0) * mCoarseSpec.voxelSize + mFineSpec.voxelSize;
}

std::uint64_t GpuRayMask::lastVisitedVoxels() const {
  if (!mLastListed) return regionVoxels(lastRegion());
  gpu::shared::UpsampleBlockListHeader h;
  std::memcpy(&h, mBlockListHeader.mapped(), sizeof(h));
  return h.totals.x; // the listed blocks' coarse voxels (coarseBlockBegins)
}

gpu::shared::MaskRegion GpuRayMask::lastRegion() const {
  gpu::shared::MaskRegion r{};
  std::memcpy(&r, mRegion.mapped(), sizeof(r));
  return r;
}

GpuRayMask::Counts GpuRayMask::counts() const {
  std::uint32_t words[kReadbackWords];
  std::memcpy(words, mCountsReadback.mapped(), sizeof(words));
  using namespace gpu::shared;
  Counts n;
  n.refinedFine = words[kMaskCountFine];
  n.maskedFine = words[kMaskCountMaskedFine];
  n.coarse = words[kMaskCountCoarse];
  n.refineList = words[kMaskCountRefineList];
  n.outOfView = words[kMaskCountOutOfView];
  n.activeBricks = words[kMaskCountWords + kBrickCountActive];
  n.overflowBricks = words[kMaskCountWords + kBrickCountOverflow];
  n.cutVoxels = words[kStatsAt + kRefineStatCutVoxels];
  n.nearHalf = words[kStatsAt + kRefineStatNearHalf];
  n.nearHalfKept = words[kStatsAt + kRefineStatNearHalfKept];
  n.movedKept = words[kStatsAt + kRefineStatMovedKept];
  // Each fine voxel lies under one coarse voxel and each coarse voxel is appended once: more would be a bug.
  const glm::ivec3 bd = mBrickDims;
  if (n.refinedFine > n.maskedFine || n.maskedFine > mFineSpec.voxelCount() || n.coarse > mCoarseSpec.voxelCount() ||
      n.refineList > n.coarse || n.outOfView > n.refineList || n.activeBricks > std::uint64_t(bd.x) * bd.y * bd.z ||
      n.overflowBricks > n.activeBricks || n.cutVoxels > n.refinedFine || n.nearHalf > n.refinedFine ||
      n.nearHalfKept > n.nearHalf || n.movedKept + n.cutVoxels > n.refinedFine)
    throw Error(fmt::format("ray mask: the GPU counted {} fine voxels to refine ({} of them cut, {} kept unwalked) of "
                            "{} under {} coarse voxels ({} listed), {} bricks ({} without a slot), more than the grids "
                            "hold ({}, {} and {})",
                            n.refinedFine, n.cutVoxels, n.movedKept, n.maskedFine, n.coarse, n.refineList,
                            n.activeBricks, n.overflowBricks, mFineSpec.voxelCount(), mCoarseSpec.voxelCount(),
                            std::uint64_t(bd.x) * bd.y * bd.z));
  return n;
}

std::vector<std::uint32_t> GpuRayMask::readRefinedVoxels(std::uint32_t frame) const {
  return readListedVoxels(frame, false);
}

std::vector<std::uint32_t> GpuRayMask::readRewrittenVoxels(std::uint32_t frame) const {
  return readListedVoxels(frame, true);
}

std::vector<std::uint32_t> GpuRayMask::readOutOfViewVoxels(std::uint32_t frame) const {
  std::vector<std::uint32_t> list;
  if (!frame || mBand <= 0.0 || !mViewLimited) return list;
  const std::vector<glm::uvec2> state = readCoarseState();
  const std::vector<glm::ivec2> ranges = maskFineRanges(mCoarseSpec, mFineSpec);
  const glm::ivec3 cd = mCoarseSpec.dims;
  for (std::size_t i = 0; i < state.size(); ++i)
    if (state[i] == glm::uvec2(frame, 0u))
      appendFineVoxelsUnder(ranges, cd, glm::ivec3(int(i % cd.x), int(i / cd.x % cd.y), int(i / cd.x / cd.y)),
                            0u, list);
  tbb::parallel_sort(list.begin(), list.end());
  return list;
}

std::vector<std::uint32_t> GpuRayMask::readRefineList(std::uint32_t frame) const {
  std::vector<std::uint32_t> entries(frame && mBand > 0.0 ? counts().refineList : 0);
  download(mCtx, mRefineList, entries.data(), entries.size() * 4);
  return entries;
}

std::vector<std::uint32_t> GpuRayMask::readMovedOnlyCoarse(std::uint32_t frame) const {
  std::vector<std::uint32_t> list;
  for (std::uint32_t entry : readRefineList(frame))
    if (entry & gpu::shared::kMaskMovedOnly) list.push_back(entry & gpu::shared::kMaskCoarseIndex);
  std::sort(list.begin(), list.end());
  return list;
}

std::vector<std::uint32_t> GpuRayMask::readListedVoxels(std::uint32_t frame, bool outOfView) const {
  using gpu::shared::kMaskOutOfView;
  const std::vector<std::uint32_t> coarse = readRefineList(frame);
  const std::vector<glm::ivec2> ranges = maskFineRanges(mCoarseSpec, mFineSpec);
  const glm::ivec3 cd = mCoarseSpec.dims;
  std::vector<std::uint32_t> list;
  for (std::uint32_t entry : coarse) {
    if (((entry & kMaskOutOfView) != 0u) != outOfView) continue;
    const std::uint32_t i = entry & gpu::shared::kMaskCoarseIndex;
    const glm::ivec3 c(int(i % cd.x), int(i / cd.x % cd.y), int(i / cd.x / cd.y));
    appendFineVoxelsUnder(ranges, cd, c, entry & (gpu::shared::kMaskFineFresh | kMaskOutOfView), list);
  }
  tbb::parallel_sort(list.begin(), list.end());
  return list;
}

std::vector<glm::uvec2> GpuRayMask::readCoarseState() const {
  std::vector<glm::uvec2> state(mCoarseSpec.voxelCount());
  download(mCtx, mCoarseState, state.data(), state.size() * 8);
  return state;
}

} // namespace rtsdf
