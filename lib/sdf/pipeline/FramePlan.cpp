#include "sdf/pipeline/FramePlan.h"

#include "sdf/coarse/CoarseSdf.h"
#include "sdf/mask/MaskPasses.h"
#include "sdf/refine/RefinePasses.h"

namespace rtsdf {

FramePlan planFrame(const FrameChanges& c, const PipelineSettings& s) {
  FramePlan plan;
  if (s.fullRebuild || s.fullRecompute || c.first) return plan;
  const bool refining = s.band > 0.0;
  const bool dueEveryFrame = settleFramesFor(s) == 0 || refreshPeriodFor(s) > 0;
  plan.coarse = c.moved || c.scrolled;
  plan.mask = refining && (plan.coarse || c.poolReset || c.viewChanged || c.lastListed || dueEveryFrame);
  plan.refine = plan.mask;
  plan.upsample = s.fineStorage == FineStorage::Dense && (plan.coarse || c.poolReset);
  plan.upsampleChanged = plan.upsample && !c.poolReset && (c.scrolled ? c.scrollMovedCoarse : c.moved);
  plan.coarseMovedSeeds = c.moved && coarseBuiltOverChanges(s);
  plan.coarseOverChange = plan.coarseMovedSeeds && !c.scrolled;
  const bool scrollKept = !c.scrolled || (c.scrollMovedCoarse && c.scrollCarriesMask);
  plan.maskOverChange = plan.mask && !c.poolReset && scrollKept && !c.viewChanged && !c.viewLimited &&
                        settleFramesFor(s) > 0 && refreshPeriodFor(s) == 0;
  plan.maskOverBlocks = plan.maskOverChange && c.scrolled;
  return plan;
}

bool coarseBuiltOverChanges(const PipelineSettings& s) {
  return s.coarseMethod == CoarseMethod::Edt && !s.fullRebuild && !s.fullRecompute;
}

std::vector<std::string> skippedPasses(const FramePlan& plan, const PipelineSettings& s) {
  std::vector<std::string> names;
  if (!plan.coarse)
    names.insert(names.end(), {VoxelizePass::kName, coarseTransformPass(s.coarseMethod), CoarseDistancePass::kName});
  const bool refining = s.band > 0.0;
  if (!plan.mask && refining) names.insert(names.end(), {MaskCompactPass::kName, BrickAllocPass::kName});
  if (!plan.mask) names.emplace_back(MaskDispatchPass::kName);
  if (!plan.refine && refining)
    names.emplace_back(s.mode == RefineMode::Rays ? RayRefinePass::kName : ClosestRefinePass::kName);
  if (!plan.upsample && s.fineStorage == FineStorage::Dense) names.emplace_back(UpsamplePass::kName);
  return names;
}

} // namespace rtsdf
