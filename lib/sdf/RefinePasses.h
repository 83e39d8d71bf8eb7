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

/// @brief The longest run of fine voxels under one coarse voxel along each axis (maskFineRanges of the grids).
glm::ivec3 longestFineRuns(const GridSpec& coarse, const GridSpec& fine);

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

/// @brief MaskCompactPass (mask_compact.comp): the ray mask on the GPU. Appends every coarse voxel with |c| <= d
///        (index and value) to the coarse list, stamps the bricks holding the fine voxels under it with the frame
///        number and, when they are to be refined this frame (gpu::shared::refinesThisFrame, which advances the
///        voxel's state), appends the voxel (kMaskFineFresh when new to the band) to the refine list, in no order;
///        counts both lists, the fine voxels refined and every fine voxel under the band in the counts buffer
///        (gpu/shared/Refine.h's kMaskCount* words, which must be zero before).
class MaskCompactPass : gpu::ComputePass {
public:
  static constexpr const char* kName = "MaskCompactPass";
  struct Inputs {
    const gpu::Buffer& coarse;     ///< c_t, dense, x fastest
    const gpu::Buffer& fineRanges; ///< maskFineRanges() of the two grids
    const gpu::Buffer& movedBoxes; ///< MovedBox per instance that moved (params.movedBoxes of them)
  };
  /// @a coarseState: (last frame in the band, refinements in a row) per coarse voxel, read and advanced;
  /// @a brickNeeded: per brick, the last frame a band voxel lay in it.
  struct Outputs { const gpu::Buffer &counts, &refineList, &coarseList, &coarseState, &brickNeeded; };
  using Params = gpu::shared::MaskParams; ///< refineCapacity / coarseCapacity: entries the lists hold
  explicit MaskCompactPass(const gpu::VulkanContext& ctx)
      : ComputePass(ctx, "mask_compact.comp", gpu::shared::kMaskBindingCount, sizeof(Params)) {}
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;
};

/// @brief MaskDispatchPass (mask_dispatch.comp): one invocation writes the refinement's indirect dispatch
///        (gpu::shared::refineDispatch of params.brickDims.w invocations per coarse voxel of the refine list), at
///        offset 0 of the counts buffer, which therefore needs VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT.
class MaskDispatchPass : gpu::ComputePass {
public:
  static constexpr const char* kName = "MaskDispatchPass";
  struct Inputs {};
  struct Outputs { const gpu::Buffer& counts; };
  using Params = gpu::shared::MaskParams;
  explicit MaskDispatchPass(const gpu::VulkanContext& ctx)
      : ComputePass(ctx, "mask_dispatch.comp", 1, sizeof(Params)) {}
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;
};

/// @brief BrickAllocPass (brick_alloc.comp): the brick pool's slots follow the ray mask on the GPU. A brick that
///        MaskCompactPass stamped this frame keeps its slot or takes one off the free stack; a brick it did not
///        stamp gives its slot back. Slots are assigned in no particular order; a needed brick finds none only when
///        the stack is empty (kBrickCountOverflow counts those). The counts' per-frame words
///        (kBrickCountActive, kBrickCountAllocated, kBrickCountOverflow) must be zero before.
class BrickAllocPass : gpu::ComputePass {
public:
  static constexpr const char* kName = "BrickAllocPass";
  struct Inputs { const gpu::Buffer& needed; };  ///< per brick: the last frame it was needed
  /// kBrickCount* words; per brick its slot (kNoBrick: none); the free stack (kBrickCountFreeTop entries).
  struct Outputs { const gpu::Buffer &counts, &slots, &freeStack; };
  using Params = gpu::shared::BrickParams;       ///< bricks and frame (phase: set by execute)
  explicit BrickAllocPass(const gpu::VulkanContext& ctx)
      : ComputePass(ctx, "brick_alloc.comp", gpu::shared::kBrickBindingCount, sizeof(Params)) {}
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;
};

/// @brief The brick pool's storage: RTSDF_BRICK_PAGES pages of values (float) and of sign votes (two halves),
///        each of pageBricks bricks; pages beyond the pool's capacity are bound to a small placeholder.
struct BrickPages {
  const gpu::Buffer* values[RTSDF_BRICK_PAGES];
  const gpu::Buffer* votes[RTSDF_BRICK_PAGES];
};

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
    const GpuSceneBvh& bvh;         ///< top level as of this frame
    const gpu::Buffer& refineList;  ///< MaskCompactPass's refine list: the coarse voxels to refine this frame
    const gpu::Buffer& counts;      ///< MaskCompactPass's counts, indirect dispatch included (MaskDispatchPass)
    const gpu::Buffer& coarse;      ///< c_t, dense, x fastest: upsampled at each voxel for its bound
    const gpu::Buffer& fineRanges;  ///< maskFineRanges() of the two grids
    const gpu::Buffer& brickSlots;  ///< per brick: its slot in the pool (kNoBrick: left alone)
  };
  /// Per fine voxel, in its brick: the SDF (in: f_{t-1} where not fresh; out: f_t, signed) and its decayed votes;
  /// @a dense: f_t also written into the dense fine SDF where params.coarseDims.w has kRefineWriteDense (else a
  /// placeholder).
  struct Outputs { const BrickPages& pool; const gpu::Buffer& dense; };
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
  /// The shader variant (refine_closest*.comp): a SIMD device runs the code it branches around, masked, so what a
  /// pipeline never runs is compiled out.
  struct Variant {
    bool signRays = true;    ///< params.rays > 0: the sign from the rays' votes, else from the closest triangle's side
    bool cellSearch = false; ///< ClosestSearch::Cell (kRefineCellSearch must be set too)
    bool cpu = false;        ///< the BVH walk's shape for CPU devices (ShaderTarget::Cpu)
  };
  ClosestRefinePass(const gpu::VulkanContext& ctx, const Variant& variant)
      : RefinePass(ctx, shaderFor(variant), kName) {}
  /// @brief The shader file of @a variant, e.g. "refine_closest_cell_side_cpu.comp".
  static const char* shaderFor(const Variant& variant);
};

} // namespace rtsdf
