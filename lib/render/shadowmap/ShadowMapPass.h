#pragma once
/// @file ShadowMapPass.h
/// @brief Shadow maps on the GPU (ShadowMapPass: shadow_map.comp builds, shadow_lookup.comp filters). Buffers are
///        bound at the indices render/shadowmap/ShadowMapParams.h names; the CPU copies are ShadowMapCpu.h.
#include "gpu/ComputePass.h"
#include "gpu/Profiler.h"
#include "gpu/Resources.h"
#include "render/gbuffer/GBufferPass.h"
#include "render/shadowmap/ShadowMapParams.h"
#include "sdf/scenebvh/GpuSceneBvh.h"

#include <vector>

namespace rtsdf {

/// @brief Shadow maps (the baseline games use): a depth map per light (orthographic for directional lights,
///        a cube map for sphere lights), then PCF lookups per pixel.
class ShadowMapPass {
public:
  static constexpr const char* kBuildName = "ShadowMapBuildPass";
  static constexpr const char* kLookupName = "ShadowMapLookupPass";
  struct Inputs {
    const GpuSceneBvh& bvh;
    const GpuGBuffer& gbuffer;
    const gpu::Buffer& lights;
    const gpu::Buffer& maps; ///< the ShadowMapParams of every light, on the GPU
  };
  /// Depth maps (6 N^2 floats per light) and the visibility (light-major).
  struct Outputs { const gpu::Buffer &depth, &visibility; };
  using Params = std::vector<gpu::shared::ShadowMapParams>; ///< one per light (host copy of Inputs::maps)
  explicit ShadowMapPass(const gpu::VulkanContext& ctx);
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& maps) const;

private:
  gpu::ComputePipeline mBuild, mLookup;
};

} // namespace rtsdf
