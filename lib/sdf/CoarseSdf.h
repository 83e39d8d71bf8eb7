#pragma once
/// @file CoarseSdf.h
/// @brief The coarse SDF of the RTSDF pipeline, made on the GPU every frame: VoxelizePass (conservative
///        triangle/voxel overlap -> seed voxels), JumpFloodPass (3D jump flooding -> nearest seed per voxel)
///        and CoarseDistancePass (c = distance - beta).
#include "gpu/Profiler.h"
#include "gpu/Resources.h"
#include "gpu/shared/CoarseSdf.h"
#include "grid/GridSpec.h"
#include "scene/SceneGeometry.h"
#include "sdf/JumpFloodSteps.h"

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace rtsdf {

/// @brief VoxelizePass. Inputs: triangle corners (3 x vec4 each, world space), the grid. Output: seeds
///        (kNoSeed, or the voxel's own packed coordinate where a triangle touches its box).
class VoxelizePass {
public:
  static constexpr const char* kName = "VoxelizePass";
  explicit VoxelizePass(const gpu::VulkanContext& ctx);
  /// @param maxChunks the most chunks (params.chunkSize voxels each) any triangle's voxel range needs.
  void record(VkCommandBuffer cmd, const gpu::Buffer& corners, const gpu::shared::VoxelizeParams& params,
              std::uint32_t maxChunks, const gpu::Buffer& seeds, gpu::GpuProfiler* profiler) const;

private:
  gpu::ComputePipeline mPipeline;
};

/// @brief JumpFloodPass. Input: seeds in @a a. Output: the nearest seed per voxel, in @a a or @a b (the
///        returned one); the other is scratch.
class JumpFloodPass {
public:
  static constexpr const char* kName = "JumpFloodPass";
  explicit JumpFloodPass(const gpu::VulkanContext& ctx);
  const gpu::Buffer& record(VkCommandBuffer cmd, const gpu::Buffer& a, const gpu::Buffer& b, const glm::ivec3& dims,
                            JfaVariant variant, gpu::GpuProfiler* profiler) const;

private:
  gpu::ComputePipeline mPipeline;
};

/// @brief CoarseDistancePass. Input: nearest seeds. Output: c = |p - seed| * h - beta per voxel.
class CoarseDistancePass {
public:
  static constexpr const char* kName = "CoarseDistancePass";
  explicit CoarseDistancePass(const gpu::VulkanContext& ctx);
  void record(VkCommandBuffer cmd, const gpu::Buffer& nearest, const gpu::Buffer& distance,
              const gpu::shared::CoarseDistanceParams& params, gpu::GpuProfiler* profiler) const;

private:
  gpu::ComputePipeline mPipeline;
};

/// @brief Settings of the coarse SDF.
struct CoarseSdfSettings {
  JfaVariant variant = JfaVariant::OnePlusJfa;
  /// Subtracted from the seed distance (scene units); negative: half a voxel.
  double beta = -1.0;
  /// Read the nearest seeds back (tests, benchmarks); the pipeline needs only the distances.
  bool readNearest = true;
};

/// @brief A coarse SDF read back from the GPU, with the time of each pass.
struct CoarseSdf {
  GridSpec spec;
  float beta = 0.0f;
  std::vector<std::uint32_t> seeds;   ///< only when asked for (for tests)
  std::vector<std::uint32_t> nearest; ///< nearest seed per voxel (x fastest), if CoarseSdfSettings::readNearest
  std::vector<float> distance;        ///< c per voxel, scene units
  std::vector<std::pair<std::string, double>> passMs; ///< GPU time per pass, in recording order
  double passTotal(const std::string& pass) const;
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
  /// @brief The last build's coarse SDF on the GPU (x fastest), valid until the next build: later passes
  ///        read it in place instead of uploading the read-back copy again.
  const gpu::Buffer& distanceBuffer() const { return mDistanceBuf; }

private:
  const gpu::VulkanContext& mCtx;
  gpu::Buffer mCorners, mSeedsA, mSeedsB, mDistanceBuf;
  VoxelizePass mVoxelize;
  JumpFloodPass mJumpFlood;
  CoarseDistancePass mDistance;
  gpu::GpuProfiler mProfiler;
};

/// @brief The value stored where no seed exists: the grid's diagonal (no distance inside it is larger).
float emptySceneDistance(const GridSpec& spec);

} // namespace rtsdf
