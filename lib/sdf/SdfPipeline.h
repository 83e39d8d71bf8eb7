#pragma once
/// @file SdfPipeline.h
/// @brief One frame of the RTSDF pipeline: coarse SDF on the GPU (voxelize + nearest seeds), its mirror in
///        a sparse OpenVDB grid whose active band |c| <= d is the ray mask, then the fine SDF refined by
///        BVH queries only under the mask, accumulated over frames. SdfPipeline orchestrates the parts in
///        lib/sdf/pipeline/ (PipelineMemory, RayMask, GpuRayMask, BrickPool, FieldPasses, InstanceMotion,
///        FrameRecorder); PipelineProbe reads the parts' state back for tests.
#include "bvh/Bvh.h"
#include "gpu/Profiler.h"
#include "gpu/Resources.h"
#include "grid/GridSpec.h"
#include "scene/Scene.h"
#include "sdf/coarse/CoarseSdf.h"
#include "sdf/scenebvh/GpuSceneBvh.h"
#include "sdf/PipelineSettings.h"
#include "sdf/refine/RefinePasses.h"
#include "sdf/pipeline/DenseFineWrites.h"
#include "sdf/pipeline/FramePlan.h"
#include "sdf/pipeline/FrameStats.h"
#include "sdf/pipeline/PipelineMemory.h"
#include "sdf/pipeline/RayMask.h"
#include "sdf/pipeline/ViewReach.h"
#include "util/EnumNames.h"
#include "util/PassTimes.h"

