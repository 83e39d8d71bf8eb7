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

#include <vector>

namespace rtsdf {

/// @brief The grid half of the refinement's push constants: both grids' corners, voxel sizes and dims (the
///        grids as the GPU sees them, e.g. GridSpec::inFrame of the frame's origin); the rest zero.
gpu::shared::RefineParams refineGridParams(const GridSpec& coarse, const GridSpec& fine);

/// @brief The fine voxels under each coarse slab, per axis: entry a-offset + i (x entries, then y, then z) is the
///        range [lo, hi] of fine indices j along axis a whose centres lie in coarse voxel i, i <= (j + 0.5) / ratio
///        < i + 1, clamped to the fine grid (lo > hi: none, where the coarse grid overhangs the fine one). The
///        grids share their corner (coarseGridOver). The CPU mirror (buildRayMask) and MaskCompactPass use these
///        very tables, so both give the same fine voxels.
std::vector<glm::ivec2> maskFineRanges(const GridSpec& coarse, const GridSpec& fine);

/// @brief Append the fine voxels under coarse voxel @a c (maskFineRanges @a ranges of a coarse grid of @a coarseDims),
///        packed x | y << 10 | z << 20, each or-ed with @a flags.
void appendFineVoxelsUnder(const std::vector<glm::ivec2>& ranges, const glm::ivec3& coarseDims, const glm::ivec3& c,
                           std::uint32_t flags, std::vector<std::uint32_t>& out);

/// @brief The inverse of maskFineRanges: entry a-offset + j (x entries, then y, then z) is the coarse index along
///        axis a whose slab holds fine index j (-1 where none does). UpsamplePass finds the ray mask's voxels with it.
std::vector<int> maskCoarseOfFine(const GridSpec& coarse, const GridSpec& fine);

/// @brief MaskCompactPass (mask_compact.comp): the ray mask on the GPU. Appends every coarse voxel with |c| <= d
///        (index and value) to the coarse list and, when they are to be refined this frame (gpu::shared::
///        refinesThisFrame, which advances the voxel's state), the fine voxels under it (packed 10 bits per axis,
///        kMaskFineFresh when new to the band) to the fine list, in no order; counts both lists and every fine voxel
///        under the band in the counts buffer (gpu/shared/Refine.h's kMaskCount* words, which must be zero before).
class MaskCompactPass : gpu::ComputePass {
public:
  static constexpr const char* kName = "MaskCompactPass";
  struct Inputs {
    const gpu::Buffer& coarse;     ///< c_t, dense, x fastest
    const gpu::Buffer& fineRanges; ///< maskFineRanges() of the two grids
    const gpu::Buffer& movedBoxes; ///< MovedBox per instance that moved (params.movedBoxes of them)
  };
  /// @a coarseState: (last frame in the band, refinements in a row) per coarse voxel, read and advanced.
  struct Outputs { const gpu::Buffer &counts, &fineList, &coarseList, &coarseState; };
  using Params = gpu::shared::MaskParams; ///< fineCapacity / coarseCapacity: entries the lists hold
  explicit MaskCompactPass(const gpu::VulkanContext& ctx)
      : ComputePass(ctx, "mask_compact.comp", gpu::shared::kMaskBindingCount, sizeof(Params)) {}
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;
};

/// @brief MaskDispatchPass (mask_dispatch.comp): one invocation writes the refinement's indirect dispatch
///        (gpu::shared::refineDispatch) from the fine voxels MaskCompactPass counted, at offset 0 of the counts
///        buffer, which therefore needs VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT.
class MaskDispatchPass : gpu::ComputePass {
public:
  static constexpr const char* kName = "MaskDispatchPass";
  struct Inputs {};
  struct Outputs { const gpu::Buffer& counts; };
  struct Params {};
  explicit MaskDispatchPass(const gpu::VulkanContext& ctx) : ComputePass(ctx, "mask_dispatch.comp", 1, 0) {}
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;
};

/// @brief UpsamplePass: fine[v] = the coarse SDF trilinearly interpolated at fine voxel v's centre, for every fine
///        voxel outside the ray mask (params.band > 0: the voxels under a coarse voxel with |c| <= band keep their
///        values; params.band = 0: every voxel).
class UpsamplePass : gpu::ComputePass {
public:
  static constexpr const char* kName = "UpsamplePass";
  /// How the work is split: the kernels give the same values bit for bit.
  enum class Kernel {
    Runs,    ///< RTSDF_UPSAMPLE_RUN_LENGTH voxels along z per invocation, coarse values reused along the run
    PerVoxel ///< one voxel per invocation, 8 coarse loads each (the baseline the benchmark shows)
  };
  struct Inputs {
    const gpu::Buffer& coarse;       ///< c_t, dense, x fastest
    const gpu::Buffer& fineToCoarse; ///< maskCoarseOfFine() of the two grids
  };
  struct Outputs { const gpu::Buffer& fine; };  ///< every fine voxel outside the mask written
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
    const gpu::Buffer& mask;      ///< MaskCompactPass's fine list: the voxels to refine this frame
    const gpu::Buffer& counts;    ///< MaskCompactPass's counts, indirect dispatch included (MaskDispatchPass)
    const gpu::Buffer& coarse;    ///< c_t, dense, x fastest: upsampled at each voxel for its bound
  };
  /// Per fine voxel: the SDF (in: f_{t-1} where not fresh; out: f_t, signed) and its decayed sign votes.
  struct Outputs { const gpu::Buffer &fine, &votes; };
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
