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
#include <string>
#include <utility>
#include <vector>

namespace rtsdf {

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
///        coordinate where a triangle touches its box). Three dispatches: voxelize_chunks.comp places every triangle
///        in voxel space, counts the chunks (params.shader.chunkSize voxels) of its range and lists the triangles
///        with more than kVoxelizeFirstChunks in @a large; voxelize.comp runs indirectly from @a dispatch, over the
///        others, then over the listed ones. The host neither transforms nor scans a triangle.
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

/// @brief ExactEdtPass: the exact nearest seed per voxel by a separable feature transform, one dispatch per axis
///        (x: seeds -> scratch, y: scratch -> seeds, z: seeds -> scratch), one invocation per grid line. The
///        result ends in the scratch buffer. Any dims up to kMaxSeedAxis per axis.
class ExactEdtPass : gpu::ComputePass {
public:
  static constexpr const char* kName = "ExactEdtPass";
  struct Inputs { const gpu::Buffer& seeds; };    ///< overwritten by the y pass
  struct Outputs { const gpu::Buffer& scratch; }; ///< the nearest seeds
  struct Params { glm::ivec3 dims{0}; };
  explicit ExactEdtPass(const gpu::VulkanContext& ctx)
      : ComputePass(ctx, "exact_edt.comp", gpu::shared::kExactEdtBindingCount, sizeof(gpu::shared::ExactEdtParams)) {}
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;
};

/// @brief CoarseDistancePass: c = |p - nearest seed| * h - beta per voxel, and the box of the voxels whose c differs
///        from what @a distance held (gpu::shared::ChangedBox, grown: the caller resets it).
class CoarseDistancePass : gpu::ComputePass {
public:
  static constexpr const char* kName = "CoarseDistancePass";
  struct Inputs { const gpu::Buffer& nearest; };
  struct Outputs { const gpu::Buffer& distance, & changed; };
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
  float record(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const InstancedTriangles& triangles,
               const GridSpec& spec, const CoarseSdfSettings& settings);
  /// @brief The last build's coarse SDF on the GPU (x fastest), valid until the next build: later passes
  ///        read it in place instead of uploading the read-back copy again.
  const gpu::Buffer& distanceBuffer() const { return mDistanceBuf; }
  /// @brief The box of the coarse voxels whose value the last build changed from the build before
  ///        (gpu::shared::ChangedBox; undefined after the buffer was (re)allocated: its old values were).
  const gpu::Buffer& changedBoxBuffer() const { return mChangedBox; }

private:
  struct Prepared {
    VoxelizePass::Params voxelize;
    JumpFloodPass::Params flood;
    gpu::shared::CoarseDistanceParams distance{};
    float beta = 0.0f;
  };
  /// Check the grid and size the buffers: everything the passes need but the triangles and the recording.
  Prepared prepare(const InstancedTriangles& triangles, const GridSpec& spec, const CoarseSdfSettings& settings);
  /// Upload world-space corners as one instance with the identity transform.
  InstancedTriangles uploadWorldCorners(const std::vector<glm::vec4>& corners);
  /// Record voxelize, transform and distance; returns the buffer that holds the nearest seeds.
  const gpu::Buffer& recordPasses(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const InstancedTriangles& triangles,
                                  const Prepared& p) const;
  const gpu::VulkanContext& mCtx;
  gpu::Buffer mCorners, mIdentityInstance, mDispatch, mPlaced, mLarge, mSeedsA, mSeedsB, mDistanceBuf, mChangedBox;
  VoxelizePass mVoxelize;
  JumpFloodPass mJumpFlood;
  ExactEdtPass mExactEdt;
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