#include <openvdb/openvdb.h>

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace rtsdf {

class BrickPool;
class FieldPasses;
class FrameRecorder;
class GpuRayMask;
class GridShiftPass;
class InstanceMotion;

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
///        union over an animation, so history stays valid while objects move). Orchestrates its parts (each owns
///        its state, so several pipelines coexist): GpuSceneBvh, FieldPasses (coarse SDF, refinement, upsampling),
///        GpuRayMask (the mask compacted on the GPU), BrickPool (the sparse fine state), InstanceMotion (the boxes
///        the instances swept) and FrameRecorder (the frame's command buffer, profiler and timing).
class SdfPipeline {
public:
  /// @throw Error when a setting is out of range, or (before anything is allocated) when the grids would
  ///        not fit the device's buffers and heap or the host's available memory (checkPipelineMemory).
  SdfPipeline(const gpu::VulkanContext& ctx, const Scene& scene, const Bounds& bounds, const PipelineSettings& s);
  /// @brief A pipeline on given (coarse, fine) @a grids (a cascade level's, CascadeLayout): the coarse grid shares
  ///        the fine one's corner and covers it.
  /// @throw Error as the other constructor; SettingError "cascades" when s.cascades is not 1 (a pipeline is one box).
  SdfPipeline(const gpu::VulkanContext& ctx, const Scene& scene, const std::pair<GridSpec, GridSpec>& grids,
              const PipelineSettings& s);
  ~SdfPipeline();
  SdfPipeline(const SdfPipeline&) = delete;
  SdfPipeline& operator=(const SdfPipeline&) = delete;

  /// @brief One frame at @a time seconds, one submission, of the passes whose inputs changed (planFrame; all with
  ///        PipelineSettings::fullRebuild, the same results): coarse SDF, the ray mask compacted on the GPU
  ///        (MaskCompactPass, MaskDispatchPass), upsample, refinement dispatched indirectly by the mask's size
  ///        (incremental unless PipelineSettings::fullRecompute: the boxes the instances swept since the previous
  ///        frame, movedInstanceBoxes, are the frame's only upload besides the BVH's top level). Only the mask's
  ///        counts (a few words) are read back, after the frame. submitFrame() then finishFrame().
  FrameStats runFrame(double time);
  /// @brief Record and submit the frame at @a time seconds without waiting for the GPU (a frame loop's call: the
  ///        host is free until the next frame). Waits first for the previous frame if it is still running (one
  ///        frame in flight: frames share their buffers); that frame's statistics are then lost. A frame whose
  ///        recording threw (a device out of memory, say) ran nothing on the GPU while the parts' host state moved
  ///        on: the next frame starts the pipeline's history over, as its first frame does.
  /// @throw Error when an instance leaves the supported coordinates at @a time (checkInstancePlacement).
  void submitFrame(double time);
  /// @brief Wait for the submitted frame and return its statistics (counts and pass times read back).
  /// @throw Error when no frame was submitted since the last finishFrame().
  FrameStats finishFrame();
  /// @brief Move the grids to @a grids, the same grids scrolled by whole bricks (scrollShift; a cascade level that
  ///        follows the camera), keeping what the pipeline knows: the refinement's history, the bricks and their
  ///        values, the dense fine SDF, shifted through @a scratch (at least as large as the dense fine SDF and the
  ///        coarse refinement state), and the coarse seeds and transform. The next frame voxelizes only the coarse
  ///        voxels that entered (and the moving instances' box; all of them with @a recut), transforms only what they
  ///        and the seeds that left reach (CoarseSdfBuilder::recordScroll: else the whole grid), and refines only the
  ///        band voxels new to it (those that entered, or that a surface entering made part of it),
  ///        with those moving instances reach:
  ///        what a pipeline built on @a grids would have, up to the float rounding of its frame (frameOrigin moves).
  ///        Waits for a frame in flight.
  /// @param recut where given, the pipeline's scene from now on (it must outlive the pipeline): the same world cut
  ///        again around @a grids (a cascade level, levelScene). Both scenes must hold every instance within
  ///        levelSceneMargin of their boxes: the voxels kept lie in the old box, so no instance in one scene and not
  ///        the other comes within the band of them, and they keep their values.
  /// @throw Error when @a grids are not a scroll of the grids (scrollShift) or @a scratch is too small; as the
  ///        constructor when @a recut's triangles do not fit (all checked before anything moves). A failure after
  ///        them (the device's) leaves the pipeline's buffers partly moved: build a new one (CascadeSet does).
  void scroll(const std::pair<GridSpec, GridSpec>& grids, const gpu::Buffer& scratch, const Scene* recut = nullptr);
  /// @brief From the next frame on, refine only the band within @a reach (world units; null: the whole band, as
  ///        built): the band voxels out of it keep the coarse SDF upsampled (no walk, no brick of their own) until
  ///        they come within it, new to the refinement then. A cascade level above 0 (CascadeSet::setView). A
  ///        change of reach runs the mask in the next frame.
  void setViewReach(const ViewReach* reach);
  /// @brief The fine voxels of the band the last frame left out of the view's reach (setViewReach), packed as
  ///        refinedVoxels' (x | y << 10 | z << 20), sorted; empty without a view limit. The frame must be finished.
  std::vector<std::uint32_t> outOfViewVoxels() const;
  /// @brief The bytes scroll() needs of its scratch buffer.
  std::uint64_t scrollScratchBytes() const;
  /// @brief The dense fine SDF of the last frame (x fastest), scene units: read back from the GPU
  ///        (FineStorage::Dense), or resolved on the host from the coarse SDF and the bricks read back (Sparse:
  ///        resolveFineCpu, the same values bit for bit).
  std::vector<float> fineField() const;
  /// @brief The last frame's fine SDF as a sparse level set of half-width @a band: the refined voxels (those under
  ///        the ray mask, less those out of the view's reach) with |f| <= @a band. Outside the mask the fine SDF is the coarse one upsampled, an unsigned
  ///        distance minus beta that can lie within the band deep inside a solid: it is left out. With d = 0 (nothing
  ///        refined) every voxel with |f| <= @a band. What a bake writes.
  openvdb::FloatGrid::Ptr levelSet(float band) const;
  /// @brief Bricks per axis of the fine grid.
  glm::ivec3 brickDims() const;
  /// @brief The pool's capacity in bricks (0 before the first frame sizes it).
  std::uint64_t poolBricks() const;
  /// @brief The last frame's coarse SDF (x fastest; read back from the GPU; empty before the first frame).
  std::vector<float> coarseField() const;
  /// @brief The box of the coarse voxels whose value the last coarse rebuild changed (gpu::shared::ChangedBox; the
  ///        upsampling after an instance moved covers the fine voxels near it). After a frame.
  gpu::shared::ChangedBox changedCoarseBox() const;
  /// @brief The last frame's ray mask, with its OpenVDB mirror: buildRayMask of the coarse SDF read back (the band
  ///        voxels MaskCompactPass counted; it keeps no list of them), the fine voxels sorted. Empty before the first
  ///        frame or when d = 0.
  RayMask rayMask() const;
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
  /// @brief Where the last frame wrote the dense fine SDF (fineBuffer()), for a copy of it kept up to date (the
  ///        renderer's 3D texture, VolumeUpdatePass): nowhere, everywhere, or the GPU's lists of the blocks its
  ///        upsampling wrote and the coarse voxels its refinement wrote, valid until the next frame is recorded.
  ///        Extent::Whole before the first frame.
  const DenseFineWrites& lastFineWrites() const { return mLastWrites; }
  /// @brief The coarse SDF on the GPU (dense, x fastest, coarseSpec()), valid after runFrame() or finishFrame().
  const gpu::Buffer& coarseBuffer() const;
  /// @brief The scene's BVH on the GPU, its top level as of the last runFrame(), in the frame of frameOrigin().
  const GpuSceneBvh& bvh() const { return *mBvh; }

private:
  friend class PipelineProbe;  // the parts' state, read back for tests
  friend class PipelineFaults; // a failure injected into a frame's recording, for tests
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
  /// The world box an instance's motion must meet to change the fields (InstanceMotion's reach): the fine grid
  /// grown by the band and the mask's reach pad.
  Bounds motionReach() const;
  /// The box the refinement asks the closed pieces' union about, in the BVH's frame (GpuSceneBvh::setUnionReach): the
  /// fine grid grown by a voxel for rounding.
  Bounds unionReach() const;
  /// Every part's buffers cleared as at construction, and the frame counts to 0: the next frame is a first frame
  /// (every pass over every voxel, the pool sized again).
  void restartHistory();
  /// Where the coarse grid lies on the world's seed lattice (seedLatticeCell), the BVH places the voxelization's
  /// triangles from the world's origin (GpuSceneBvh::setSeedOrigin).
  void placeSeedsOnLattice();
  const gpu::VulkanContext& mCtx;
  PipelineSettings mSettings;
  PipelineMemory mMemory;   ///< the estimate checked at construction (the pool is added when sized)
  GridSpec mCoarseSpec, mFineSpec;
  std::uint32_t mFrame = 0;
  /// Frames the mask ran (MaskCompactPass's frame numbers: the band's and the bricks' stamps count its runs, so a
  /// frame that skips it leaves every voxel as the run before left it).
  std::uint32_t mMaskFrame = 0;
  bool mPoolReset = false; ///< the pool was (re)allocated since the last frame was recorded
  bool mScrolled = false;  ///< the grids scrolled since the last frame was recorded
  bool mViewChanged = false; ///< the view's reach changed since the last frame was recorded
  /// A frame's recording began and was not submitted: the parts' host state (the motion's last time, the kept
  /// transform, the mask's boxes, the frame counts) ran ahead of the GPU's buffers, so the next frame restarts.
  bool mRecordingInterrupted = false;
  /// Tests (PipelineFaults): throw Error in the next frame's recording, after its coarse SDF is recorded.
  bool mFailNextRecording = false;
  /// Tests (PipelineFaults): throw Error in the next scroll, after its shifts are recorded, before the submit.
  bool mFailNextScroll = false;
  std::optional<ViewReach> mView; ///< setViewReach's
  FramePlan mPlan;         ///< the passes the last frame ran
  DenseFineWrites mLastWrites; ///< where the last frame wrote the dense fine SDF
  std::unique_ptr<GpuSceneBvh> mBvh;
  std::unique_ptr<InstanceMotion> mMotion;
  std::unique_ptr<FieldPasses> mFields;
  std::unique_ptr<GpuRayMask> mMask;
  std::unique_ptr<BrickPool> mPool;
  std::unique_ptr<GridShiftPass> mGridShift; ///< made by the first scroll on a GPU (a CPU device: transfers)
  std::unique_ptr<FrameRecorder> mRecorder;
};

} // namespace rtsdf
