#pragma once
/// @file SdfPipeline.h
/// @brief One frame of the RTSDF pipeline: coarse SDF on the GPU (voxelize + nearest seeds), its mirror in
///        a sparse OpenVDB grid whose active band |c| <= d is the ray mask, then the fine SDF refined by
///        BVH queries only under the mask, accumulated over frames.
#include "bvh/Bvh.h"
#include "gpu/Profiler.h"
#include "gpu/Resources.h"
#include "sdf/refine/RefineParams.h"
#include "grid/GridSpec.h"
#include "scene/Scene.h"
#include "sdf/coarse/CoarseSdf.h"
#include "sdf/scenebvh/GpuSceneBvh.h"
#include "sdf/PipelineSettings.h"
#include "sdf/refine/RefinePasses.h"
#include "util/EnumNames.h"
#include "util/PassTimes.h"

#include <openvdb/openvdb.h>

#include <chrono>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace rtsdf {


/// @brief What SdfPipeline would allocate for some settings and bounds, computed without allocating.
///
/// Device buffers: per coarse voxel 32 bytes (seeds, jump-flood scratch, coarse SDF, the compacted coarse band,
/// the refinement state, the list of voxels to refine: the GPU appends to them, so they are sized for every
/// voxel); per brick 8 bytes (stamp, slot); per fine voxel 4 bytes with FineStorage::Dense (the dense fine SDF);
/// the BVH (about 160 bytes per triangle). Not counted: the brick pool (8 bytes per fine voxel of a brick under
/// the band: values and sign votes), which the first frame sizes from the band and checks against the same
/// limits (SdfPipeline::poolBricks()). Host memory at its peak, when the results are read back (a frame itself
/// reads back a few words): per coarse voxel 29 bytes (coarseField() and its staging copy; rayMask()'s coarse
/// band, its staging copy and the OpenVDB mirror), per fine voxel 16 bytes (rayMask()'s list and fineField(),
/// each with its staging copy).
struct PipelineMemory {
  GridSpec coarse, fine;          ///< the grids (pipelineGrids)
  std::uint64_t largestBuffer = 0;///< bytes of the largest single storage buffer
  std::string largestBufferName;  ///< which one ("fine SDF" or "coarse band list")
  std::uint64_t deviceBytes = 0;  ///< every device buffer together
  std::uint64_t hostBytes = 0;    ///< host copies and staging buffers (peak of one frame)
  std::string describe() const;
};

/// @brief The boxes the instances of @a scene swept between @a before and @a after seconds, one per instance whose
///        transform changed: the union of its world bounds in both poses (the corners of @a meshBounds[mesh]
///        transformed in double), measured from @a origin and rounded outwards to float. At most
///        RTSDF_MAX_MOVED_BOXES; further ones are merged into the last box. The incremental refinement's input.
std::vector<gpu::shared::MovedBox> movedInstanceBoxes(const Scene& scene, const std::vector<Bounds>& meshBounds,
                                                      double before, double after, const glm::dvec3& origin);

/// @brief Estimate the memory of a pipeline (see PipelineMemory) for @a triangles triangles.
/// @throw Error as pipelineGrids does.
PipelineMemory estimatePipelineMemory(const Bounds& bounds, const PipelineSettings& s, std::uint64_t triangles = 0);

/// @brief Limits an estimate is checked against.
struct MemoryLimits {
  std::uint64_t maxStorageBufferRange = 0; ///< largest storage buffer (VkPhysicalDeviceLimits)
  std::uint64_t deviceBytes = 0;           ///< the largest device-local heap; 0: unknown (not checked)
  std::uint64_t hostBytes = 0;             ///< host memory available (MemAvailable); 0: unknown (not checked)
  bool unifiedMemory = false;              ///< device memory is host memory (a CPU device such as lavapipe)
  std::string deviceName;
};

/// @brief The limits of @a device on this machine: its buffer range and heap, and /proc/meminfo's
///        MemAvailable (0 where unknown).
MemoryLimits memoryLimits(const gpu::DeviceInfo& device);

