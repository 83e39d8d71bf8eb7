#pragma once
/// @file RefinePasses.h
/// @brief The fine SDF's passes: UpsamplePass (the coarse SDF trilinearly upsampled into every fine voxel: the
///        value outside the ray mask) and the refinement of the masked voxels through the scene BVH, by the
///        paper's random rays (RayRefinePass) or exact closest points (ClosestRefinePass). Same shape as every
///        pass: execute(cmd, profiler, inputs, outputs, params), bindings named in sdf/refine/RefineParams.h. The
///        mask they refine under comes from sdf/mask/MaskPasses.h; the CPU copies are RefineCpu.h.
#include "gpu/ComputePass.h"
#include "gpu/Profiler.h"
#include "gpu/Resources.h"
#include "grid/GridSpec.h"
#include "sdf/mask/MaskPasses.h"
#include "sdf/refine/RefineParams.h"
#include "sdf/scenebvh/GpuSceneBvh.h"

#include <array>
#include <vector>

namespace rtsdf {

/// @brief The grid half of the refinement's push constants: both grids' corners, voxel sizes and dims (the
///        grids as the GPU sees them, e.g. GridSpec::inFrame of the frame's origin); the rest zero.
gpu::shared::RefineParams refineGridParams(const GridSpec& coarse, const GridSpec& fine);

/// @brief How the refinement splits the fine voxels under one coarse voxel among its invocations: into boxes of at
///        most @a box voxels per axis, @a count boxes per axis (x fastest), one invocation each.
struct RefineParts {
  glm::ivec3 box{1};
  glm::ivec3 count{1};
  std::uint32_t total() const { return std::uint32_t(count.x * count.y * count.z); }
};

/// @brief The boxes for fine runs of at most @a longestRuns voxels (longestFineRuns). Per voxel search: one box per
///        (x, y) column, a run along z (the BVH is walked per voxel, so the most invocations). @a cellSearch: boxes
///        of at most RTSDF_CELL_BOX voxels per axis, as few as cover the runs (one box of 2x2x2 voxels at a
///        fine/coarse ratio of 2), so that one walk serves each box's voxels.
RefineParts refinePartsFor(const glm::ivec3& longestRuns, bool cellSearch);

/// @brief UpsamplePass: the dense fine SDF after the refinement (which writes it too under the mask). fine[v] = the
///        coarse SDF trilinearly interpolated at fine voxel v's centre for every fine voxel outside the ray mask; the
///        voxels under a coarse voxel with |c| <= params.band whose brick has a slot keep their values (the
///        refinement's); where the brick has none (a full pool) they are upsampled too. params.band = 0: every
///        voxel is upsampled.
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
    const gpu::Buffer& brickSlots;   ///< per brick: its slot in the pool (kNoBrick: none)
  };
  struct Outputs { const gpu::Buffer& fine; };  ///< every fine voxel but the slotted ones under the band written
  using Params = gpu::shared::RefineParams;     ///< grids of both levels
  /// @throw VulkanError when the shader is missing or its whole-grid region cannot be uploaded.
  explicit UpsamplePass(const gpu::VulkanContext& ctx, Kernel kernel = Kernel::Runs);
  /// @brief Record the upsampling of every fine voxel.
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;

private:
  int mRun;
  gpu::Buffer mWholeGrid; ///< the UpsampleRegion of every fine voxel (begin 0, end unbounded: the grid's dims)
};

/// @brief The first fine voxel of each coarse block (RTSDF_COARSE_BLOCK^3 coarse voxels) per axis, then the fine grid's
///        end: x's, then y's, then z's (gpu::shared::upsampleBlockFineAt), for @a coarse and @a fine as the GPU sees
///        them. A fine voxel belongs to the block holding the coarse voxel its centre lies in (clamped to the grid), so
///        the blocks split the fine grid; the coarse voxels its upsampling reads lie within one of that one.
std::vector<int> upsampleBlockFineBegins(const GridSpec& coarse, const GridSpec& fine);

/// @brief UpsampleBlocksPass: after a coarse build, the coarse blocks whose fine voxels the upsampling must write again
///        (upsample_blocks.comp): those a changed voxel's upsampling reaches (CoarseDistancePass's marks) and those
///        near @a boxes (what a scroll invalidated), listed with the indirect dispatch of UpsampleByBlocksPass and the
///        count of their fine voxels (gpu::shared::UpsampleBlockListHeader). Its CPU copy is upsampleBlocksCpu.
class UpsampleBlocksPass : gpu::ComputePass {
public:
  static constexpr const char* kName = "UpsampleBlocksPass";
  struct Inputs {
    const gpu::Buffer& marks;      ///< CoarseSdfBuilder::changedBlocksBuffer
    const gpu::Buffer& boxes;      ///< a gpu::shared::UpsampleBoxes
    const gpu::Buffer& fineBegins; ///< upsampleBlockFineBegins of the grids
  };
  struct Outputs { const gpu::Buffer& list; }; ///< the header and a word per block (storage, indirect, transfer dst)
  explicit UpsampleBlocksPass(const gpu::VulkanContext& ctx)
      : ComputePass(ctx, "upsample_blocks.comp", gpu::shared::kUpsampleBlocksBindingCount,
                    sizeof(gpu::shared::UpsampleBlocksParams)) {}
  /// @brief Record the list's reset, the listing over a coarse grid of @a coarseDims voxels and the dispatch.
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const glm::ivec3& coarseDims) const;
  /// @brief The bytes of the list of a coarse grid of @a coarseDims voxels.
  static std::uint64_t listBytes(const glm::ivec3& coarseDims);
};

