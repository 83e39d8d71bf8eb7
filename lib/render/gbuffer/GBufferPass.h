#pragma once
/// @file GBufferPass.h
/// @brief Primary visibility on the GPU (GBufferPass, gbuffer.comp): the G-buffer every later pass of the renderer
///        reads. Buffers are bound at the indices render/gbuffer/GBufferParams.h names. Its CPU counterpart is
///        Embree's primary rays (render/RayTracedShadows.h).
#include "gpu/ComputePass.h"
#include "gpu/Profiler.h"
#include "gpu/Resources.h"
#include "render/gbuffer/GBufferParams.h"
#include "sdf/scenebvh/GpuSceneBvh.h"

namespace rtsdf {

/// @brief The G-buffer on the GPU: vec4 position (w: ray distance, < 0 on a miss) and vec4 normal (w: instance).
struct GpuGBuffer {
  int width = 0, height = 0;
  gpu::Buffer position, normal;
  void reserve(const gpu::VulkanContext& ctx, int width, int height);
};

/// @brief The work groups of 8x8 pixels over a @a width x @a height image: the dispatch of every pass that runs per
///        pixel of the G-buffer.
inline glm::uvec3 imageGroups(int width, int height) {
  return {gpu::groupsFor(std::uint64_t(width), 8), gpu::groupsFor(std::uint64_t(height), 8), 1u};
}

/// @brief Primary visibility: one camera ray per pixel through the scene's BVH.
class GBufferPass : gpu::ComputePass {
public:
  static constexpr const char* kName = "GBufferPass";
  struct Inputs { const GpuSceneBvh& bvh; };
  struct Outputs { const GpuGBuffer& gbuffer; }; ///< reserved for the camera's image size
  using Params = gpu::shared::CameraParams;
  explicit GBufferPass(const gpu::VulkanContext& ctx)
      : ComputePass(ctx, "gbuffer.comp", gpu::shared::kGBufferBindingCount, sizeof(Params)) {}
  /// @throw Error when the G-buffer is not reserved for the camera's image size.
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& camera) const;
};

} // namespace rtsdf
