#include "sdf/RefinePasses.h"

#include <array>

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

void UpsamplePass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                           const Params& params) const {
  gpu::ProfileScope scope(profiler, cmd, kName);
  std::array<gpu::Binding, kUpsampleBindingCount> b;
  b[kUpsampleBindingCoarse] = &in.coarse;
  b[kUpsampleBindingFine] = &out.fine;
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
  b[kRefineBindingHistory] = &out.history;
  b[kRefineBindingVotes] = &out.votes;
  b[kRefineBindingLastFrame] = &out.lastFrame;
  mPipeline.dispatchIndirect(cmd, b, &params, in.dispatch);
  gpu::computeBarrier(cmd);
}

} // namespace rtsdf