/// @brief UpsampleByBlocksPass: UpsamplePass over the fine voxels of the blocks UpsampleBlocksPass listed (a work group
///        a block, dispatched indirectly from the list), the same values bit for bit; profiled as UpsamplePass.
class UpsampleByBlocksPass : gpu::ComputePass {
public:
  static constexpr const char* kName = UpsamplePass::kName;
  struct Inputs {
    UpsamplePass::Inputs upsample;
    const gpu::Buffer& list;       ///< UpsampleBlocksPass's
    const gpu::Buffer& fineBegins; ///< upsampleBlockFineBegins of the grids
  };
  using Outputs = UpsamplePass::Outputs;
  using Params = gpu::shared::RefineParams;
  explicit UpsampleByBlocksPass(const gpu::VulkanContext& ctx)
      : ComputePass(ctx, "refine_upsample_blocks.comp", gpu::shared::kUpsampleBlocksKernelBindingCount,
                    sizeof(Params)) {}
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;
};

/// @brief The refinement of the masked fine voxels (refine_main.glsl): the shared shape of RayRefinePass and
///        ClosestRefinePass, which differ in the shader variant and their profiler name.
class RefinePass : gpu::ComputePass {
public:
  struct Inputs {
    const GpuSceneBvh& bvh;         ///< top level as of this frame
    const gpu::Buffer& refineList;  ///< MaskCompactPass's refine list: the coarse voxels to refine this frame
    const gpu::Buffer& counts;      ///< MaskCompactPass's counts, indirect dispatch included (MaskDispatchPass)
    const gpu::Buffer& coarse;      ///< c_t, dense, x fastest: upsampled at each voxel for its bound
    const gpu::Buffer& fineRanges;  ///< maskFineRanges() of the two grids
    const gpu::Buffer& brickSlots;  ///< per brick: its slot in the pool (kNoBrick: left alone)
    /// the boxes the moving instances swept (InstanceMotion::buffer(); their count in params.coarseDims.w from bit
    /// kRefineMovedBoxesShift): closest mode keeps the fine voxels of kMaskMovedOnly entries that none comes near
    const gpu::Buffer& movedBoxes;
  };
  /// Per fine voxel, in its brick: the SDF (in: f_{t-1} where not fresh; out: f_t, signed) and its decayed votes;
  /// @a dense: f_t also written into the dense fine SDF where params.coarseDims.w has kRefineWriteDense (else a
  /// placeholder).
  /// @a stats: the kRefineStat* words, added to (the caller zeroes them).
  /// @a doubts: closest mode's list of voxels for WindingExactPass (its header zeroed by the caller; a placeholder
  /// in rays mode).
  struct Outputs {
    const BrickPages& pool;
    const gpu::Buffer& dense;
    const gpu::Buffer& stats;
    const gpu::Buffer& doubts;
  };
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

/// @brief Exact refinement: the closest point through the BVH (sign from ray votes when x > 0). With kRefineCellSearch
///        in params.coarseDims.w (ClosestSearch::Cell) one walk per box of fine voxels collects the triangles its
///        voxels test; the same distances as a walk per voxel.
class ClosestRefinePass : public RefinePass {
public:
  static constexpr const char* kName = "ClosestRefinePass";
  /// The shader variant (refine_closest*.comp, rows of lib/Shaders.cmake): a SIMD device runs the code it branches
  /// around, masked, so what a pipeline never runs is compiled out.
  struct Variant {
    bool signRays = true;    ///< params.rays > 0: the sign from the rays' votes, else from the closest triangle's side
    bool cellSearch = false; ///< ClosestSearch::Cell (kRefineCellSearch must be set too)
    bool cpu = false;        ///< the BVH walk's shape for CPU devices (ShaderTarget::Cpu)
  };
  ClosestRefinePass(const gpu::VulkanContext& ctx, const Variant& variant)
      : RefinePass(ctx, shaderFor(variant), kName) {}
  /// @brief The embedded shader of @a variant, e.g. "refine_closest_cell_side_cpu.comp".
  static const char* shaderFor(const Variant& variant);
};

/// @brief After ClosestRefinePass: the voxels whose walked winding number lay within kWindingExactBand of 1/2 (listed
///        by the refinement, at most kWindingExactCapacity a frame) take the side of the exact sum over every triangle
///        of their mesh, one work group per voxel (winding_exact.comp), as the exact field's rule does there.
class WindingExactPass : gpu::ComputePass {
public:
  static constexpr const char* kName = "WindingExactPass";
  struct Inputs {
    const GpuSceneBvh& bvh;     ///< the refinement's (corners, instances, instanceTriangles())
    const gpu::Buffer& doubts;  ///< the refinement's list (kRefineBindingWindingDoubts), the indirect dispatch first
  };
  /// The listed voxels' values re-signed in the pool (and @a dense where params has kRefineWriteDense); @a stats:
  /// kRefineStatNearHalfKept counts the voxels of meshes too large to sum.
  struct Outputs { const BrickPages& pool; const gpu::Buffer& dense; const gpu::Buffer& stats; };
  using Params = gpu::shared::RefineParams;
  explicit WindingExactPass(const gpu::VulkanContext& ctx)
      : ComputePass(ctx, "winding_exact.comp", gpu::shared::kWindingExactBindingCount, sizeof(Params)) {}
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;
};

} // namespace rtsdf
