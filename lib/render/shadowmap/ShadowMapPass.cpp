#include "render/shadowmap/ShadowMapPass.h"

#include <array>

namespace rtsdf {
using gpu::Buffer;
using namespace gpu::shared;

ShadowMapPass::ShadowMapPass(const gpu::VulkanContext& ctx)
    : mBuild(ctx, "shadow_map.comp", kShadowMapBindingCount, sizeof(ShadowMapParams)),
      mLookup(ctx, "shadow_lookup.comp", kShadowLookupBindingCount, sizeof(ShadowMapParams)) {}

void ShadowMapPass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                            const Params& maps) const {
  if (maps.empty()) return;
  {
    gpu::ProfileScope scope(profiler, cmd, kBuildName);
    std::array<gpu::Binding, kShadowMapBindingCount> b;
    in.bvh.bindTo(b);
    b[kShadowMapBindingLights] = &in.lights;
    b[kShadowMapBindingDepth] = &out.depth;
    for (const ShadowMapParams& m : maps) {
      const std::uint32_t n = std::uint32_t(m.info.x);
      const std::uint32_t faces = std::uint32_t(m.info.z) == kLightSphere ? 6u : 1u;
      mBuild.dispatch(cmd, b, &m, {gpu::groupsFor(n, 8), gpu::groupsFor(n, 8), faces});
    }
    gpu::computeBarrier(cmd);
  }
  gpu::ProfileScope scope(profiler, cmd, kLookupName);
  std::array<gpu::Binding, kShadowLookupBindingCount> b;
  b[kShadowLookupBindingPositions] = &in.gbuffer.position;
  b[kShadowLookupBindingNormals] = &in.gbuffer.normal;
  b[kShadowLookupBindingDepth] = &out.depth;
  b[kShadowLookupBindingLights] = &in.lights;
  b[kShadowLookupBindingMaps] = &in.maps;
  b[kShadowLookupBindingVisibility] = &out.visibility;
  mLookup.dispatch(cmd, b, &maps[0], imageGroups(in.gbuffer.width, in.gbuffer.height));
  gpu::computeBarrier(cmd);
}

} // namespace rtsdf