/// @brief Refuse an estimate that does not fit: the largest buffer against maxStorageBufferRange, the
///        device buffers against the device heap, host copies (plus device buffers on a unified-memory
///        device) against the host memory available.
/// @throw SettingError stating the grid, the bytes needed, the limit, and the setting to lower (the fine or
///        the coarse resolution).
void checkPipelineMemory(const PipelineMemory& need, const MemoryLimits& limits);

/// @brief The ray mask: the coarse SDF mirrored into OpenVDB (active exactly where |c| <= d) and the fine
///        voxels whose centres lie in active coarse voxels (maskFineRanges), packed 10 bits per axis, sorted.
struct RayMask {
  /// The mirror (null when d = 0: nothing is refined). Its transform is the coarse grid's; where the coarse
  /// voxels are smaller than OpenVDB accepts (minVdbVoxelSize()), the mirror is measured in voxels (voxel
  /// size 1, values and background divided by h) and covers the same voxels.
  openvdb::FloatGrid::Ptr coarse;
  std::vector<std::uint32_t> fineVoxels;
  std::uint64_t coarseVoxels = 0; ///< active coarse voxels
};
/// @brief The CPU reference of the ray mask, from a dense coarse SDF (x fastest). SdfPipeline compacts the same
///        mask on the GPU (MaskCompactPass) and builds its mirror on demand (SdfPipeline::rayMask()).
RayMask buildRayMask(const std::vector<float>& coarse, const GridSpec& coarseSpec, const GridSpec& fineSpec,
                     double band);

/// @brief The brick pool's capacity for @a activeBricks bricks under the band: half as many again and 64 more (room
///        for the band to grow as instances move before the pool must be regrown), at most every brick of a grid of
///        @a brickDims bricks.
std::uint64_t poolBricksFor(std::uint64_t activeBricks, const glm::ivec3& brickDims);

/// @brief What one frame did and cost.
struct FrameStats {
  double time = 0.0;
  std::uint64_t maskCoarseVoxels = 0, maskFineVoxels = 0;
  std::uint64_t refinedFineVoxels = 0; ///< masked fine voxels refined this frame (the others kept their value)
  std::uint64_t activeBricks = 0;      ///< bricks holding fine voxels under the band (each has a pool slot...)
  std::uint64_t overflowBricks = 0;    ///< ...but these: the pool was full; the next frame grows it and starts over
  std::uint64_t poolBricks = 0;        ///< the pool's capacity this frame
  std::uint64_t deviceBytes = 0;       ///< the pipeline's device buffers this frame (estimate and pool)
  std::uint64_t movedInstances = 0;    ///< instances whose transform changed since the previous frame
  /// CPU time of the frame outside its wait for the GPU: the BVH's top level and the instance transforms,
  /// recording, submitting, and reading the counts after the GPU finished. It grows with the instances, not with
  /// their triangles or the voxels (the GPU places the triangles and compacts the ray mask).
  double hostMs = 0.0;
  double wallMs = 0.0; ///< submitFrame() to the return of finishFrame(): host work, submission and the GPU's work
  PassTimes passMs;      ///< GPU time per pass
  double passTotal(const std::string& pass) const { return rtsdf::passTotal(passMs, pass); }
  /// @brief The refinement pass's time, whichever mode ran (RayRefinePass or ClosestRefinePass).
  double refineMs() const;
};

/// @brief The fine SDF as FineStorage::Sparse keeps it on the GPU, for shading passes that sample it without a dense
///        copy: fine voxel v's value is the pool's where v lies under the band (|c| <= d at its coarse slab,
///        @a fineToCoarse) and its brick has a slot, else the coarse SDF upsampled at v (coarse_upsample.glsl with
///        @a params): resolveFineCpu's values.
struct GpuBrickField {
  const gpu::Buffer& coarse;       ///< c_t, dense, x fastest
  const gpu::Buffer& fineToCoarse; ///< maskCoarseOfFine() of the grids
  const gpu::Buffer& slots;        ///< per brick (x fastest, params.brickDims): its slot, kNoBrick: none
  const gpu::Buffer& params;       ///< one gpu::shared::RefineParams: grids in the GPU's frame, brickDims, pageBricks
  BrickPages pool;                 ///< the values (votes unused)
};

