#pragma once
/// @file ComputePass.h
/// @brief The base of the passes that run one compute shader. Every pass, whatever its base, has the same
///        shape: a profiler label kName, Inputs / Outputs structs of named buffers, Params (push constants and
///        dispatch extents) and execute(cmd, profiler, inputs, outputs, params), which records into @a cmd
///        inside a profiler scope (null profiler: none) and leaves submitting to the caller.
#include "gpu/Resources.h"

#include <cstdint>

namespace rtsdf::gpu {

/// @brief Owns the compute pipeline of one embedded shader whose bindings are all storage buffers.
class ComputePass {
protected:
  ComputePass(const VulkanContext& ctx, const char* shader, std::uint32_t bindings, std::uint32_t pushBytes)
      : mPipeline(ctx, shader, bindings, pushBytes) {}
  ComputePipeline mPipeline;
};

} // namespace rtsdf::gpu
