#include "sdf/pipeline/BrickPool.h"

#include "sdf/pipeline/GridShift.h"
#include "sdf/refine/RefineParams.h"
#include "util/Error.h"

#include <fmt/format.h>

#include <algorithm>
#include <utility>

namespace rtsdf {
using gpu::Buffer;
using gpu::kStorage;
using gpu::kStorageFilled;
using gpu::kStorageRead;

namespace {
constexpr std::uint64_t kBrickBytes = gpu::shared::kBrickVoxels * 4;
} // namespace

glm::ivec3 brickDimsOf(const GridSpec& fine) { return (fine.dims + (RTSDF_BRICK - 1)) / RTSDF_BRICK; }

std::uint64_t poolBricksFor(std::uint64_t activeBricks, const glm::ivec3& brickDims) {
  const std::uint64_t all = std::uint64_t(brickDims.x) * brickDims.y * brickDims.z;
  return std::min(all, activeBricks + activeBricks / 2 + 64);
}

BrickPool::BrickPool(const gpu::VulkanContext& ctx, const GridSpec& fine)
    : mCtx(ctx), mFineSpec(fine), mBrickDims(brickDimsOf(fine)), mAlloc(ctx) {
  const std::uint64_t bricks = gridBricks();
  mNeeded = Buffer(ctx, bricks * 4, kStorageFilled, Buffer::Memory::Device, "brick band counts");
  mSlots = Buffer(ctx, bricks * 4, kStorageRead, Buffer::Memory::Device, "brick slots");
  mCounts = Buffer(ctx, gpu::shared::kBrickCountWords * 4, kStorageRead, Buffer::Memory::Device, "brick counts");
  mPlaceholder = Buffer(ctx, 16, kStorage, Buffer::Memory::Device, "brick pool placeholder");
}

void BrickPool::recordClear(VkCommandBuffer cmd) const {
  vkCmdFillBuffer(cmd, mNeeded.handle(), 0, VK_WHOLE_SIZE, 0u);
  vkCmdFillBuffer(cmd, mSlots.handle(), 0, VK_WHOLE_SIZE, gpu::shared::kNoBrick);
  vkCmdFillBuffer(cmd, mCounts.handle(), 0, VK_WHOLE_SIZE, 0u);
}

std::uint64_t BrickPool::deviceBytesFor(std::uint64_t bricks) { return bricks * (2 * kBrickBytes + 4); }

void BrickPool::allocate(std::uint64_t bricks, const PipelineMemory& estimate, const gpu::Buffer& coarseState) {
  const std::uint64_t range = mCtx.info().maxStorageBufferRange;
  mPageBricks = std::max<std::uint64_t>(1, std::min<std::uint64_t>(std::max<std::uint64_t>(bricks, 1),
                                                                   range ? range / kBrickBytes : bricks));
  mPageBricks = std::min<std::uint64_t>(mPageBricks, 0xFFFFFFFFu / gpu::shared::kBrickVoxels);
  const std::uint64_t pages = (bricks + mPageBricks - 1) / mPageBricks;
  PipelineMemory need = estimate;
  need.deviceBytes += deviceBytesFor(bricks);
  if (pages > RTSDF_BRICK_PAGES)
    throw SettingError("fine resolution", fmt::format("SdfPipeline: fine grid {}: the band needs {} bricks ({}), more "
                                                      "than {} pages of {}'s maxStorageBufferRange: lower the fine "
                                                      "resolution or the band", mFineSpec.describe(), bricks,
                                                      formatMiB(bricks * 2 * kBrickBytes), RTSDF_BRICK_PAGES,
                                                      mCtx.info().name));
  checkPipelineMemory(need, memoryLimits(mCtx.info()));
  for (int k = 0; k < RTSDF_BRICK_PAGES; ++k) {
    const std::uint64_t first = std::uint64_t(k) * mPageBricks;
    const std::uint64_t n = first < bricks ? std::min(mPageBricks, bricks - first) : 0;
    mValues[k] = n ? Buffer(mCtx, n * kBrickBytes, kStorageFilled, Buffer::Memory::Device,
                            fmt::format("brick pool values {}", k)) : Buffer();
    mVotes[k] = n ? Buffer(mCtx, n * kBrickBytes, kStorageFilled, Buffer::Memory::Device,
                           fmt::format("brick pool votes {}", k)) : Buffer();
  }
  // Every slot free (the stack pops slot 0 first), no brick holding one, every coarse voxel new to the band.
  std::vector<std::uint32_t> stack(std::max<std::uint64_t>(bricks, 1), 0u);
  for (std::uint64_t k = 0; k < bricks; ++k) stack[k] = std::uint32_t(bricks - 1 - k);
  gpu::reserveAndUpload(mCtx, mFree, stack.data(), stack.size() * 4, kStorage, "brick free stack");
  const std::uint32_t counts[gpu::shared::kBrickCountWords] = {std::uint32_t(bricks), 0, 0, 0};
  gpu::CommandBuffer cmd(mCtx);
  gpu::recordUpload(cmd.handle(), mCounts, counts, sizeof(counts));
  vkCmdFillBuffer(cmd.handle(), mSlots.handle(), 0, VK_WHOLE_SIZE, gpu::shared::kNoBrick);
  vkCmdFillBuffer(cmd.handle(), coarseState.handle(), 0, VK_WHOLE_SIZE, 0xFFFFFFFFu);
  for (int k = 0; k < RTSDF_BRICK_PAGES; ++k) {
    if (mValues[k]) vkCmdFillBuffer(cmd.handle(), mValues[k].handle(), 0, VK_WHOLE_SIZE, 0u);
    if (mVotes[k]) vkCmdFillBuffer(cmd.handle(), mVotes[k].handle(), 0, VK_WHOLE_SIZE, 0u);
  }
  cmd.submitAndWait();
  mPoolBricks = bricks;
}

void BrickPool::recordResetCounts(VkCommandBuffer cmd, bool bandCounts) const {
  vkCmdFillBuffer(cmd, mCounts.handle(), 4, (gpu::shared::kBrickCountWords - 1) * 4, 0u);
  if (bandCounts) vkCmdFillBuffer(cmd, mNeeded.handle(), 0, VK_WHOLE_SIZE, 0u);
}

void BrickPool::recordAlloc(VkCommandBuffer cmd, gpu::GpuProfiler* profiler) const {
  gpu::shared::BrickParams bp{};
  bp.bricks = std::uint32_t(gridBricks());
  mAlloc.execute(cmd, profiler, {mNeeded}, {mCounts, mSlots, mFree}, bp);
}

void BrickPool::recordScroll(VkCommandBuffer cmd, const glm::ivec3& brickShift, const gpu::Buffer& scratch,
                             const GridShiftPass* shiftPass) {
  if (mPoolBricks > 0) {
    // The slots of the bricks that leave the grid (brick b goes to b - brickShift) return to the free stack.
    const std::vector<std::uint32_t> slots = readSlots();
    std::uint32_t counts[gpu::shared::kBrickCountWords] = {};
    download(mCtx, mCounts, counts, sizeof(counts));
    std::vector<std::uint32_t> freed;
    const glm::ivec3& d = mBrickDims;
    for (int z = 0; z < d.z; ++z)
      for (int y = 0; y < d.y; ++y)
        for (int x = 0; x < d.x; ++x) {
          const glm::ivec3 to = glm::ivec3(x, y, z) - brickShift;
          const std::uint32_t slot = slots[std::size_t((z * d.y + y) * d.x + x)];
          const bool stays = glm::all(glm::greaterThanEqual(to, glm::ivec3(0))) && glm::all(glm::lessThan(to, d));
          if (!stays && slot != gpu::shared::kNoBrick) freed.push_back(slot);
        }
    const std::uint32_t top = counts[gpu::shared::kBrickCountFreeTop];
    if (std::uint64_t(top) + freed.size() > mPoolBricks)
      throw Error(fmt::format("BrickPool: {} free slots and {} freed exceed the pool's {} (a bug)", top, freed.size(),
                              mPoolBricks));
    // The stack's entries above its top are free to overwrite: push the freed slots there (in pieces of at most
    // 64 KiB, vkCmdUpdateBuffer's limit), then raise the top.
    for (std::size_t at = 0; at < freed.size(); at += 16384) {
      const std::size_t n = std::min<std::size_t>(16384, freed.size() - at);
      vkCmdUpdateBuffer(cmd, mFree.handle(), VkDeviceSize(top + at) * 4, VkDeviceSize(n) * 4, freed.data() + at);
    }
    const std::uint32_t newTop = top + std::uint32_t(freed.size());
    vkCmdUpdateBuffer(cmd, mCounts.handle(), gpu::shared::kBrickCountFreeTop * 4, 4, &newTop);
  }
  recordGridShift(cmd, shiftPass, mSlots, scratch, mBrickDims, 4, brickShift, gpu::shared::kNoBrick);
  // The band voxels counted over each brick move with it, so that the next mask may count only what changed
  // (GpuRayMask::carriesOverScroll; a run over every voxel counts from zero anyway).
  recordGridShift(cmd, shiftPass, mNeeded, scratch, mBrickDims, 4, brickShift, 0u);
}

void BrickPool::noteFrame(std::uint64_t activeBricks, std::uint64_t overflowBricks) {
  if (overflowBricks) mGrowTo = poolBricksFor(activeBricks, mBrickDims);
}

std::uint64_t BrickPool::takeRegrowth() { return std::exchange(mGrowTo, 0); }

BrickPages BrickPool::pages() const {
  BrickPages p{};
  for (int k = 0; k < RTSDF_BRICK_PAGES; ++k) {
    p.values[k] = mValues[k] ? &mValues[k] : &mPlaceholder;
    p.votes[k] = mVotes[k] ? &mVotes[k] : &mPlaceholder;
  }
  return p;
}

std::vector<std::uint32_t> BrickPool::readSlots() const {
  std::vector<std::uint32_t> slots(mSlots.size() / 4);
  download(mCtx, mSlots, slots.data(), slots.size() * 4);
  return slots;
}

std::vector<float> BrickPool::readValues() const {
  std::vector<float> values(mPoolBricks * gpu::shared::kBrickVoxels);
  std::size_t at = 0;
  for (const Buffer& page : mValues) {
    if (!page) continue;
    download(mCtx, page, values.data() + at, page.size());
    at += page.size() / 4;
  }
  return values;
}

} // namespace rtsdf
