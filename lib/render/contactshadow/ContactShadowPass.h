#pragma once
/// @file ContactShadowPass.h
/// @brief Contact shadows on the GPU (ContactShadowPass, contact_shadow.comp). Buffers are bound at the indices
///        render/contactshadow/ContactShadowParams.h names; the CPU copy is ContactShadowCpu.h.
#include "gpu/ComputePass.h"
#include "gpu/Profiler.h"
#include "gpu/Resources.h"
#include "render/contactshadow/ContactShadowParams.h"
#include "render/gbuffer/GBufferPass.h"
#include "sdf/scenebvh/GpuSceneBvh.h"

namespace rtsdf {

/// @brief Contact shadows: per pixel and light, a few short rays through the scene's BVH over the first fine voxels
///        off the surface, towards points of the light's disc; the SDF's visibility is lowered to the fraction of
///        them that nothing blocks (what lies within a voxel of the receiver is below the SDF's resolution: a gap
///        under a wall, a crease, the contact of two boxes). Runs after SdfShadowPass, in place, and traces only the
///        pixels that pass marked (kContactPending: its march saw something nearer than the receiver's own plane).
class ContactShadowPass : gpu::ComputePass {
public:
  static constexpr const char* kName = "ContactShadowPass";
  struct Inputs {
    const GpuSceneBvh& bvh;
    const GpuGBuffer& gbuffer;
    const gpu::Buffer& lights;
  };
  struct Outputs { const gpu::Buffer& visibility; }; ///< in: SdfShadowPass's; out: lowered (light-major)
  using Params = gpu::shared::ContactShadowParams;
  explicit ContactShadowPass(const gpu::VulkanContext& ctx)
      : ComputePass(ctx, "contact_shadow.comp", gpu::shared::kContactShadowBindingCount, sizeof(Params)) {}
  /// @throw Error when params.rays is 0 (the caller skips the pass instead) or the image size is not the
  ///        G-buffer's.
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;
};

} // namespace rtsdf
