#pragma once
/// @file TaaPass.h
/// @brief Temporal accumulation on the GPU (TaaPass, taa.comp). Buffers are bound at the indices
///        render/taa/TaaParams.h names; the CPU copy is TaaCpu.h.
#include "gpu/ComputePass.h"
#include "gpu/Profiler.h"
#include "gpu/Resources.h"
#include "render/taa/TaaParams.h"

namespace rtsdf {

/// @brief Temporal accumulation of the visibility with neighbourhood clamping.
class TaaPass : gpu::ComputePass {
public:
  static constexpr const char* kName = "TaaPass";
  struct Inputs { const gpu::Buffer& current; };
  struct Outputs { const gpu::Buffer& history; }; ///< in: the last output; out: this frame's
  using Params = gpu::shared::TaaParams;
  explicit TaaPass(const gpu::VulkanContext& ctx)
      : ComputePass(ctx, "taa.comp", gpu::shared::kTaaBindingCount, sizeof(Params)) {}
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;
};

} // namespace rtsdf
