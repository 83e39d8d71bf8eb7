#include "sdf/CoarseSdf.h"

#include "sdf/CoarseReference.h"
#include "util/Error.h"

#include <fmt/format.h>

#include <array>
#include <cmath>

namespace rtsdf {
using namespace gpu::shared;

void VoxelizePass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                           const Params& params) const {
  gpu::ProfileScope scope(profiler, cmd, kName);
  vkCmdFillBuffer(cmd, out.seeds.handle(), 0, VK_WHOLE_SIZE, kNoSeed);
  gpu::computeBarrier(cmd);
  std::array<gpu::Binding, kVoxelizeBindingCount> b;
  b[kVoxelizeBindingCorners] = &in.corners;
  b[kVoxelizeBindingSeeds] = &out.seeds;
  if (params.shader.triangleCount)
    mPipeline.dispatch(cmd, b, &params.shader, {gpu::groupsFor(params.shader.triangleCount, 64), params.maxChunks, 1});
}

void JumpFloodPass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                            const Params& params) const {
  gpu::ProfileScope scope(profiler, cmd, kName);
  const gpu::Buffer* src = &in.seeds;
  const gpu::Buffer* dst = &out.scratch;
  const glm::ivec3 dims = params.dims;
  const glm::uvec3 groups(gpu::groupsFor(dims.x, RTSDF_JFA_GROUP_X), gpu::groupsFor(dims.y, RTSDF_JFA_GROUP_Y),
                          gpu::groupsFor(dims.z, RTSDF_JFA_GROUP_Z));
  for (int step : jumpFloodSteps(dims, params.variant)) {
    JumpFloodParams p{};
    p.dims = glm::ivec4(dims, 0);
    p.step = step;
    gpu::computeBarrier(cmd); // the previous step (or pass) wrote src
    std::array<gpu::Binding, kJumpFloodBindingCount> b;
    b[kJumpFloodBindingSrc] = src;
    b[kJumpFloodBindingDst] = dst;
    mPipeline.dispatch(cmd, b, &p, groups);
    std::swap(src, dst);
  }
  gpu::computeBarrier(cmd);
}

const gpu::Buffer& JumpFloodPass::result(const Inputs& in, const Outputs& out, const Params& params) {
  return jumpFloodSteps(params.dims, params.variant).size() % 2 ? out.scratch : in.seeds;
}

void ExactEdtPass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                           const Params& params) const {
  gpu::ProfileScope scope(profiler, cmd, kName);
  const glm::ivec3 dims = params.dims;
  const gpu::Buffer* src = &in.seeds;
  const gpu::Buffer* dst = &out.scratch;
  for (int axis = 0; axis < 3; ++axis) {
    ExactEdtParams p{};
    p.dims = glm::ivec4(dims, 0);
    p.axis = axis;
    const int na = axis == 0 ? dims.y : dims.x, nb = axis == 2 ? dims.y : dims.z;
    gpu::computeBarrier(cmd); // the previous axis (or pass) wrote src
    std::array<gpu::Binding, kExactEdtBindingCount> b;
    b[kExactEdtBindingSrc] = src;
    b[kExactEdtBindingDst] = dst;
    mPipeline.dispatch(cmd, b, &p, {gpu::groupsFor(na, RTSDF_EDT_GROUP_X), std::uint32_t(nb), 1});
    std::swap(src, dst);
  }
  gpu::computeBarrier(cmd);
}

void CoarseDistancePass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in,
                                 const Outputs& out, const Params& params) const {
  gpu::ProfileScope scope(profiler, cmd, kName);
  std::array<gpu::Binding, kCoarseDistanceBindingCount> b;
  b[kCoarseDistanceBindingNearest] = &in.nearest;
  b[kCoarseDistanceBindingDistance] = &out.distance;
  mPipeline.dispatch(cmd, b, &params,
                     {gpu::groupsFor(params.dims.x, RTSDF_JFA_GROUP_X), gpu::groupsFor(params.dims.y, RTSDF_JFA_GROUP_Y),
                      gpu::groupsFor(params.dims.z, RTSDF_JFA_GROUP_Z)});
  gpu::computeBarrier(cmd);
}

float emptySceneDistance(const GridSpec& spec) { return float(glm::length(glm::dvec3(spec.dims)) * spec.voxelSize); }

CoarseSdfBuilder::CoarseSdfBuilder(const gpu::VulkanContext& ctx)
    : mCtx(ctx), mVoxelize(ctx), mJumpFlood(ctx), mExactEdt(ctx), mDistance(ctx), mProfiler(ctx) {}

CoarseSdf CoarseSdfBuilder::build(const SceneGeometry& geometry, const GridSpec& spec, const CoarseSdfSettings& settings,
                                  bool keepSeeds) {
  // The corners are relative to the geometry's frame: so is the grid they are voxelized on.
  CoarseSdf out = build(triangleCorners(geometry), spec.inFrame(geometry.origin), settings, keepSeeds);
  out.spec = spec;
  return out;
}