/// @brief Runs frames of the pipeline for one scene on fixed grids (bounds given by the caller, e.g. the
///        union over an animation, so history stays valid while objects move).
class SdfPipeline {
public:
  /// @throw Error when a setting is out of range, or (before anything is allocated) when the grids would
  ///        not fit the device's buffers and heap or the host's available memory (checkPipelineMemory).
  SdfPipeline(const gpu::VulkanContext& ctx, const Scene& scene, const Bounds& bounds, const PipelineSettings& s);
  ~SdfPipeline();
  SdfPipeline(const SdfPipeline&) = delete;
  SdfPipeline& operator=(const SdfPipeline&) = delete;

  /// @brief One frame at @a time seconds, one submission: coarse SDF, the ray mask compacted on the GPU
  ///        (MaskCompactPass, MaskDispatchPass), upsample, refinement dispatched indirectly by the mask's size
  ///        (incremental unless PipelineSettings::fullRecompute: the boxes the instances swept since the previous
  ///        frame, movedInstanceBoxes, are the frame's only upload besides the BVH's top level). Only the mask's
  ///        counts (a few words) are read back, after the frame. submitFrame() then finishFrame().
  FrameStats runFrame(double time);
  /// @brief Record and submit the frame at @a time seconds without waiting for the GPU (a frame loop's call: the
  ///        host is free until the next frame). Waits first for the previous frame if it is still running (one
  ///        frame in flight: frames share their buffers); that frame's statistics are then lost.
  /// @throw Error when an instance leaves the supported coordinates at @a time (checkInstancePlacement).
  void submitFrame(double time);
  /// @brief Wait for the submitted frame and return its statistics (counts and pass times read back).
  /// @throw Error when no frame was submitted since the last finishFrame().
  FrameStats finishFrame();
  /// @brief The dense fine SDF of the last frame (x fastest), scene units: read back from the GPU
  ///        (FineStorage::Dense), or resolved on the host from the coarse SDF and the bricks read back (Sparse:
  ///        resolveFineCpu, the same values bit for bit).
  std::vector<float> fineField() const;
  /// @brief Per brick of the fine grid (x fastest, brickDims()): its slot in the pool, kNoBrick where it has none
  ///        (read back).
  std::vector<std::uint32_t> brickSlots() const;
  /// @brief The pool's values, slot after slot (kBrickVoxels each; read back): the refinement's, for the voxels
  ///        of a slotted brick under the band (the others hold nothing meaningful).
  std::vector<float> brickValues() const;
  /// @brief Bricks per axis of the fine grid.
  glm::ivec3 brickDims() const;
  /// @brief The pool's capacity in bricks (0 before the first frame sizes it).
  std::uint64_t poolBricks() const { return mPoolBricks; }
  /// @brief The last frame's coarse SDF (x fastest; read back from the GPU; empty before the first frame).
  std::vector<float> coarseField() const;
  /// @brief The last frame's ray mask as the GPU compacted it, with its OpenVDB mirror built on demand from the
  ///        compacted band (no dense read-back): the same voxels as buildRayMask(coarseField(), ...), the fine
  ///        voxels sorted. Empty before the first frame or when d = 0.
  RayMask rayMask() const;
  /// @brief The fine voxels the last frame refined (MaskCompactPass's refine list, read back, expanded into the
  ///        fine voxels under each coarse voxel and sorted): packed 10 bits per axis, with
  ///        gpu::shared::kMaskFineFresh on those new to the band.
  std::vector<std::uint32_t> refinedVoxels() const;
  /// @brief Per coarse voxel (x fastest): the last frame it was in the band and its refinements in a row (read back;
  ///        0xFFFFFFFF before it has been in the band).
  std::vector<glm::uvec2> coarseState() const;
  /// @brief MaskCompactPass's parameters in the last frame and the moving boxes it read (maskDecisionsCpu's input).
  const gpu::shared::MaskParams& lastMaskParams() const { return mLastMaskParams; }
  const std::vector<gpu::shared::MovedBox>& lastMovedBoxes() const { return mLastMovedBoxes; }
  const GridSpec& coarseSpec() const { return mCoarseSpec; }
  /// @brief The world point the GPU passes measure from: the fine grid's corner. Triangles, the BVH's top level
  ///        and the grids are moved into this frame in double before they become floats, so a scene far from
  ///        the world's origin keeps the precision it has at the origin.
  const glm::dvec3& frameOrigin() const { return mFineSpec.origin; }
  const GridSpec& fineSpec() const { return mFineSpec; }
  /// The settings in effect: shaderTarget and an Auto closestSearch resolved for the device.
  const PipelineSettings& settings() const { return mSettings; }
  /// @brief The fine SDF on the GPU (dense, x fastest, fineSpec()), valid after runFrame() or finishFrame().
  /// @throw Error with FineStorage::Sparse (there is none).
  const gpu::Buffer& fineBuffer() const;
  /// @brief The fine SDF as the bricks hold it, valid after runFrame() or finishFrame().
  /// @throw Error with FineStorage::Dense (sample fineBuffer()).
  GpuBrickField brickField() const;
  /// @brief The coarse SDF on the GPU (dense, x fastest, coarseSpec()), valid after runFrame() or finishFrame().
  const gpu::Buffer& coarseBuffer() const;
  /// @brief The scene's BVH on the GPU, its top level as of the last runFrame(), in the frame of frameOrigin().
  const GpuSceneBvh& bvh() const { return *mBvh; }

private:
  struct Gpu;
  /// MaskCompactPass's parameters for this frame, with @a movedBoxes moving instances.
  gpu::shared::MaskParams maskParams(std::uint32_t movedBoxes) const;
  /// Record: counters reset, MaskCompactPass (band > 0), MaskDispatchPass.
  void recordMask(VkCommandBuffer cmd, const gpu::shared::MaskParams& params);
  /// Record: the counts copied into the host-visible readback buffer, visible to the host after the frame.
  void recordCountsReadback(VkCommandBuffer cmd) const;
  struct MaskCounts {
    std::uint32_t refinedFine = 0, maskedFine = 0, coarse = 0, refineList = 0;
    std::uint32_t activeBricks = 0, overflowBricks = 0;
  };
  /// What the last frame's mask counted (from the readback).
  MaskCounts maskCounts() const;
  gpu::shared::RefineParams refineParams() const;
  /// Wait for a submitted frame (the read-backs need its results).
  void waitForFrame() const;
  /// Before a frame at @a time: the pool sized by the first frame's band (PipelineSettings::poolBricks where given),
  /// or regrown after a frame that overflowed it (then every voxel starts over). One-off waits, outside the frame's
  /// host time.
  void preparePool(double time);
  /// The first frame's pool size: the bricks under the band of the coarse SDF at @a time, with headroom.
  std::uint64_t firstPoolSize(double time);
  /// (Re)allocate the pool for @a bricks bricks, every slot free, every coarse voxel new to the band.
  /// @throw SettingError when it does not fit the device (checkPipelineMemory).
  void allocatePool(std::uint64_t bricks);
  PipelineMemory mMemory;          ///< the estimate checked at construction (the pool is added when sized)
  std::uint64_t mPoolBricks = 0, mPageBricks = 0;
  std::uint64_t mGrowTo = 0;       ///< > 0: the last frame overflowed; the next one reallocates the pool
  RefineParts mRefineParts;        ///< the refinement's boxes per coarse voxel (refinePartsFor)
  const gpu::VulkanContext& mCtx;
  const Scene& mScene;
  PipelineSettings mSettings;
  GridSpec mCoarseSpec, mFineSpec;
  std::unique_ptr<GpuSceneBvh> mBvh;
  std::uint32_t mFrame = 0;
  double mPreviousTime = 0.0;
  gpu::shared::MaskParams mLastMaskParams{};
  std::vector<gpu::shared::MovedBox> mLastMovedBoxes;
  std::vector<Bounds> mMeshBounds; ///< per mesh, in its own space: the moving instances' boxes come from these
  FrameStats mSubmitted;           ///< the submitted frame's statistics so far (host time of its recording)
  bool mAwaitingFinish = false;    ///< a frame was submitted and finishFrame() has not read it
  std::chrono::steady_clock::time_point mSubmitStart;
  std::unique_ptr<Gpu> mGpu;
};

} // namespace rtsdf
