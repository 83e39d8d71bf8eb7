#pragma once
/// @file RefinePasses.h
/// @brief The fine SDF's passes: UpsamplePass (the coarse SDF trilinearly upsampled into every fine voxel: the
///        value outside the ray mask) and the refinement of the masked voxels through the scene BVH, by the
///        paper's random rays (RayRefinePass) or exact closest points (ClosestRefinePass). Same shape as every
///        pass: execute(cmd, profiler, inputs, outputs, params), bindings named in gpu/shared/Refine.h.
#include "gpu/ComputePass.h"
#include "gpu/Profiler.h"
#include "gpu/Resources.h"
#include "gpu/shared/Refine.h"
#include "grid/GridSpec.h"
#include "sdf/GpuSceneBvh.h"

namespace rtsdf {

/// @brief The grid half of the refinement's push constants: both grids' corners, voxel sizes and dims (the
///        grids as the GPU sees them, e.g. GridSpec::inFrame of the frame's origin); the rest zero.
gpu::shared::RefineParams refineGridParams(const GridSpec& coarse, const GridSpec& fine);

/// @brief UpsamplePass: fine[v] = the coarse SDF trilinearly interpolated at fine voxel v's centre.
class UpsamplePass : gpu::ComputePass {
public:
  static constexpr const char* kName = "UpsamplePass";
  /// How the work is split: the kernels give the same values bit for bit.
  enum class Kernel {
    Runs,    ///< RTSDF_UPSAMPLE_RUN_LENGTH voxels along z per invocation, coarse values reused along the run
    PerVoxel ///< one voxel per invocation, 8 coarse loads each (the baseline the benchmark shows)
  };
  struct Inputs { const gpu::Buffer& coarse; }; ///< c_t, dense, x fastest
  struct Outputs { const gpu::Buffer& fine; };  ///< every fine voxel written
  using Params = gpu::shared::RefineParams;     ///< grids of both levels
  explicit UpsamplePass(const gpu::VulkanContext& ctx, Kernel kernel = Kernel::Runs)
      : ComputePass(ctx, kernel == Kernel::Runs ? "refine_upsample.comp" : "refine_upsample_voxel.comp",
                    gpu::shared::kUpsampleBindingCount, sizeof(Params)),
        mRun(kernel == Kernel::Runs ? RTSDF_UPSAMPLE_RUN_LENGTH : 1) {}
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;

private:
  int mRun;
};

/// @brief The refinement of the masked fine voxels (refine_main.glsl): the shared shape of RayRefinePass and
///        ClosestRefinePass, which differ in the shader variant and their profiler name.
class RefinePass : gpu::ComputePass {
public:
  struct Inputs {
    const GpuSceneBvh& bvh;       ///< top level as of this frame
    const gpu::Buffer& mask;      ///< packed fine voxels (10 bits per axis)
    const gpu::Buffer& dispatch;  ///< VkDispatchIndirectCommand: the mask's size, in groups of RTSDF_REFINE_GROUP
  };
  /// Per fine voxel: the SDF (in: c_t upsampled, out: f_t), its unsigned history, decayed sign votes, and the
  /// frame it was last refined in.
  struct Outputs { const gpu::Buffer &fine, &history, &votes, &lastFrame; };
  using Params = gpu::shared::RefineParams;
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;
  const char* name() const { return mName; }

protected:
  RefinePass(const gpu::VulkanContext& ctx, const char* shader, const char* name)
      : ComputePass(ctx, shader, gpu::shared::kRefineBindingCount, sizeof(Params)), mName(name) {}

private:
  const char* mName;
};

/// @brief The paper's refinement: x random rays per masked voxel, f_t = min(alpha f_{t-1} + (1 - alpha) c^_t, r_t).
class RayRefinePass : public RefinePass {
public:
  static constexpr const char* kName = "RayRefinePass";
  explicit RayRefinePass(const gpu::VulkanContext& ctx) : RefinePass(ctx, "refine_rays.comp", kName) {}
};

/// @brief Exact refinement: the closest point through the BVH (sign from ray votes when x > 0).
class ClosestRefinePass : public RefinePass {
public:
  static constexpr const char* kName = "ClosestRefinePass";
  explicit ClosestRefinePass(const gpu::VulkanContext& ctx) : RefinePass(ctx, "refine_closest.comp", kName) {}
};

} // namespace rtsdf
