#include "sdf/SdfPipeline.h"

#include "grid/VdbIO.h"

#include "sdf/cascade/CascadeScene.h"
#include "sdf/coarse/CoarseScroll.h"
#include "sdf/cascade/SingleBoxCheck.h"
#include "sdf/refine/RefineCpu.h"
#include "sdf/pipeline/BrickPool.h"
#include "sdf/pipeline/FieldPasses.h"
#include "sdf/pipeline/FrameRecorder.h"
#include "sdf/pipeline/GpuRayMask.h"
#include "sdf/pipeline/GridShift.h"
#include "sdf/pipeline/InstanceMotion.h"
#include "util/Error.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

namespace rtsdf {

SdfPipeline::SdfPipeline(const gpu::VulkanContext& ctx, const Scene& scene, const Bounds& bounds,
                         const PipelineSettings& given)
    : SdfPipeline(ctx, scene, pipelineGrids(bounds, given), withLengthsResolved(given, bounds)) {
  // One box over the whole scene: say when it is too coarse for the scene (what the cascades are for).
  const std::string advice = singleBoxAdvice(scene, mCoarseSpec, mFineSpec);
  if (!advice.empty()) spdlog::warn("{}", advice);
}

SdfPipeline::SdfPipeline(const gpu::VulkanContext& ctx, const Scene& scene,
                         const std::pair<GridSpec, GridSpec>& grids, const PipelineSettings& given)
    : mCtx(ctx), mSettings(withLengthsResolved(given, grids.second.voxelSize)) {
  const PipelineSettings& s = mSettings; // lengths in scene units from here on
  s.validate();
  if (s.cascades != 1)
    throw SettingError("cascades", fmt::format("cascades {}: one SdfPipeline is one box; a bake builds cascade levels "
                                               "(CascadeSet), shading, animation and the viewer use one box so far "
                                               "(cascades 1)", s.cascades));
  requirePipelineGrids(grids.first, grids.second, s);
  const bool cpuShaders = s.shaderTarget == ShaderTarget::Device ? ctx.info().type == VK_PHYSICAL_DEVICE_TYPE_CPU
                                                                 : s.shaderTarget == ShaderTarget::Cpu;
  // The settings in effect (settings()): the target and the search resolved for this device.
  mSettings.shaderTarget = cpuShaders ? ShaderTarget::Cpu : ShaderTarget::Gpu;
  if (s.closestSearch == ClosestSearch::Auto)
    mSettings.closestSearch = cpuShaders ? ClosestSearch::Cell : ClosestSearch::Voxel;
  const bool cellSearch = s.mode == RefineMode::Closest && mSettings.closestSearch == ClosestSearch::Cell;
  // Everything is checked before anything is allocated (the brick pool, sized by the first frame's band, then).
  mMemory = estimatePipelineMemory(grids, s, sceneGpuSize(scene));
  checkPipelineMemory(mMemory, memoryLimits(ctx.info()));
  mCoarseSpec = mMemory.coarse;
  mFineSpec = mMemory.fine;
  const RefineParts parts = refinePartsFor(longestFineRuns(mCoarseSpec, mFineSpec), cellSearch);
  // The refinement's invocations (refineParts per listed coarse voxel) are counted in 32 bits.
  if (double(mCoarseSpec.voxelCount()) * parts.total() > 4294967295.0)
    throw SettingError("coarse resolution", fmt::format("SdfPipeline: coarse grid {} over fine grid {}: too many "
                                                        "refinement invocations; lower the fine resolution or raise "
                                                        "the coarse one", mCoarseSpec.describe(),
                                                        mFineSpec.describe()));
  mBvh = std::make_unique<GpuSceneBvh>(ctx, scene, frameOrigin());
  mBvh->setUnionReach(unionReach());
  placeSeedsOnLattice();
  mFields = std::make_unique<FieldPasses>(ctx, mCoarseSpec, mFineSpec, mSettings, parts,
                                          ClosestRefinePass::Variant{s.rays > 0, cellSearch, cpuShaders});
  mMask = std::make_unique<GpuRayMask>(ctx, mCoarseSpec, mFineSpec, mSettings, parts.total());
  mMotion = std::make_unique<InstanceMotion>(ctx, scene, motionReach());
  mPool = std::make_unique<BrickPool>(ctx, mFineSpec);
  mRecorder = std::make_unique<FrameRecorder>(ctx);
  restartHistory();
}

void SdfPipeline::restartHistory() {
  waitForFrame();
  gpu::CommandBuffer cmd(mCtx);
  mPool->recordClear(cmd.handle());
  mMask->recordClear(cmd.handle());
  mFields->recordClear(cmd.handle());
  mMotion->recordClear(cmd.handle());
  cmd.submitAndWait();
  mBvh->forgetUpload();
  mFrame = 0;
  mMaskFrame = 0;
  mPoolReset = mScrolled = mViewChanged = false; // a first frame runs everything over every voxel
  mRecordingInterrupted = false;
}

Bounds SdfPipeline::unionReach() const {
  Bounds box;
  box.add(glm::dvec3(-mFineSpec.voxelSize));
  box.add(glm::dvec3(mFineSpec.dims + 1) * mFineSpec.voxelSize);
  return box;
}

Bounds SdfPipeline::motionReach() const {
  // An instance moving farther from the grid than the band and the mask's reach pad changes none of its fields
  // (a cascade level keeps every moving instance of the world, but most move far from it).
  const double margin = double(mSettings.band) + mMask->reachPad();
  Bounds reach;
  reach.add(mFineSpec.origin - margin);
  reach.add(mFineSpec.origin + glm::dvec3(mFineSpec.dims) * mFineSpec.voxelSize + margin);
  return reach;
}

std::uint64_t SdfPipeline::scrollScratchBytes() const {
  return scrollScratchBytesFor(mCoarseSpec, mFineSpec, mSettings.fineStorage);
}

void SdfPipeline::scroll(const std::pair<GridSpec, GridSpec>& grids, const gpu::Buffer& scratch, const Scene* recut) {
  const std::optional<glm::ivec3> shift = scrollShift({mCoarseSpec, mFineSpec}, grids);
  if (!shift)
    throw Error(fmt::format("SdfPipeline: cannot scroll from coarse {} / fine {} to coarse {} / fine {} (not the same "
                            "grids moved by whole bricks)", mCoarseSpec.describe(), mFineSpec.describe(),
                            grids.first.describe(), grids.second.describe()));
  if (scratch.size() < scrollScratchBytes())
    throw Error(fmt::format("SdfPipeline: a scroll scratch of {} bytes, {} needed", scratch.size(),
                            scrollScratchBytes()));
  PipelineMemory memory = mMemory;
  if (recut) { // checked before anything moves
    memory = estimatePipelineMemory(grids, mSettings, sceneGpuSize(*recut));
    PipelineMemory withPool = memory;
    withPool.deviceBytes += BrickPool::deviceBytesFor(mPool->capacity());
    checkPipelineMemory(withPool, memoryLimits(mCtx.info()));
  }
  waitForFrame(); // the frame's buffers are about to move, and the pool's slots are read back
  const glm::ivec3 fineShift = *shift * (mFineSpec.dims / mCoarseSpec.dims);
  // A GPU moves the grids by a dispatch each, a CPU device by transfers (recordGridShift).
  if (!mGridShift && mCtx.info().type != VK_PHYSICAL_DEVICE_TYPE_CPU)
    mGridShift = std::make_unique<GridShiftPass>(mCtx);
  gpu::CommandBuffer cmd(mCtx);
  mMask->recordScroll(cmd.handle(), grids.first, grids.second, *shift, scratch, mGridShift.get());
  mFields->recordScroll(cmd.handle(), grids, *shift, scratch, recut != nullptr, mGridShift.get());
  mPool->recordScroll(cmd.handle(), fineShift / RTSDF_BRICK, scratch, mGridShift.get());
  if (mFailNextScroll) {
    mFailNextScroll = false;
    throw Error("SdfPipeline: a failure injected into the scroll (PipelineFaults)");
  }
  cmd.submitAndWait();
  mMemory = memory;
  mCoarseSpec = mMemory.coarse = grids.first;
  mFineSpec = mMemory.fine = grids.second;
  if (recut) {
    mBvh = std::make_unique<GpuSceneBvh>(mCtx, *recut, frameOrigin());
    mBvh->setUnionReach(unionReach());
    placeSeedsOnLattice();
    mMotion->setScene(*recut);
  } else {
    mBvh->setFrameOrigin(frameOrigin());
  }
  mMotion->setReach(motionReach());
  mScrolled = true;
}

void SdfPipeline::placeSeedsOnLattice() {
  // A grid on the world's seed lattice (a cascade level's) voxelizes from the world's origin: each voxel's seed is
  // then decided by its world voxel alone, so those a scroll keeps equal a full build's (CoarseSdfSettings).
  if (seedLatticeCell(mCoarseSpec)) mBvh->setSeedOrigin(glm::dvec3(0.0));
}

SdfPipeline::~SdfPipeline() {
  // The buffers must outlive a frame still on the GPU; a failed wait has nowhere to go.
  try {
    if (mRecorder) mRecorder->wait();
  } catch (const std::exception&) {
  }
}

glm::ivec3 SdfPipeline::brickDims() const { return mPool->brickDims(); }

std::uint64_t SdfPipeline::poolBricks() const { return mPool->capacity(); }

std::uint64_t SdfPipeline::firstPoolSize(double time) {
  if (mSettings.band <= 0.0) return 0; // nothing is refined
  mMotion->checkPlacement(time);
  // The coarse SDF of the first frame, once more: the pool is sized by the bricks under its band.
  gpu::CommandBuffer cmd(mCtx);
  mBvh->recordUpdate(cmd.handle(), time);
  mFields->recordCoarse(cmd.handle(), nullptr, *mBvh);
  cmd.submitAndWait();
  const std::vector<float> coarse = mFields->readCoarse();
  const std::uint64_t active = bandBricksCpu(coarse, mCoarseSpec, mFineSpec, mSettings.band).size();
  return poolBricksFor(active, brickDims());
}

void SdfPipeline::preparePool(double time) {
  if (mRecorder->awaitingFinish()) { // the previous frame's statistics are lost, but not a full pool
    waitForFrame();
    const GpuRayMask::Counts n = mMask->counts();
    mPool->noteFrame(n.activeBricks, n.overflowBricks);
  }
  const std::uint64_t regrow = mPool->takeRegrowth();
  if (mFrame == 0)
    allocatePool(mSettings.poolBricks > 0 ? std::min<std::uint64_t>(std::uint64_t(mSettings.poolBricks),
                                                                    mPool->gridBricks())
                                          : firstPoolSize(time));
  else if (regrow)
    allocatePool(regrow);
}

void SdfPipeline::allocatePool(std::uint64_t bricks) {
  waitForFrame(); // the pool's buffers are the frame's
  mPool->allocate(bricks, mMemory, mMask->coarseState());
  mPoolReset = true;
}

FrameStats SdfPipeline::runFrame(double time) {
  submitFrame(time);
  return finishFrame();
}

void SdfPipeline::submitFrame(double time) {
  mRecorder->wait(); // one frame in flight: the previous one's buffers are this one's
  if (mRecordingInterrupted) restartHistory();
  preparePool(time);
  const auto t0 = FrameRecorder::Clock::now();
  // The host's work grows with the instances only: the GPU places their triangles.
  mMotion->checkPlacement(time);
  mRecordingInterrupted = true; // until submitted: a throw from here on leaves the host's state ahead of the GPU's
  ++mFrame;
  FrameStats stats;
  stats.time = time;
  // What moved since the previous frame (the first frame refines every voxel: all are new to the mask).
  const std::uint32_t moved = std::uint32_t(mMotion->advance(mFrame, time, frameOrigin()).size());
  stats.movedInstances = moved;
  // One command buffer for the whole frame, reused frame after frame: nothing is read back inside it.
  const VkCommandBuffer cmd = mRecorder->begin();
  gpu::GpuProfiler* profiler = mRecorder->profiler();
  // The frame's only uploads, recorded with it: the moved boxes (at most RTSDF_MAX_MOVED_BOXES x 32 bytes; barrier:
  // recordMask's) and the instance transforms (recordUpdate).
  mMotion->recordUpload(cmd);
  mBvh->recordUpdate(cmd, time);
  // Only the passes whose inputs changed: the others' buffers hold what they would write again. The previous frame
  // is finished (waited for above), so the mask's last counts are on the host.
  FrameChanges changes;
  changes.first = mFrame == 1;
  changes.moved = moved > 0;
  changes.poolReset = mPoolReset;
  changes.scrolled = mScrolled;
  changes.scrollMovedCoarse = mScrolled && mFields->scrollMovedCoarse();
  changes.scrollCarriesMask = mScrolled && mMask->carriesOverScroll();
  changes.viewChanged = mViewChanged;
  changes.viewLimited = mView.has_value();
  // Listed for a walk: the band voxels out of the view's reach written again are listed too, and a run skipped keeps
  // what they hold.
  if (!changes.first) { // before the first frame nothing has been read back
    const GpuRayMask::Counts last = mMask->counts();
    changes.lastListed = last.refineList > last.outOfView;
  }
  mPlan = planFrame(changes, mSettings);
  mPoolReset = false;
  mScrolled = false;
  mViewChanged = false;
  stats.skippedPasses = skippedPasses(mPlan, mSettings);
  stats.fieldChanged = mPlan.coarse || mPlan.refine || mPlan.upsample;
  if (mPlan.coarse) {
    // Only instances moved: the coarse SDF over what their seeds reach. After a scroll, their seeds and those that
    // entered are voxelized, then the whole transform runs.
    const CoarseVoxelBox change = movedSeedBox(mMotion->lastBoxes(), mCoarseSpec.inFrame(frameOrigin()));
    mFields->recordCoarse(cmd, profiler, *mBvh, mPlan.coarseMovedSeeds ? &change : nullptr);
  }
  if (mFailNextRecording) {
    mFailNextRecording = false;
    throw Error("SdfPipeline: a failure injected into the frame's recording (PipelineFaults)");
  }
  if (mPlan.mask) {
    // The band out of the view's reach is written again everywhere where bricks may have taken new slots anywhere,
    // else where the coarse SDF changed (outOfViewRewritten).
    using namespace gpu::shared;
    const bool anywhere = changes.first || changes.poolReset || changes.scrolled || changes.viewChanged;
    const int flags = (anywhere ? kMaskRelistOutOfView : 0) | (mPlan.coarse ? kMaskCoarseRebuilt : 0) |
                      (mSettings.mode == RefineMode::Closest ? kMaskMotionKeepsSettled : 0) |
                      (mPlan.maskOverChange ? kMaskRegionOnly : 0) | (mPlan.maskOverBlocks ? kMaskBlockList : 0);
    // Over what changed: the band voxels a moving box can come within reach of (movedWithinReach: |c| <= band).
    const CoarseVoxelBox near = movedReachBox(mMotion->lastBoxes(), mCoarseSpec.inFrame(frameOrigin()),
                                              mSettings.band + mMask->reachPad());
    mMask->recordMask(cmd, profiler, ++mMaskFrame, moved, mFields->coarseBuffer(), mMotion->buffer(),
                      mFields->changedBoxBuffer(), flags, *mPool, near, &mFields->changedBlocksBuffer());
  }
  mFields->recordFine(cmd, profiler, mFields->refineParams(mFrame, *mPool, moved), *mBvh, *mMask, *mPool,
                      mMotion->buffer(), mPlan.refine, mPlan.upsample, mPlan.upsampleChanged);
  // A first frame cleared the dense fine SDF, a scroll shifted it: every voxel may differ from a copy of the last.
  mLastWrites = mFields->denseWrites(*mMask, mPlan.refine, changes.first || changes.scrolled);
  mLastWrites.frame = mFrame;
  gpu::computeBarrier(cmd);
  if (mPlan.mask) mMask->recordCountsReadback(cmd, *mPool);
  mRecorder->submit(stats, t0);
  mRecordingInterrupted = false;
}

FrameStats SdfPipeline::finishFrame() {
  return mRecorder->finish([this](FrameStats& stats) {
    const GpuRayMask::Counts counts = mMask->counts();
    stats.maskFineVoxels = counts.maskedFine;
    stats.maskCoarseVoxels = counts.coarse;
    stats.refinedFineVoxels = mPlan.refine ? counts.refinedFine : 0; // a skipped mask left the last run's counts
    stats.cutVoxels = mPlan.refine ? counts.cutVoxels : 0;
    stats.movedKeptVoxels = mPlan.refine ? counts.movedKept : 0;
    stats.nearHalfVoxels = mPlan.refine ? counts.nearHalf : 0;
    stats.nearHalfKept = mPlan.refine ? counts.nearHalfKept : 0;
    stats.activeBricks = counts.activeBricks;
    stats.overflowBricks = counts.overflowBricks;
    stats.poolBricks = mPool->capacity();
    stats.upsampledFineVoxels = mFields->lastUpsampledVoxels();
    stats.maskVisitedVoxels = mPlan.mask && mSettings.band > 0.0 ? mMask->lastVisitedVoxels() : 0;
    stats.coarseRebuiltVoxels = !mPlan.coarse                     ? 0
                                : mFields->lastCoarseOverChange() ? mFields->readCoarseRegion().counts.z
                                                                  : mCoarseSpec.voxelCount();
    stats.coarseVoxelizedVoxels = mPlan.coarse ? mFields->lastCoarseVoxelized() : 0;
    stats.deviceBytes = mMemory.deviceBytes + BrickPool::deviceBytesFor(mPool->capacity());
    if (mPlan.mask) mPool->noteFrame(counts.activeBricks, counts.overflowBricks);
  });
}

void SdfPipeline::waitForFrame() const { mRecorder->wait(); }

const gpu::Buffer& SdfPipeline::fineBuffer() const {
  if (!mFields->dense())
    throw Error("SdfPipeline: the fine SDF is kept sparse (fine storage 'sparse'): there is no dense fine buffer");
  return mFields->fineBuffer();
}

gpu::shared::ChangedBox SdfPipeline::changedCoarseBox() const { return mFields->readChangedBox(); }

const gpu::Buffer& SdfPipeline::coarseBuffer() const { return mFields->coarseBuffer(); }

GpuBrickField SdfPipeline::brickField() const {
  if (mFields->dense())
    throw Error("SdfPipeline: the fine SDF is kept dense (fine storage 'dense'): its bricks hold only the band");
  return {mFields->coarseBuffer(), mMask->fineToCoarse(), mPool->slots(), mFields->samplingParams(), mPool->pages()};
}

std::vector<float> SdfPipeline::coarseField() const {
  waitForFrame();
  return mFrame ? mFields->readCoarse() : std::vector<float>{};
}

RayMask SdfPipeline::rayMask() const {
  if (mFrame == 0 || mSettings.band <= 0.0) return RayMask{};
  waitForFrame();
  return buildRayMask(mFields->readCoarse(), mCoarseSpec, mFineSpec, mSettings.band);
}

void SdfPipeline::setViewReach(const ViewReach* reach) {
  const std::optional<ViewReach> next = reach ? std::optional<ViewReach>(*reach) : std::nullopt;
  if (next == mView) return;
  mView = next;
  mViewChanged = true;
  mMask->setViewReach(reach);
}

std::vector<std::uint32_t> SdfPipeline::outOfViewVoxels() const {
  if (mFrame == 0 || mSettings.band <= 0.0) return {};
  waitForFrame();
  return mMask->readOutOfViewVoxels(mMaskFrame);
}

openvdb::FloatGrid::Ptr SdfPipeline::levelSet(float band) const {
  const std::vector<float> fine = fineField();
  if (mSettings.band <= 0.0) return denseToLevelSet(fine, mFineSpec, band);
  const std::vector<std::uint32_t> outOfView = outOfViewVoxels();
  std::vector<std::pair<std::uint64_t, float>> refined;
  for (const std::uint32_t packed : rayMask().fineVoxels) {
    if (std::binary_search(outOfView.begin(), outOfView.end(), packed)) continue; // the coarse SDF's value
    const std::uint64_t i = mFineSpec.linear(int(packed & 1023u), int((packed >> 10) & 1023u), int(packed >> 20 & 1023u));
    if (std::fabs(fine[i]) <= band) refined.emplace_back(i, fine[i]);
  }
  return activeVoxelsToLevelSet(std::move(refined), mFineSpec, band);
}

std::vector<float> SdfPipeline::fineField() const {
  waitForFrame();
  if (mFields->dense()) return mFields->readDenseFine();
  if (mFrame == 0) return std::vector<float>(mFineSpec.voxelCount(), 0.0f);
  // The grids as the GPU sees them: the same upsampled values, bit for bit.
  return resolveFineCpu(coarseField(), mCoarseSpec.inFrame(frameOrigin()), mFineSpec.inFrame(frameOrigin()),
                        float(mSettings.band), mPool->readSlots(), mPool->readValues());
}

} // namespace rtsdf
