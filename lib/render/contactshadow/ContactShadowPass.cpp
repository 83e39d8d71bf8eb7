#include "render/contactshadow/ContactShadowPass.h"

#include "util/Error.h"

#include <array>

namespace rtsdf {
using gpu::Buffer;
using namespace gpu::shared;

void ContactShadowPass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                                const Params& params) const {
  const GpuGBuffer& g = in.gbuffer;
  if (params.rays == 0u) throw Error("ContactShadowPass: no rays to trace");
  if (g.width != params.image.x || g.height != params.image.y)
    throw Error("ContactShadowPass: the image size is not the G-buffer's");
  gpu::ProfileScope scope(profiler, cmd, kName);
  std::array<gpu::Binding, kContactShadowBindingCount> b;
  in.bvh.bindTo(b);
  b[kContactShadowBindingPositions] = &g.position;
  b[kContactShadowBindingNormals] = &g.normal;
  b[kContactShadowBindingLights] = &in.lights;
  b[kContactShadowBindingVisibility] = &out.visibility;
  mPipeline.dispatch(cmd, b, &params, imageGroups(g.width, g.height));
  gpu::computeBarrier(cmd);
}

} // namespace rtsdf
