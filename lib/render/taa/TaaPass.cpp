#include "render/taa/TaaPass.h"

#include "render/gbuffer/GBufferPass.h" // imageGroups: the per-pixel dispatch

#include <array>

namespace rtsdf {
using gpu::Buffer;
using namespace gpu::shared;

void TaaPass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                      const Params& params) const {
  gpu::ProfileScope scope(profiler, cmd, kName);
  std::array<gpu::Binding, kTaaBindingCount> b;
  b[kTaaBindingCurrent] = &in.current;
  b[kTaaBindingHistory] = &out.history;
  mPipeline.dispatch(cmd, b, &params, imageGroups(params.image.x, params.image.y));
  gpu::computeBarrier(cmd);
}

} // namespace rtsdf
