#pragma once
/// @file ComposePass.h
/// @brief The picture for a window, made on the GPU (ComposePass, compose.comp). Buffers are bound at the indices
///        render/compose/ComposeParams.h names; the CPU copy is ComposeCpu.h.
#include "gpu/ComputePass.h"
#include "gpu/Profiler.h"
#include "gpu/Resources.h"
#include "render/compose/ComposeParams.h"
#include "render/gbuffer/GBufferPass.h"

namespace rtsdf {

/// @brief The picture for a window (render/compose/ComposeParams.h): the lit scene as composeImage and displayImage
///        make it, or a horizontal slice through the fine SDF or the ray mask, under a strip of text; one packed 8-bit
///        pixel per uint, in the byte order of ComposeParams::coarseDims.w (a swapchain's format).
class ComposePass : gpu::ComputePass {
public:
  static constexpr const char* kName = "ComposePass";
  struct Inputs {
    const GpuGBuffer& gbuffer;
    const gpu::Buffer& visibility; ///< light-major (after TAA)
    const gpu::Buffer& lights;
    const gpu::Buffer& fine;       ///< dense fine SDF (any buffer when params.fineDims.x is 0)
    const gpu::Buffer& coarse;     ///< dense coarse SDF (read by the mask view)
    const gpu::Buffer& overlay;    ///< params.fineDims.w rows of text coverage, one byte per pixel
  };
  struct Outputs { const gpu::Buffer& pixels; }; ///< width * height uints
  using Params = gpu::shared::ComposeParams;     ///< recorded into the pass's own parameter buffer
  explicit ComposePass(const gpu::VulkanContext& ctx);
  /// @throw Error when the G-buffer's size differs from params.image.
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;

private:
  gpu::Buffer mParams;
};

} // namespace rtsdf
