#include "sdf/pipeline/PipelineProbe.h"

#include "sdf/pipeline/BrickPool.h"
#include "sdf/pipeline/FieldPasses.h"
#include "sdf/pipeline/GpuRayMask.h"
#include "sdf/pipeline/InstanceMotion.h"

namespace rtsdf {

std::vector<std::uint32_t> PipelineProbe::brickSlots() const {
  mPipe.waitForFrame();
  return mPipe.mPool->readSlots();
}

std::vector<float> PipelineProbe::brickValues() const {
  mPipe.waitForFrame();
  return mPipe.mPool->readValues();
}

std::vector<std::uint32_t> PipelineProbe::refinedVoxels() const {
  mPipe.waitForFrame();
  // A frame that skipped the mask refined nothing (the list is the last run's).
  return mPipe.mPlan.refine ? mPipe.mMask->readRefinedVoxels(mPipe.mFrame) : std::vector<std::uint32_t>{};
}

std::vector<std::uint32_t> PipelineProbe::movedOnlyCoarse() const {
  mPipe.waitForFrame();
  return mPipe.mPlan.refine ? mPipe.mMask->readMovedOnlyCoarse(mPipe.mFrame) : std::vector<std::uint32_t>{};
}

std::vector<std::uint32_t> PipelineProbe::rewrittenVoxels() const {
  mPipe.waitForFrame();
  return mPipe.mPlan.refine ? mPipe.mMask->readRewrittenVoxels(mPipe.mFrame) : std::vector<std::uint32_t>{};
}

std::vector<glm::uvec2> PipelineProbe::coarseState() const {
  mPipe.waitForFrame();
  return mPipe.mMask->readCoarseState();
}

const gpu::shared::MaskParams& PipelineProbe::lastMaskParams() const { return mPipe.mMask->lastParams(); }

const std::vector<gpu::shared::MovedBox>& PipelineProbe::lastMovedBoxes() const {
  return mPipe.mMotion->lastBoxes();
}

std::vector<std::uint32_t> PipelineProbe::coarseBlockMax() const {
  mPipe.waitForFrame();
  return mPipe.mFields->readCoarseBlockMax();
}

std::vector<std::uint32_t> PipelineProbe::changedCoarseBlocks() const {
  mPipe.waitForFrame();
  return mPipe.mFields->readChangedCoarseBlocks();
}

std::vector<std::uint32_t> PipelineProbe::upsampledBlocks() const {
  mPipe.waitForFrame();
  return mPipe.mFields->readUpsampledBlocks();
}

std::vector<std::uint32_t> PipelineProbe::coarseSeeds() const {
  mPipe.waitForFrame();
  return mPipe.mFields->readCoarseSeeds();
}

CoarseRegionLists PipelineProbe::coarseRegion() const {
  mPipe.waitForFrame();
  return mPipe.mFields->readCoarseRegionLists();
}

gpu::shared::MaskRegion PipelineProbe::lastMaskRegion() const {
  mPipe.waitForFrame();
  return mPipe.mMask->lastRegion();
}

bool PipelineProbe::coarseOverChange() const { return mPipe.mPlan.coarse && mPipe.mFields->lastCoarseOverChange(); }

} // namespace rtsdf
