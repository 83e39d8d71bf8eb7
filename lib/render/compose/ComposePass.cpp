#include "render/compose/ComposePass.h"

#include "util/Error.h"

#include <fmt/format.h>
#include <array>

namespace rtsdf {
using gpu::Buffer;
using namespace gpu::shared;

ComposePass::ComposePass(const gpu::VulkanContext& ctx)
    : ComputePass(ctx, "compose.comp", kComposeBindingCount, 0),
      mParams(ctx, sizeof(ComposeParams), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, Buffer::Memory::Device,
              "compose parameters") {}

void ComposePass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                          const Params& params) const {
  if (in.gbuffer.width != params.image.x || in.gbuffer.height != params.image.y)
    throw Error(fmt::format("ComposePass: a {}x{} picture from a {}x{} G-buffer", params.image.x, params.image.y,
                            in.gbuffer.width, in.gbuffer.height));
  gpu::ProfileScope scope(profiler, cmd, kName);
  gpu::recordUpload(cmd, mParams, &params, sizeof(params));
  gpu::computeBarrier(cmd);
  std::array<gpu::Binding, kComposeBindingCount> b;
  b[kComposeBindingPositions] = &in.gbuffer.position;
  b[kComposeBindingNormals] = &in.gbuffer.normal;
  b[kComposeBindingVisibility] = &in.visibility;
  b[kComposeBindingLights] = &in.lights;
  b[kComposeBindingFine] = &in.fine;
  b[kComposeBindingCoarse] = &in.coarse;
  b[kComposeBindingOverlay] = &in.overlay;
  b[kComposeBindingParams] = &mParams;
  b[kComposeBindingOutput] = &out.pixels;
  mPipeline.dispatch(cmd, b, nullptr, imageGroups(params.image.x, params.image.y));
  gpu::computeBarrier(cmd);
}

} // namespace rtsdf