CoarseSdfBuilder::Prepared CoarseSdfBuilder::prepare(const std::vector<glm::vec4>& corners, const GridSpec& spec,
                                                     const CoarseSdfSettings& settings) {
  const glm::ivec3 dims = spec.dims;
  if (glm::any(glm::greaterThan(dims, glm::ivec3(kMaxSeedAxis))))
    throw Error(fmt::format("coarse SDF: grid {}x{}x{} exceeds the {} voxels per axis that seeds can address",
                            dims.x, dims.y, dims.z, kMaxSeedAxis));
  if (corners.size() % 3) throw Error("coarse SDF: triangle corners must come in threes");
  const std::uint64_t voxels = spec.voxelCount();
  const std::uint32_t tris = std::uint32_t(corners.size() / 3);
  Prepared p;
  p.voxelize.shader = voxelizeParams(spec, tris);
  const VoxelizeParams& vp = p.voxelize.shader;
  // The most chunks any triangle's voxel range needs: the second dispatch dimension of VoxelizePass.
  for (std::uint32_t t = 0; t < tris; ++t) {
    const vec3 t0 = toVoxelSpace(glm::vec3(corners[3 * t]), vp.originInvH);
    const vec3 t1 = toVoxelSpace(glm::vec3(corners[3 * t + 1]), vp.originInvH);
    const vec3 t2 = toVoxelSpace(glm::vec3(corners[3 * t + 2]), vp.originInvH);
    const glm::ivec3 n = voxelRangeHi(t0, t1, t2, dims) - voxelRangeLo(t0, t1, t2) + 1;
    if (n.x > 0 && n.y > 0 && n.z > 0)
      p.voxelize.maxChunks = std::max(p.voxelize.maxChunks, gpu::groupsFor(std::uint64_t(n.x) * n.y * n.z, vp.chunkSize));
  }

  using gpu::Buffer;
  // Kept between builds: a frame loop allocates them once.
  const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  gpu::reserve(mCtx, mCorners, corners.size() * sizeof(glm::vec4), storage, Buffer::Memory::Device, "triangle corners");
  upload(mCtx, mCorners, corners.data(), corners.size() * sizeof(glm::vec4));
  gpu::reserve(mCtx, mSeedsA, voxels * 4, storage, Buffer::Memory::Device, "seeds / transform A");
  gpu::reserve(mCtx, mSeedsB, voxels * 4, storage, Buffer::Memory::Device, "transform B");
  gpu::reserve(mCtx, mDistanceBuf, voxels * 4, storage, Buffer::Memory::Device, "coarse SDF");

  p.beta = float(settings.beta >= 0.0 ? settings.beta : 0.5 * spec.voxelSize);
  p.distance.dims = glm::ivec4(dims, 0);
  p.distance.voxelSize = float(spec.voxelSize);
  p.distance.beta = p.beta;
  p.distance.emptyDistance = emptySceneDistance(spec);
  p.flood = {dims, settings.method};
  return p;
}

const gpu::Buffer& CoarseSdfBuilder::recordPasses(VkCommandBuffer cmd, gpu::GpuProfiler* profiler,
                                                  const Prepared& p) const {
  const bool exact = !isJumpFlooding(p.flood.variant);
  const gpu::Buffer& nearest = exact ? mSeedsB : JumpFloodPass::result({mSeedsA}, {mSeedsB}, p.flood);
  mVoxelize.execute(cmd, profiler, {mCorners}, {mSeedsA}, p.voxelize);
  if (exact)
    mExactEdt.execute(cmd, profiler, {mSeedsA}, {mSeedsB}, {p.flood.dims});
  else
    mJumpFlood.execute(cmd, profiler, {mSeedsA}, {mSeedsB}, p.flood);
  mDistance.execute(cmd, profiler, {nearest}, {mDistanceBuf}, p.distance);
  return nearest;
}

float CoarseSdfBuilder::record(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const SceneGeometry& geometry,
                               const GridSpec& spec, const CoarseSdfSettings& settings) {
  const Prepared p = prepare(triangleCorners(geometry), spec.inFrame(geometry.origin), settings);
  recordPasses(cmd, profiler, p);
  return p.beta;
}

CoarseSdf CoarseSdfBuilder::build(const std::vector<glm::vec4>& corners, const GridSpec& spec,
                                  const CoarseSdfSettings& settings, bool keepSeeds) {
  const Prepared p = prepare(corners, spec, settings);
  const std::uint64_t voxels = spec.voxelCount();
  CoarseSdf out;
  out.spec = spec;
  out.beta = p.beta;
  if (keepSeeds) {
    gpu::CommandBuffer cmd(mCtx);
    mVoxelize.execute(cmd.handle(), nullptr, {mCorners}, {mSeedsA}, p.voxelize);
    cmd.submitAndWait();
    out.seeds.resize(voxels);
    download(mCtx, mSeedsA, out.seeds.data(), voxels * 4);
  }
  gpu::CommandBuffer cmd(mCtx);
  mProfiler.reset(cmd.handle());
  const gpu::Buffer& nearest = recordPasses(cmd.handle(), &mProfiler, p);
  cmd.submitAndWait();
  out.passMs = mProfiler.results();
  out.distance.resize(voxels);
  if (settings.readNearest) {
    out.nearest.resize(voxels);
    download(mCtx, nearest, out.nearest.data(), voxels * 4);
  }
  download(mCtx, mDistanceBuf, out.distance.data(), voxels * 4);
  return out;
}

} // namespace rtsdf
