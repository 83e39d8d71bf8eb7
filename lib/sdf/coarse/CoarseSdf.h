#pragma once
/// @file CoarseSdf.h
/// @brief The coarse SDF of the RTSDF pipeline, made on the GPU every frame: VoxelizePass (conservative
///        triangle/voxel overlap -> seed voxels), ExactEdtPass (exact feature transform) or JumpFloodPass (3D
///        jump flooding, the paper's) -> nearest seed per voxel, and CoarseDistancePass (c = distance - beta).
#include "gpu/ComputePass.h"
#include "gpu/Profiler.h"
#include "gpu/Resources.h"
#include "sdf/coarse/CoarseParams.h"
#include "grid/GridSpec.h"
#include "scene/SceneGeometry.h"
#include "sdf/coarse/CoarseMethod.h"
#include "util/PassTimes.h"

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace rtsdf {

class GridShiftPass; // sdf/pipeline/GridShift.h

// The passes have the shape of gpu/ComputePass.h; buffers are bound at the indices sdf/coarse/CoarseParams.h names.

/// @brief Triangles placed by instance transforms on the GPU: what VoxelizePass reads. A list of world-space
///        triangles is one instance with the identity transform.
struct InstancedTriangles {
  const gpu::Buffer& corners;       ///< 3 x vec4 per mesh triangle, in its mesh's space
  const gpu::Buffer& instances;     ///< gpu::shared::VoxelizeInstance per instance, by firstInstanceTriangle
  std::uint32_t instanceCount = 0;
  std::uint32_t triangleCount = 0;  ///< every instance's triangles together
};

/// @brief VoxelizePass: conservative triangle/voxel overlap. Output: seeds (kNoSeed, or the voxel's own packed
///        coordinate where a triangle touches its box) inside the clip box params.shader.clipLo..clipHi: the whole
///        grid, or in a build over a change the box outside which the seeds are the last build's (those stay). The
///        box's seeds are reset (a fill of the whole buffer, or voxelize_clear.comp over a part); voxelize_chunks.comp
///        places every triangle in voxel space, counts the chunks (params.shader.chunkSize voxels) of its range inside
///        the box and lists the triangles with more than kVoxelizeFirstChunks in @a large; voxelize.comp runs
///        indirectly from @a dispatch, over the others, then over the listed ones. The host neither transforms nor
///        scans a triangle.
class VoxelizePass : gpu::ComputePass {
public:
  static constexpr const char* kName = "VoxelizePass";
  struct Inputs { InstancedTriangles triangles; };
  struct Outputs {
    const gpu::Buffer& seeds;
    /// kVoxelizeDispatchWords uints, VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT: voxelize.comp's two dispatches
    const gpu::Buffer& dispatch;
    const gpu::Buffer& placed;   ///< scratch: 3 x vec4 per triangle (its corners in voxel space)
    const gpu::Buffer& large;    ///< scratch: a uint per triangle (those listed for the second dispatch)
  };
  struct Params { gpu::shared::VoxelizeParams shader; };
  explicit VoxelizePass(const gpu::VulkanContext& ctx);
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;

private:
  gpu::ComputePipeline mChunks; // voxelize_chunks.comp
  gpu::ComputePipeline mClear;  // voxelize_clear.comp
};

/// @brief JumpFloodPass: 3D jump flooding, ping-ponging between the seeds and a scratch buffer. The nearest
///        seed per voxel ends in whichever of the two result() names; the other holds the last-but-one step.
class JumpFloodPass : gpu::ComputePass {
public:
  static constexpr const char* kName = "JumpFloodPass";
  struct Inputs { const gpu::Buffer& seeds; };     ///< overwritten by the even steps
  struct Outputs { const gpu::Buffer& scratch; };  ///< written by the odd steps
  struct Params {
    glm::ivec3 dims{0};
    CoarseMethod variant = CoarseMethod::OnePlusJfa; ///< a jump-flooding variant
  };
  explicit JumpFloodPass(const gpu::VulkanContext& ctx)
      : ComputePass(ctx, "jump_flood.comp", gpu::shared::kJumpFloodBindingCount,
                    sizeof(gpu::shared::JumpFloodParams)) {}
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;
  /// @brief The buffer that holds the nearest seeds after execute() with the same arguments.
  static const gpu::Buffer& result(const Inputs& in, const Outputs& out, const Params& params);
};

/// @brief A box of coarse voxels, inclusive (empty where any lo > hi).
struct CoarseVoxelBox {
  glm::ivec3 lo{0};
  glm::ivec3 hi{-1};
  bool empty() const { return glm::any(glm::greaterThan(lo, hi)); }
};

/// @brief ExactEdtPass: the exact nearest seed per voxel by a separable feature transform, one dispatch per axis, one
///        invocation per grid line. Any dims up to kMaxSeedAxis per axis. Without @a planes and @a nearest: x: seeds
///        -> scratch, y: scratch -> seeds, z: seeds -> scratch (the result). With them (kept from build to build):
///        x: seeds -> scratch, y: scratch -> planes, z: planes -> nearest, all three kept; and then Params::changes
///        may restrict the build to what a change of seeds inside those boxes reaches: the x lines crossing one (the
///        others keep their output in @a scratch), the y lines of the planes z crossing one (the planes elsewhere
///        hold the same seeds), and the z lines of the columns listed in @a lists (CoarseRegionPass; dispatched
///        indirectly from @a region). @a lists is bound in any case.
class ExactEdtPass : gpu::ComputePass {
public:
  static constexpr const char* kName = "ExactEdtPass";
  struct Inputs {
    const gpu::Buffer& seeds;  ///< overwritten by the y pass unless @a planes is given
    const gpu::Buffer& region; ///< gpu::shared::CoarseRegion: the indirect dispatch with Params::change
    const gpu::Buffer& lists;  ///< its lists (coarseRegionListWords), read with Params::change
  };
  struct Outputs {
    const gpu::Buffer& scratch;             ///< the x pass's output (kept with @a planes and @a nearest); the
                                            ///< nearest seeds unless @a nearest is given
    const gpu::Buffer* planes = nullptr;    ///< the y pass's output, kept (the nearest seed in each plane z)
    const gpu::Buffer* nearest = nullptr;   ///< the nearest seeds, kept
  };
  struct Params {
    glm::ivec3 dims{0};
    /// Where given: the boxes outside which the seeds are those of the build before, which wrote @a planes and
    /// @a nearest on the same grid (or moved them as its grid scrolled: a box beyond the grid holds seeds that left).
    const std::vector<CoarseVoxelBox>* changes = nullptr;
  };
  explicit ExactEdtPass(const gpu::VulkanContext& ctx)
      : ComputePass(ctx, "exact_edt.comp", gpu::shared::kExactEdtBindingCount, sizeof(gpu::shared::ExactEdtParams)) {}
  /// @throw Error where Params::changes is given without @a planes and @a nearest.
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;
};

/// @brief Runs of grid lines (a in [x, z), b in [y, w)) that cover @a runs' lines: two merged into their bounding run
///        wherever it holds no more lines than the two, so that ExactEdtPass runs no line twice where the boxes of a
///        change share them (a line outside every box costs its time, nothing else: its seeds are current).
std::vector<glm::ivec4> mergeLineRuns(std::vector<glm::ivec4> runs);

/// @brief CoarseRegionPass: the region a change of seeds inside boxes @a changes can reach: the blocks that
///        coarseBlockReached says a box lies within their seed distance, by @a blockMax of the last build, and
///        their columns of blocks, listed in @a lists (coarseRegionListWords words) and counted in @a region
///        (gpu::shared::CoarseRegion, reset first) with the indirect dispatches over them.
class CoarseRegionPass : gpu::ComputePass {
public:
  static constexpr const char* kName = "CoarseRegionPass";
  struct Inputs { const gpu::Buffer& blockMax; };
  struct Outputs { const gpu::Buffer& region, & lists; };
  struct Params {
    glm::ivec3 dims{0};
    std::vector<CoarseVoxelBox> changes; ///< at most RTSDF_COARSE_MAX_CHANGES; they may lie beyond the grid
  };
  explicit CoarseRegionPass(const gpu::VulkanContext& ctx)
      : ComputePass(ctx, "coarse_region.comp", gpu::shared::kCoarseRegionBindingCount,
                    sizeof(gpu::shared::CoarseRegionParams)) {}
  /// @throw Error with more than RTSDF_COARSE_MAX_CHANGES boxes.
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;
};

/// @brief CoarseRegionPass's region as the CPU copy gives it: its lists in ascending order, and its voxels.
struct CoarseRegionLists {
  std::vector<std::uint32_t> blocks;  ///< coarseBlockIndex of each listed block
  std::vector<std::uint32_t> columns; ///< bx + by * blocks along x of each column holding a listed block
  std::uint64_t voxels = 0;           ///< the listed blocks' voxels
};

/// @brief CPU copy of CoarseRegionPass: the region of @a changes on a grid of @a dims with the block bounds
///        @a blockMax.
CoarseRegionLists coarseRegionCpu(const std::vector<std::uint32_t>& blockMax, const glm::ivec3& dims,
                                  const std::vector<CoarseVoxelBox>& changes);
/// @brief The same for one box.
CoarseRegionLists coarseRegionCpu(const std::vector<std::uint32_t>& blockMax, const glm::ivec3& dims,
                                  const CoarseVoxelBox& change);

/// @brief The voxels of region @a r's box (0 when empty): a CoarseVoxelBox or a MaskRegion.
template <class Region> std::uint64_t regionVoxels(const Region& r) {
  if (r.lo.x > r.hi.x || r.lo.y > r.hi.y || r.lo.z > r.hi.z) return 0;
  const glm::u64vec3 n = glm::u64vec3(r.hi) - glm::u64vec3(r.lo) + glm::u64vec3(1);
  return n.x * n.y * n.z;
}

/// @brief SeedShiftPass (seed_shift.comp): the seeds or nearest seeds of a grid that scrolled by whole voxels,
///        moved: voxel v takes what v + shift held, a packed seed u becoming u - shift, kNoSeed where v + shift or
///        u - shift lies outside the grid (a seed buffer's seeds are their own voxels: they move with them). @a source
///        is a copy of the buffer before (it must not alias it).
class SeedShiftPass : gpu::ComputePass {
public:
  static constexpr const char* kName = "SeedShiftPass";
  struct Inputs { const gpu::Buffer& source; };
  struct Outputs { const gpu::Buffer& seeds; };
  using Params = gpu::shared::SeedShiftParams;
  explicit SeedShiftPass(const gpu::VulkanContext& ctx)
      : ComputePass(ctx, "seed_shift.comp", gpu::shared::kSeedShiftBindingCount, sizeof(Params)) {}
  /// @throw Error when a buffer is smaller than the grid.
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;
};

/// @brief CoarseDistancePass: c = |p - nearest seed| * h - beta per voxel, the box of the voxels whose c differs
///        from what @a distance held (gpu::shared::ChangedBox, grown: the caller resets it), and per block of
///        RTSDF_COARSE_BLOCK^3 voxels, with kCoarseDistanceKeepBounds, @a blockMax raised to at least each voxel's
///        squared seed distance (the caller zeroes it for a full build), and per block @a changedBlocks or'd with
///        changedBlockReach of each voxel whose c changed (the caller zeroes it). With kCoarseDistanceRegionOnly,
///        over the blocks listed in @a lists alone (dispatched indirectly from @a region); @a lists and @a blockMax
///        are bound in any case.
class CoarseDistancePass : gpu::ComputePass {
public:
  static constexpr const char* kName = "CoarseDistancePass";
  struct Inputs { const gpu::Buffer& nearest, & region, & lists; };
  struct Outputs { const gpu::Buffer& distance, & changed, & blockMax, & changedBlocks; };
  using Params = gpu::shared::CoarseDistanceParams;
  explicit CoarseDistancePass(const gpu::VulkanContext& ctx)
      : ComputePass(ctx, "coarse_distance.comp", gpu::shared::kCoarseDistanceBindingCount, sizeof(Params)) {}
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;
};

/// @brief Settings of the coarse SDF.
struct CoarseSdfSettings {
  CoarseMethod method = CoarseMethod::Edt;
  /// Subtracted from the seed distance (scene units); negative: half a voxel.
  double beta = -1.0;
  /// Read the nearest seeds back (tests, benchmarks); the pipeline needs only the distances.
  bool readNearest = true;
  /// The most work groups VoxelizePass runs along y (kVoxelizeMinChunkGroups to kVoxelizeMaxChunkGroups, which
  /// every device allows): the chunks of a larger range go in layers along z. Lower only to test the layers.
  std::uint32_t maxChunkGroups = gpu::shared::kVoxelizeMaxChunkGroups;
  /// Voxels of a triangle's range that one VoxelizePass invocation tests (16 to 65536); 0: the device's
  /// default, kVoxelizeChunkVoxelsCpu on a CPU device (lavapipe: every invocation costs, loops are cheap) and
  /// kVoxelizeChunkVoxelsGpu on a GPU (one long loop stalls the whole pass). Raised (doubled) where a grid's
  /// chunks would not fit maxChunkGroups x 65535 work groups.
  std::uint32_t chunkVoxels = 0;
  /// Keep the exact transform's planes and nearest seeds in buffers of their own (8 more bytes per voxel; Edt only),
  /// so that a later record() on the same grid can build over what changed.
  bool keepTransform = false;
  /// Where given: the grid's corner is this cell of the lattice of its voxel size from its frame's origin (the
  /// spec's origin is that many voxels from it: seedLatticeCell()), and the triangles are placed from that origin,
  /// so that each voxel's seed is decided by its lattice cell alone wherever the grid lies: the seeds a scroll keeps
  /// (recordScroll) equal a full build's. None: the grid is its own lattice (its corner the cell 0).
  std::optional<glm::ivec3> seedLatticeCell;
};

/// @brief A coarse SDF read back from the GPU, with the time of each pass.
struct CoarseSdf {
  GridSpec spec;
  float beta = 0.0f;
  std::vector<std::uint32_t> seeds;   ///< only when asked for (for tests)
  std::uint32_t largeTriangles = 0;   ///< with the seeds: the triangles VoxelizePass listed for its second dispatch
  std::vector<std::uint32_t> nearest; ///< nearest seed per voxel (x fastest), if CoarseSdfSettings::readNearest
  std::vector<float> distance;        ///< c per voxel, scene units
  PassTimes passMs;                   ///< GPU time per pass, in recording order
  double passTotal(const std::string& pass) const { return rtsdf::passTotal(passMs, pass); }
};

/// @brief Runs the three passes for a scene on a grid and reads the result back.
class CoarseSdfBuilder {
public:
  explicit CoarseSdfBuilder(const gpu::VulkanContext& ctx);
  /// @throw Error when the grid exceeds 1024 voxels per axis or the device's buffer limits.
  CoarseSdf build(const SceneGeometry& geometry, const GridSpec& spec, const CoarseSdfSettings& settings,
                  bool keepSeeds = false);
  /// @brief The same on raw triangle corners (3 per triangle; an empty list gives an empty scene).
  CoarseSdf build(const std::vector<glm::vec4>& corners, const GridSpec& spec, const CoarseSdfSettings& settings,
                  bool keepSeeds = false);
  /// @brief The same on triangles placed on the GPU (@a spec in the instances' frame).
  CoarseSdf build(const InstancedTriangles& triangles, const GridSpec& spec, const CoarseSdfSettings& settings);
  /// @brief Record the three passes into @a cmd without reading anything back or waiting: the coarse SDF is left
  ///        in distanceBuffer() for later passes of @a cmd. Scopes go to @a profiler (null: none), which the caller
  ///        reset on @a cmd. The host's cost does not depend on the triangles or the voxels.
  /// @param spec the grid in the instances' frame.
  /// @return beta as applied (scene units).
  /// @throw Error as build() does.
  /// @param change where given: the box (in this grid's voxels) outside which the triangles' seeds are those of the
  ///        last record(), so that the exact transform and the distances run over what a change there can reach
  ///        (ExactEdtPass, CoarseRegionPass) with the same result bit for bit; taken only where the last record() was
  ///        an Edt build with keepTransform on the same grid (dims, origin, voxel size) with the same beta, and so are
  ///        these settings (else: a full build). The triangles outside @a change must be the last record()'s.
  ///        After recordScroll(), the seeds it moved are kept whatever @a change is: the triangles are voxelized only
  ///        where they entered and inside @a change, and the transform and the distances run over the whole grid.
  float record(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const InstancedTriangles& triangles,
               const GridSpec& spec, const CoarseSdfSettings& settings, const CoarseVoxelBox* change = nullptr);
  /// @brief Record the move of the kept seeds of a grid that scrolled by @a shift voxels (the voxel at v takes what
  ///        v + shift held: SeedShiftPass, through @a scratch), so that the next record() on the grid voxelizes only
  ///        the voxels that entered. Where the shift is whole blocks (RTSDF_COARSE_BLOCK) and the last record()
  ///        followed no other scroll, the kept transform, distances and block bounds move too (SeedShiftPass;
  ///        recordGridShift by @a gridShift, or transfers where null), and the next record() transforms only what
  ///        the seeds that entered and those that left reach (scrollChanges, with its change box), bit for bit as a
  ///        full build. Nothing is recorded, and the next record() builds whole, where the last one kept no transform
  ///        on the seed lattice (CoarseSdfSettings::seedLatticeCell: seeds decided in the grid's old frame could
  ///        differ from a full build's) or @a sceneChanged (the triangles changed other than by the scroll).
  /// @throw Error when @a scratch is smaller than the seeds.
  void recordScroll(VkCommandBuffer cmd, const glm::ivec3& shift, const gpu::Buffer& scratch, bool sceneChanged,
                    const GridShiftPass* gridShift = nullptr);
  /// @brief Whether the last record() built over what changed (its change was taken).
  bool lastBuiltOverChange() const { return mLastOverChange; }
  /// @brief Whether a recordScroll() since the last record() moved the kept distances with the grid, so that the next
  ///        record() on it builds over what the scroll changed and its ChangedBox holds the voxels whose value differs
  ///        from their moved one.
  bool scrollMovedDistances() const { return mScrolled && mScrollChanges.has_value(); }
  /// @brief The voxels whose seeds the last record() voxelized: the grid's, or where it built over what changed
  ///        those of the change box, or after a scroll those that entered and the change box's.
  std::uint64_t lastVoxelizedVoxels() const { return mLastVoxelized; }
  /// @brief Read back the region of the last record() over what changed. Its command buffer must be finished.
  gpu::shared::CoarseRegion readRegion() const;
  /// @brief Read back the lists of that region (in ascending order) and its voxels, on a grid of @a dims. Its command
  ///        buffer must be finished.
  CoarseRegionLists readRegionLists(const glm::ivec3& dims) const;
  /// @brief Read back the block bounds of the squared seed distances (RTSDF_COARSE_BLOCK^3 voxels per block, x
  ///        fastest) of a grid of @a dims as the last record() on it left them. Its command buffer must be finished.
  std::vector<std::uint32_t> readBlockMax(const glm::ivec3& dims) const { return readBlockWords(mBlockMax, dims); }
  /// @brief Read back the seeds (VoxelizePass's output, x fastest) of a grid of @a dims as the last record() or
  ///        recordScroll() left them: meaningful where it kept its transform. Its command buffer must be finished.
  std::vector<std::uint32_t> readSeeds(const glm::ivec3& dims) const;
  /// @brief The last build's coarse SDF on the GPU (x fastest), valid until the next build: later passes
  ///        read it in place instead of uploading the read-back copy again.
  const gpu::Buffer& distanceBuffer() const { return mDistanceBuf; }
  /// @brief The box of the coarse voxels whose value the last build changed from the build before
  ///        (gpu::shared::ChangedBox; undefined after the buffer was (re)allocated: its old values were).
  const gpu::Buffer& changedBoxBuffer() const { return mChangedBox; }
  /// @brief Per block of RTSDF_COARSE_BLOCK^3 voxels, the changedBlockReach bits of its voxels whose value the last
  ///        record() changed (CoarseDistancePass).
  const gpu::Buffer& changedBlocksBuffer() const { return mChangedBlocks; }
  /// @brief Read back those marks of a grid of @a dims. Its command buffer must be finished.
  std::vector<std::uint32_t> readChangedBlocks(const glm::ivec3& dims) const {
    return readBlockWords(mChangedBlocks, dims);
  }

private:
  /// A word per block of a grid of @a dims in @a buffer, read back.
  std::vector<std::uint32_t> readBlockWords(const gpu::Buffer& buffer, const glm::ivec3& dims) const;
  struct Prepared {
    VoxelizePass::Params voxelize;
    JumpFloodPass::Params flood;
    gpu::shared::CoarseDistanceParams distance{};
    float beta = 0.0f;
    bool keep = false; ///< the kept transform's buffers are there
  };
  /// Check the grid and size the buffers: everything the passes need but the triangles and the recording.
  Prepared prepare(const InstancedTriangles& triangles, const GridSpec& spec, const CoarseSdfSettings& settings);
  /// Upload world-space corners as one instance with the identity transform.
  InstancedTriangles uploadWorldCorners(const std::vector<glm::vec4>& corners);
  /// Remember the grid, its lattice cell and beta the last record() built on, with whether its transform was kept
  /// (@a keep).
  void keepGrid(bool keep, const GridSpec& spec, const CoarseSdfSettings& settings, float beta);
  /// Record voxelize (over @a boxes; none: the whole grid), transform and distance (over what changed inside
  /// @a changes, where given); returns the buffer that holds the nearest seeds.
  const gpu::Buffer& recordPasses(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const InstancedTriangles& triangles,
                                  const Prepared& p, const std::vector<CoarseVoxelBox>* changes = nullptr,
                                  const std::vector<CoarseVoxelBox>& boxes = {}) const;
  /// Record SeedShiftPass on @a buffer (a grid of the kept dims) through @a scratch.
  void recordSeedShift(VkCommandBuffer cmd, const gpu::Buffer& buffer, const glm::ivec3& shift,
                       const gpu::Buffer& scratch) const;
  /// Record VoxelizePass over each of @a boxes in turn (none: the whole grid).
  void recordVoxelize(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const InstancedTriangles& triangles,
                      const Prepared& p, const std::vector<CoarseVoxelBox>& boxes) const;
  /// What record() voxelizes (none: the whole grid) and the change boxes its transform runs over (none: whole).
  struct BuildPlan {
    std::vector<CoarseVoxelBox> voxelize;
    std::optional<std::vector<CoarseVoxelBox>> changes;
  };
  /// The plan of a record() with @a change; sets mLastVoxelized.
  BuildPlan planBuild(const GridSpec& spec, const CoarseSdfSettings& settings, const Prepared& p,
                      const CoarseVoxelBox* change);
  const gpu::VulkanContext& mCtx;
  gpu::Buffer mCorners, mIdentityInstance, mDispatch, mPlaced, mLarge, mSeedsA, mSeedsB, mDistanceBuf, mChangedBox;
  gpu::Buffer mChangedBlocks; ///< CoarseDistancePass's marks of the blocks whose voxels changed
  gpu::Buffer mBlockMax, mRegion; ///< the block bounds (CoarseDistancePass) and the region of a build over changes
  gpu::Buffer mRegionLists;       ///< the region's lists (coarseRegionListWords)
  gpu::Buffer mPlanes, mNearest;  ///< kept transform (CoarseSdfSettings::keepTransform)
  glm::ivec3 mKeptDims{-1};       ///< the grid the kept transform and block bounds are of; -1: none
  glm::dvec3 mKeptOrigin{0.0};
  std::optional<glm::ivec3> mKeptCell; ///< its seedLatticeCell (then its origin is not compared)
  double mKeptVoxel = 0.0;
  float mKeptBeta = 0.0f;
  /// The voxels of the kept grid whose seeds are the scene's (the whole grid after a build that kept its transform,
  /// what stayed in the grid after recordScroll; empty: none).
  CoarseVoxelBox mSeedsKept;
  bool mScrolled = false; ///< recordScroll() moved the seeds since the last build
  /// The change boxes a scroll left the next build (scrollChanges), where it moved the transform too.
  std::optional<std::vector<CoarseVoxelBox>> mScrollChanges;
  bool mLastOverChange = false;
  std::uint64_t mLastVoxelized = 0;
  VoxelizePass mVoxelize;
  SeedShiftPass mSeedShift;
  JumpFloodPass mJumpFlood;
  ExactEdtPass mExactEdt;
  CoarseRegionPass mRegionPass;
  CoarseDistancePass mDistance;
  gpu::GpuProfiler mProfiler;
};

/// @brief The identity placement of @a triangleCount world-space triangles (what build() on corners uploads).
gpu::shared::VoxelizeInstance identityInstance(std::uint32_t triangleCount);

/// @brief GPU milliseconds of the nearest-seed transform in @a times: ExactEdtPass or JumpFloodPass, whichever ran.
inline double coarseTransformMs(const PassTimes& times) {
  return passTotal(times, ExactEdtPass::kName) + passTotal(times, JumpFloodPass::kName);
}

/// @brief The profiler name of the pass that runs @a method's transform.
inline const char* coarseTransformPass(CoarseMethod method) {
  return isJumpFlooding(method) ? JumpFloodPass::kName : ExactEdtPass::kName;
}

/// @brief The value stored where no seed exists: the grid's diagonal (no distance inside it is larger).
float emptySceneDistance(const GridSpec& spec);

} // namespace rtsdf
