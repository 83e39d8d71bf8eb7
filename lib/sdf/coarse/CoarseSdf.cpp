#include "sdf/coarse/CoarseSdf.h"

#include "sdf/coarse/CoarseCpu.h"
#include "sdf/coarse/CoarseScroll.h"
#include "sdf/pipeline/GridShift.h"
#include "util/Error.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstring>

namespace rtsdf {
using namespace gpu::shared;

VoxelizePass::VoxelizePass(const gpu::VulkanContext& ctx)
    : ComputePass(ctx, "voxelize.comp", kVoxelizeBindingCount, sizeof(VoxelizeParams)),
      mChunks(ctx, "voxelize_chunks.comp", kVoxelizeBindingCount, sizeof(VoxelizeParams)),
      mClear(ctx, "voxelize_clear.comp", kVoxelizeBindingCount, sizeof(VoxelizeParams)) {}

void VoxelizePass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                           const Params& params) const {
  const CoarseVoxelBox clip{glm::ivec3(params.shader.clipLo), glm::ivec3(params.shader.clipHi)};
  const glm::ivec3 dims(params.shader.dims);
  const bool clipEmpty = clip.empty();
  if (!clipEmpty && (glm::any(glm::lessThan(clip.lo, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(clip.hi, dims))))
    throw Error("VoxelizePass: the clip box lies partly outside the grid");
  gpu::ProfileScope scope(profiler, cmd, kName);
  std::array<gpu::Binding, kVoxelizeBindingCount> b;
  b[kVoxelizeBindingCorners] = &in.triangles.corners;
  b[kVoxelizeBindingInstances] = &in.triangles.instances;
  b[kVoxelizeBindingSeeds] = &out.seeds;
  b[kVoxelizeBindingDispatch] = &out.dispatch;
  b[kVoxelizeBindingPlaced] = &out.placed;
  b[kVoxelizeBindingLarge] = &out.large;
  // The clip box's seeds reset: the whole buffer at once, or one invocation per voxel of a part.
  if (regionVoxels(clip) == std::uint64_t(dims.x) * dims.y * dims.z)
    vkCmdFillBuffer(cmd, out.seeds.handle(), 0, VK_WHOLE_SIZE, kNoSeed);
  else if (!clipEmpty) {
    const glm::ivec3 n = clip.hi - clip.lo + 1;
    mClear.dispatch(cmd, b, &params.shader,
                    {gpu::groupsFor(n.x, RTSDF_JFA_GROUP_X), gpu::groupsFor(n.y, RTSDF_JFA_GROUP_Y),
                     gpu::groupsFor(n.z, RTSDF_JFA_GROUP_Z)});
  }
  // The first dispatch's x: one invocation per triangle; every other count is raised by voxelize_chunks.comp from 0
  // (no triangle touches the clip box, none listed).
  std::array<std::uint32_t, kVoxelizeDispatchWords> words{};
  words[kVoxelizeDispatchFirst] = gpu::groupsFor(params.shader.triangleCount, 64);
  gpu::recordUpload(cmd, out.dispatch, words.data(), sizeof(words));
  gpu::computeBarrier(cmd);
  if (!params.shader.triangleCount || clipEmpty) return;
  mChunks.dispatch(cmd, b, &params.shader, {words[kVoxelizeDispatchFirst], 1, 1});
  gpu::computeBarrier(cmd);
  VoxelizeParams shader = params.shader;
  shader.largePass = 0;
  mPipeline.dispatchIndirect(cmd, b, &shader, out.dispatch, kVoxelizeDispatchFirst * 4);
  gpu::computeBarrier(cmd); // both write seeds (the same value where two triangles touch a voxel)
  shader.largePass = 1;
  mPipeline.dispatchIndirect(cmd, b, &shader, out.dispatch, kVoxelizeDispatchLarge * 4);
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

std::vector<glm::ivec4> mergeLineRuns(std::vector<glm::ivec4> runs) {
  auto area = [](const glm::ivec4& r) { return std::int64_t(std::max(r.z - r.x, 0)) * std::max(r.w - r.y, 0); };
  // Two runs become their bounding run where it holds no more lines than the two (they overlap or touch; a line
  // outside both recomputes what it holds from current seeds): a scroll's two slabs span the same lines, and a line
  // run twice costs twice.
  for (bool merged = true; merged;) {
    merged = false;
    for (std::size_t i = 0; i < runs.size() && !merged; ++i)
      for (std::size_t j = i + 1; j < runs.size() && !merged; ++j) {
        const glm::ivec4 a = runs[i], b = runs[j];
        const glm::ivec4 bound(glm::min(a.x, b.x), glm::min(a.y, b.y), glm::max(a.z, b.z), glm::max(a.w, b.w));
        if (area(a) == 0 || area(b) == 0 || area(bound) <= area(a) + area(b)) {
          runs[i] = area(a) == 0 ? b : area(b) == 0 ? a : bound;
          runs.erase(runs.begin() + std::ptrdiff_t(j));
          merged = true;
        }
      }
  }
  return runs;
}

void ExactEdtPass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                           const Params& params) const {
  const bool keep = out.planes && out.nearest;
  if (params.changes && !keep)
    throw Error("ExactEdtPass: a build over what changed needs the planes and nearest seeds of the build before");
  gpu::ProfileScope scope(profiler, cmd, kName);
  const glm::ivec3 dims = params.dims;
  // Each axis reads the one before's output: seeds, x, y (planes), z (nearest).
  const std::array<const gpu::Buffer*, 4> stages{&in.seeds, &out.scratch, keep ? out.planes : &in.seeds,
                                                 keep ? out.nearest : &out.scratch};
  for (int axis = 0; axis < 3; ++axis) {
    ExactEdtParams p{};
    p.dims = glm::ivec4(dims, 0);
    p.axis = axis;
    const int na = axis == 0 ? dims.y : dims.x, nb = axis == 2 ? dims.y : dims.z;
    // Over what changed: the x lines crossing a change box (the x pass's output elsewhere is the last build's, kept
    // in the scratch), the y lines of the planes z one crosses (a box beyond the grid, seeds that left it, crosses
    // the lines and planes it spans), the z lines of the region's columns. Lines in two boxes run twice, alike.
    std::vector<glm::ivec4> runs{glm::ivec4(0, 0, na, nb)};
    if (params.changes && axis < 2) {
      runs.clear();
      for (const CoarseVoxelBox& c : *params.changes) {
        if (c.empty()) continue;
        const glm::ivec4 lines = axis == 0 ? glm::ivec4(c.lo.y, c.lo.z, c.hi.y + 1, c.hi.z + 1)
                                           : glm::ivec4(0, c.lo.z, na, c.hi.z + 1);
        runs.push_back(glm::clamp(lines, glm::ivec4(0), glm::ivec4(na, nb, na, nb)));
      }
      runs = mergeLineRuns(std::move(runs));
    }
    p.fromRegion = params.changes && axis == 2 ? 1 : 0;
    gpu::computeBarrier(cmd); // the previous axis (or pass) wrote src
    std::array<gpu::Binding, kExactEdtBindingCount> b;
    b[kExactEdtBindingSrc] = stages[axis];
    b[kExactEdtBindingDst] = stages[axis + 1];
    b[kExactEdtBindingLists] = &in.lists;
    if (p.fromRegion) {
      mPipeline.dispatchIndirect(cmd, b, &p, in.region, offsetof(CoarseRegion, edtGroups));
      continue;
    }
    for (const glm::ivec4& lines : runs) {
      p.lines = lines;
      if (lines.z > lines.x && lines.w > lines.y)
        mPipeline.dispatch(cmd, b, &p,
                           {gpu::groupsFor(std::uint32_t(lines.z - lines.x), RTSDF_EDT_GROUP_X),
                            std::uint32_t(lines.w - lines.y), 1});
    }
  }
  gpu::computeBarrier(cmd);
}

void CoarseRegionPass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                               const Params& params) const {
  if (params.changes.size() > RTSDF_COARSE_MAX_CHANGES)
    throw Error(fmt::format("CoarseRegionPass: {} change boxes, at most {}", params.changes.size(),
                            RTSDF_COARSE_MAX_CHANGES));
  gpu::ProfileScope scope(profiler, cmd, kName);
  vkCmdFillBuffer(cmd, out.lists.handle(), 0, std::uint64_t(coarseRegionZeroedWords(params.dims)) * 4, 0u);
  gpu::computeBarrier(cmd);
  CoarseRegionParams p{};
  p.dims = glm::ivec4(params.dims, RTSDF_COARSE_REGION_GROW);
  for (int k = 0; k < RTSDF_COARSE_MAX_CHANGES; ++k) { // the boxes not given are empty
    const CoarseVoxelBox c = std::size_t(k) < params.changes.size() ? params.changes[std::size_t(k)] : CoarseVoxelBox{};
    p.changeLo[k] = glm::ivec4(c.lo, 0);
    p.changeHi[k] = glm::ivec4(c.hi, 0);
  }
  std::array<gpu::Binding, kCoarseRegionBindingCount> b;
  b[kCoarseRegionBindingBlockMax] = &in.blockMax;
  b[kCoarseRegionBindingRegion] = &out.region;
  b[kCoarseRegionBindingLists] = &out.lists;
  // One invocation per block: at most 65535 groups along x (every device's limit), the rest along y.
  const glm::u64vec3 blocks(coarseBlockDims(params.dims));
  const std::uint32_t groups = gpu::groupsFor(blocks.x * blocks.y * blocks.z, RTSDF_COARSE_REGION_GROUP);
  const std::uint32_t groupsX = std::min<std::uint32_t>(groups, 65535u);
  mPipeline.dispatch(cmd, b, &p, {groupsX, (groups + groupsX - 1) / groupsX, 1});
  gpu::computeBarrier(cmd);
  p.dims.w = RTSDF_COARSE_REGION_DISPATCH;
  mPipeline.dispatch(cmd, b, &p, {1, 1, 1});
  gpu::computeBarrier(cmd); // its dispatches are read as indirect commands
}

void SeedShiftPass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                            const Params& params) const {
  const glm::ivec3 dims(params.dims);
  const VkDeviceSize bytes = VkDeviceSize(dims.x) * VkDeviceSize(dims.y) * VkDeviceSize(dims.z) * 4;
  if (in.source.size() < bytes || out.seeds.size() < bytes)
    throw Error(fmt::format("SeedShiftPass: a grid of {} bytes, a source of {} and seeds of {}", bytes,
                            in.source.size(), out.seeds.size()));
  gpu::ProfileScope scope(profiler, cmd, kName);
  std::array<gpu::Binding, kSeedShiftBindingCount> b;
  b[kSeedShiftBindingSource] = &in.source;
  b[kSeedShiftBindingSeeds] = &out.seeds;
  mPipeline.dispatch(cmd, b, &params,
                     {gpu::groupsFor(dims.x, RTSDF_JFA_GROUP_X), gpu::groupsFor(dims.y, RTSDF_JFA_GROUP_Y),
                      gpu::groupsFor(dims.z, RTSDF_JFA_GROUP_Z)});
}

CoarseRegionLists coarseRegionCpu(const std::vector<std::uint32_t>& blockMax, const glm::ivec3& dims,
                                  const CoarseVoxelBox& change) {
  return coarseRegionCpu(blockMax, dims, std::vector<CoarseVoxelBox>{change});
}

CoarseRegionLists coarseRegionCpu(const std::vector<std::uint32_t>& blockMax, const glm::ivec3& dims,
                                  const std::vector<CoarseVoxelBox>& changes) {
  const glm::ivec3 bd = coarseBlockDims(dims);
  CoarseRegionLists region;
  std::vector<bool> columnListed(std::size_t(bd.x) * bd.y, false);
  for (int z = 0; z < bd.z; ++z)
    for (int y = 0; y < bd.y; ++y)
      for (int x = 0; x < bd.x; ++x) {
        const glm::ivec3 lo = glm::ivec3(x, y, z) * RTSDF_COARSE_BLOCK;
        const glm::ivec3 hi = glm::min(lo + glm::ivec3(RTSDF_COARSE_BLOCK - 1), dims - 1);
        const auto block = std::uint32_t((z * bd.y + y) * bd.x + x);
        const bool reached = std::any_of(changes.begin(), changes.end(), [&](const CoarseVoxelBox& c) {
          return coarseBlockReached(lo, hi, c.lo, c.hi, blockMax.at(block));
        });
        if (!reached) continue;
        region.blocks.push_back(block);
        const glm::u64vec3 n = glm::u64vec3(hi - lo + 1);
        region.voxels += n.x * n.y * n.z;
        columnListed[std::size_t(y) * bd.x + x] = true;
      }
  for (std::size_t c = 0; c < columnListed.size(); ++c)
    if (columnListed[c]) region.columns.push_back(std::uint32_t(c));
  return region;
}

void CoarseDistancePass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in,
                                 const Outputs& out, const Params& params) const {
  gpu::ProfileScope scope(profiler, cmd, kName);
  std::array<gpu::Binding, kCoarseDistanceBindingCount> b;
  b[kCoarseDistanceBindingNearest] = &in.nearest;
  b[kCoarseDistanceBindingDistance] = &out.distance;
  b[kCoarseDistanceBindingChanged] = &out.changed;
  b[kCoarseDistanceBindingBlockMax] = &out.blockMax;
  b[kCoarseDistanceBindingLists] = &in.lists;
  b[kCoarseDistanceBindingChangedBlocks] = &out.changedBlocks;
  if (params.flags & kCoarseDistanceRegionOnly)
    mPipeline.dispatchIndirect(cmd, b, &params, in.region, offsetof(CoarseRegion, distanceGroups));
  else
    mPipeline.dispatch(cmd, b, &params,
                       {gpu::groupsFor(params.dims.x, RTSDF_JFA_GROUP_X),
                        gpu::groupsFor(params.dims.y, RTSDF_JFA_GROUP_Y),
                        gpu::groupsFor(params.dims.z, RTSDF_JFA_GROUP_Z)});
  gpu::computeBarrier(cmd);
}

float emptySceneDistance(const GridSpec& spec) { return float(glm::length(glm::dvec3(spec.dims)) * spec.voxelSize); }

CoarseSdfBuilder::CoarseSdfBuilder(const gpu::VulkanContext& ctx)
    : mCtx(ctx), mVoxelize(ctx), mSeedShift(ctx), mJumpFlood(ctx), mExactEdt(ctx), mRegionPass(ctx), mDistance(ctx),
      mProfiler(ctx) {}

VoxelizeInstance identityInstance(std::uint32_t triangleCount) {
  VoxelizeInstance inst{};
  for (int r = 0; r < 3; ++r) inst.objectToFrame[r][r] = 1.0f;
  inst.triangleCount = triangleCount;
  return inst;
}

CoarseSdf CoarseSdfBuilder::build(const SceneGeometry& geometry, const GridSpec& spec, const CoarseSdfSettings& settings,
                                  bool keepSeeds) {
  // The corners are relative to the geometry's frame: so is the grid they are voxelized on.
  CoarseSdf out = build(triangleCorners(geometry), spec.inFrame(geometry.origin), settings, keepSeeds);
  out.spec = spec;
  return out;
}

namespace {

// The first dispatch's chunks fit along y on every device and within any maxChunkGroups a caller may set.
static_assert(kVoxelizeFirstChunks <= kVoxelizeMinChunkGroups);
// coarse_distance.comp over listed blocks: a work group holds RTSDF_COARSE_REGION_BLOCKS_PER_GROUP whole blocks.
static_assert(RTSDF_JFA_GROUP_X * RTSDF_JFA_GROUP_Y * RTSDF_JFA_GROUP_Z ==
              RTSDF_COARSE_REGION_BLOCKS_PER_GROUP * RTSDF_COARSE_BLOCK * RTSDF_COARSE_BLOCK * RTSDF_COARSE_BLOCK);

/// CoarseSdfSettings::chunkVoxels resolved for a device and a grid of @a voxels.
std::uint32_t voxelizeChunkVoxels(const CoarseSdfSettings& settings, bool cpuDevice, std::uint64_t voxels) {
  if (settings.chunkVoxels && (settings.chunkVoxels < 16 || settings.chunkVoxels > 65536))
    throw Error(fmt::format("coarse SDF: {} voxels per voxelization invocation are outside [16, 65536]",
                            settings.chunkVoxels));
  std::uint64_t chunk = settings.chunkVoxels ? settings.chunkVoxels
                                             : (cpuDevice ? kVoxelizeChunkVoxelsCpu : kVoxelizeChunkVoxelsGpu);
  // A triangle's range lies inside the grid: its chunks must fit the groups along y times the layers along z.
  const std::uint64_t maxChunks = std::uint64_t(settings.maxChunkGroups) * kVoxelizeMaxChunkGroups;
  while ((voxels + chunk - 1) / chunk > maxChunks) chunk *= 2;
  return std::uint32_t(chunk);
}

} // namespace

CoarseSdfBuilder::Prepared CoarseSdfBuilder::prepare(const InstancedTriangles& triangles, const GridSpec& spec,
                                                     const CoarseSdfSettings& settings) {
  const glm::ivec3 dims = spec.dims;
  if (glm::any(glm::greaterThan(dims, glm::ivec3(kMaxSeedAxis))))
    throw Error(fmt::format("coarse SDF: grid {}x{}x{} exceeds the {} voxels per axis that seeds can address",
                            dims.x, dims.y, dims.z, kMaxSeedAxis));
  // One invocation per triangle along x, in groups of 64: the most groups any device runs along x.
  constexpr std::uint64_t kMaxTriangles = std::uint64_t(kVoxelizeMaxChunkGroups) * 64;
  if (triangles.triangleCount > kMaxTriangles)
    throw Error(fmt::format("coarse SDF: {} triangles are more than the {} one voxelization dispatch addresses",
                            triangles.triangleCount, kMaxTriangles));
  if (triangles.triangleCount && !triangles.instanceCount)
    throw Error("coarse SDF: triangles without an instance to place them");
  const std::uint64_t voxels = spec.voxelCount();
  Prepared p;
  p.voxelize.shader = voxelizeParams(spec, triangles.triangleCount, settings.seedLatticeCell);
  p.voxelize.shader.instanceCount = triangles.instanceCount;
  if (settings.maxChunkGroups < kVoxelizeMinChunkGroups || settings.maxChunkGroups > kVoxelizeMaxChunkGroups)
    throw Error(fmt::format("coarse SDF: {} chunk groups are outside [{}, {}]", settings.maxChunkGroups,
                            kVoxelizeMinChunkGroups, kVoxelizeMaxChunkGroups));
  p.voxelize.shader.maxChunkGroups = settings.maxChunkGroups;
  p.voxelize.shader.chunkSize = voxelizeChunkVoxels(settings, mCtx.info().typeName == "cpu", voxels);

  using gpu::Buffer;
  // Kept between builds: a frame loop allocates them once.
  const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  gpu::reserve(mCtx, mDispatch, kVoxelizeDispatchWords * 4, storage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
               Buffer::Memory::Device, "voxelize dispatch");
  gpu::reserve(mCtx, mLarge, std::uint64_t(triangles.triangleCount) * 4, storage, Buffer::Memory::Device,
               "voxelize large triangles");
  gpu::reserve(mCtx, mPlaced, std::uint64_t(triangles.triangleCount) * 3 * sizeof(glm::vec4), storage,
               Buffer::Memory::Device, "placed triangles");
  gpu::reserve(mCtx, mSeedsA, voxels * 4, storage, Buffer::Memory::Device, "seeds / transform A");
  gpu::reserve(mCtx, mSeedsB, voxels * 4, storage, Buffer::Memory::Device, "transform B");
  gpu::reserve(mCtx, mDistanceBuf, voxels * 4, storage, Buffer::Memory::Device, "coarse SDF");
  gpu::reserve(mCtx, mChangedBox, sizeof(ChangedBox), storage, Buffer::Memory::Device, "coarse SDF changed box");
  const glm::u64vec3 blocks(coarseBlockDims(dims));
  gpu::reserve(mCtx, mBlockMax, blocks.x * blocks.y * blocks.z * 4, storage, Buffer::Memory::Device,
               "coarse SDF block bounds");
  gpu::reserve(mCtx, mChangedBlocks, blocks.x * blocks.y * blocks.z * 4, storage, Buffer::Memory::Device,
               "coarse SDF changed blocks");
  // Host memory: a frame's statistics read it mapped (readRegion), without a copy.
  gpu::reserve(mCtx, mRegion, sizeof(CoarseRegion), storage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
               Buffer::Memory::Host, "coarse SDF region");
  gpu::reserve(mCtx, mRegionLists, std::uint64_t(coarseRegionListWords(dims)) * 4,
               storage, Buffer::Memory::Device, "coarse SDF region lists");
  p.keep = settings.keepTransform && settings.method == CoarseMethod::Edt;
  if (p.keep) {
    gpu::reserve(mCtx, mPlanes, voxels * 4, storage, Buffer::Memory::Device, "transform planes (kept)");
    gpu::reserve(mCtx, mNearest, voxels * 4, storage, Buffer::Memory::Device, "nearest seeds (kept)");
  }

  p.beta = float(settings.beta >= 0.0 ? settings.beta : 0.5 * spec.voxelSize);
  p.distance.dims = glm::ivec4(dims, 0);
  p.distance.voxelSize = float(spec.voxelSize);
  p.distance.beta = p.beta;
  p.distance.emptyDistance = emptySceneDistance(spec);
  p.flood = {dims, settings.method};
  return p;
}

InstancedTriangles CoarseSdfBuilder::uploadWorldCorners(const std::vector<glm::vec4>& corners) {
  if (corners.size() % 3) throw Error("coarse SDF: triangle corners must come in threes");
  const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  gpu::reserve(mCtx, mCorners, corners.size() * sizeof(glm::vec4), storage, gpu::Buffer::Memory::Device,
               "triangle corners");
  upload(mCtx, mCorners, corners.data(), corners.size() * sizeof(glm::vec4));
  const auto tris = std::uint32_t(corners.size() / 3);
  const VoxelizeInstance identity = identityInstance(tris);
  gpu::reserveAndUpload(mCtx, mIdentityInstance, &identity, sizeof(identity), storage, "identity instance");
  return {mCorners, mIdentityInstance, 1u, tris};
}

const gpu::Buffer& CoarseSdfBuilder::recordPasses(VkCommandBuffer cmd, gpu::GpuProfiler* profiler,
                                                  const InstancedTriangles& triangles, const Prepared& p,
                                                  const std::vector<CoarseVoxelBox>* changes,
                                                  const std::vector<CoarseVoxelBox>& boxes) const {
  const bool exact = !isJumpFlooding(p.flood.variant);
  const gpu::Buffer& nearest = exact ? (p.keep ? mNearest : mSeedsB)
                                     : JumpFloodPass::result({mSeedsA}, {mSeedsB}, p.flood);
  // Over what changed (or after a scroll): the triangles' seeds inside the boxes alone (the rest are kept).
  recordVoxelize(cmd, profiler, triangles, p, boxes);
  // Over what changed: the region from the last build's block bounds, before this build raises them.
  if (changes) mRegionPass.execute(cmd, nullptr, {mBlockMax}, {mRegion, mRegionLists}, {p.flood.dims, *changes});
  if (exact)
    mExactEdt.execute(cmd, profiler, {mSeedsA, mRegion, mRegionLists},
                      {mSeedsB, p.keep ? &mPlanes : nullptr, p.keep ? &mNearest : nullptr}, {p.flood.dims, changes});
  else
    mJumpFlood.execute(cmd, profiler, {mSeedsA}, {mSeedsB}, p.flood);
  // The box starts empty; the pass grows it over the voxels whose value changed. A full build that keeps its
  // transform raises the block bounds from zero (others leave them: no build over a change follows them).
  static const ChangedBox kEmpty{glm::uvec4(kChangedBoxEmptyLo), glm::uvec4(0u)};
  gpu::recordUpload(cmd, mChangedBox, &kEmpty, sizeof(kEmpty));
  if (p.keep && !changes) vkCmdFillBuffer(cmd, mBlockMax.handle(), 0, VK_WHOLE_SIZE, 0u);
  vkCmdFillBuffer(cmd, mChangedBlocks.handle(), 0, VK_WHOLE_SIZE, 0u);
  gpu::computeBarrier(cmd);
  CoarseDistanceParams distance = p.distance;
  distance.flags = (changes ? kCoarseDistanceRegionOnly : 0u) | (p.keep ? kCoarseDistanceKeepBounds : 0u);
  mDistance.execute(cmd, profiler, {nearest, mRegion, mRegionLists}, {mDistanceBuf, mChangedBox, mBlockMax, mChangedBlocks},
                    distance);
  return nearest;
}

void CoarseSdfBuilder::recordVoxelize(VkCommandBuffer cmd, gpu::GpuProfiler* profiler,
                                      const InstancedTriangles& triangles, const Prepared& p,
                                      const std::vector<CoarseVoxelBox>& boxes) const {
  const VoxelizePass::Outputs out{mSeedsA, mDispatch, mPlaced, mLarge};
  if (boxes.empty()) {
    mVoxelize.execute(cmd, profiler, {triangles}, out, p.voxelize);
    return;
  }
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    if (i) { // the last box's indirect dispatches read the words this one uploads, and its seeds are cleared again
      VkMemoryBarrier b{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
      b.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
      b.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
      vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT,
                           VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &b, 0,
                           nullptr, 0, nullptr);
    }
    VoxelizePass::Params voxelize = p.voxelize;
    voxelize.shader.clipLo = glm::ivec4(boxes[i].lo, 0);
    voxelize.shader.clipHi = glm::ivec4(boxes[i].hi, 0);
    mVoxelize.execute(cmd, profiler, {triangles}, out, voxelize);
  }
}

CoarseSdfBuilder::BuildPlan CoarseSdfBuilder::planBuild(const GridSpec& spec, const CoarseSdfSettings& settings,
                                                        const Prepared& p, const CoarseVoxelBox* change) {
  // The kept seeds, transform, distances and block bounds must be of this grid and beta, from a build that kept them.
  const bool sameCorner = mKeptCell ? mKeptCell == settings.seedLatticeCell
                                    : !settings.seedLatticeCell && mKeptOrigin == spec.origin;
  const bool sameGrid = mKeptDims == spec.dims && sameCorner && mKeptVoxel == spec.voxelSize && mKeptBeta == p.beta;
  BuildPlan plan;
  if (p.keep && sameGrid && !mSeedsKept.empty()) {
    if (mScrolled) { // the seeds that entered, and those of the change box
      plan.voxelize = boxesOutside(spec.dims, mSeedsKept);
      if (change && !change->empty()) plan.voxelize.push_back(*change);
      plan.changes = mScrollChanges;
      if (plan.changes && change && !change->empty()) plan.changes->push_back(*change);
    } else if (change) {
      plan.voxelize = {*change};
      plan.changes = std::vector<CoarseVoxelBox>{*change};
    }
  }
  mLastVoxelized = plan.voxelize.empty() ? spec.voxelCount() : 0; // none: the whole grid
  for (const CoarseVoxelBox& b : plan.voxelize) mLastVoxelized += regionVoxels(b);
  return plan;
}

float CoarseSdfBuilder::record(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const InstancedTriangles& triangles,
                               const GridSpec& spec, const CoarseSdfSettings& settings, const CoarseVoxelBox* change) {
  const Prepared p = prepare(triangles, spec, settings);
  const BuildPlan plan = planBuild(spec, settings, p, change);
  recordPasses(cmd, profiler, triangles, p, plan.changes ? &*plan.changes : nullptr, plan.voxelize);
  mLastOverChange = plan.changes.has_value();
  keepGrid(p.keep, spec, settings, p.beta);
  return p.beta;
}

void CoarseSdfBuilder::recordSeedShift(VkCommandBuffer cmd, const gpu::Buffer& buffer, const glm::ivec3& shift,
                                       const gpu::Buffer& scratch) const {
  const glm::ivec3 dims = mKeptDims;
  const VkDeviceSize bytes = VkDeviceSize(dims.x) * VkDeviceSize(dims.y) * VkDeviceSize(dims.z) * 4;
  if (scratch.size() < bytes)
    throw Error(fmt::format("coarse SDF: a scroll scratch of {} bytes, {} needed", scratch.size(), bytes));
  gpu::computeBarrier(cmd); // the scratch may still be read by another shift
  const VkBufferCopy whole{0, 0, bytes};
  vkCmdCopyBuffer(cmd, buffer.handle(), scratch.handle(), 1, &whole);
  gpu::computeBarrier(cmd);
  mSeedShift.execute(cmd, nullptr, {scratch}, {buffer}, {glm::ivec4(dims, 0), glm::ivec4(shift, 0)});
  gpu::computeBarrier(cmd);
}

void CoarseSdfBuilder::recordScroll(VkCommandBuffer cmd, const glm::ivec3& shift, const gpu::Buffer& scratch,
                                    bool sceneChanged, const GridShiftPass* gridShift) {
  const glm::ivec3 dims = mKeptDims;
  // Only seeds decided by their lattice cell are kept: decided in the grid's old frame, they could differ.
  if (sceneChanged || !mKeptCell || glm::any(glm::lessThan(dims, glm::ivec3(1))) || mSeedsKept.empty()) {
    mSeedsKept = {};
    return;
  }
  recordSeedShift(cmd, mSeedsA, shift, scratch);
  // The transform moves too where the shift is whole blocks (the block bounds move with them) and the last build
  // followed no other scroll: the next one runs over what the seeds that entered and those that left reach.
  const bool blocksWhole = glm::all(glm::equal(shift % RTSDF_COARSE_BLOCK, glm::ivec3(0)));
  const CoarseVoxelBox kept = keptByShift(dims, shift);
  if (blocksWhole && !mScrolled && !kept.empty()) {
    // The x pass's output is rewritten whole after a move along x (the two slabs cross every x line), the planes after
    // one along x or y (the slabs cross every plane z): those are not moved.
    if (shift.x == 0) recordSeedShift(cmd, mSeedsB, shift, scratch);
    if (shift.x == 0 && shift.y == 0) recordSeedShift(cmd, mPlanes, shift, scratch);
    recordSeedShift(cmd, mNearest, shift, scratch);
    recordGridShift(cmd, gridShift, mDistanceBuf, scratch, dims, 4, shift, 0u);
    recordGridShift(cmd, gridShift, mBlockMax, scratch, coarseBlockDims(dims), 4, shift / RTSDF_COARSE_BLOCK, 0u);
    mScrollChanges = scrollChanges(dims, shift);
  } else {
    mScrollChanges.reset();
  }
  // A voxel keeps its seed where v + shift was kept.
  const CoarseVoxelBox moved{mSeedsKept.lo - shift, mSeedsKept.hi - shift};
  mSeedsKept = {glm::max(moved.lo, kept.lo), glm::min(moved.hi, kept.hi)};
  *mKeptCell += shift; // the corner moved by the shift
  mScrolled = true;
}

void CoarseSdfBuilder::keepGrid(bool keep, const GridSpec& spec, const CoarseSdfSettings& settings, float beta) {
  mKeptDims = keep ? spec.dims : glm::ivec3(-1);
  mKeptOrigin = spec.origin;
  mKeptCell = settings.seedLatticeCell;
  mKeptVoxel = spec.voxelSize;
  mKeptBeta = beta;
  mSeedsKept = keep ? CoarseVoxelBox{glm::ivec3(0), spec.dims - 1} : CoarseVoxelBox{};
  mScrolled = false;
  mScrollChanges.reset();
}

gpu::shared::CoarseRegion CoarseSdfBuilder::readRegion() const {
  CoarseRegion r{};
  if (mRegion) std::memcpy(&r, mRegion.mapped(), sizeof(r));
  return r;
}

CoarseRegionLists CoarseSdfBuilder::readRegionLists(const glm::ivec3& dims) const {
  const CoarseRegion r = readRegion();
  std::vector<std::uint32_t> words(coarseRegionListWords(dims));
  download(mCtx, mRegionLists, words.data(), words.size() * 4);
  const auto columnsAt = std::ptrdiff_t(coarseRegionColumnsAt(dims));
  const auto blocksAt = std::ptrdiff_t(coarseRegionBlocksAt(dims));
  CoarseRegionLists out;
  out.columns.assign(words.begin() + columnsAt, words.begin() + columnsAt + std::ptrdiff_t(r.counts.y));
  out.blocks.assign(words.begin() + blocksAt, words.begin() + blocksAt + std::ptrdiff_t(r.counts.x));
  std::sort(out.columns.begin(), out.columns.end());
  std::sort(out.blocks.begin(), out.blocks.end());
  out.voxels = r.counts.z;
  return out;
}

std::vector<std::uint32_t> CoarseSdfBuilder::readBlockWords(const gpu::Buffer& buffer, const glm::ivec3& dims) const {
  const glm::u64vec3 blocks(coarseBlockDims(dims));
  std::vector<std::uint32_t> out(blocks.x * blocks.y * blocks.z);
  download(mCtx, buffer, out.data(), out.size() * 4);
  return out;
}

std::vector<std::uint32_t> CoarseSdfBuilder::readSeeds(const glm::ivec3& dims) const {
  std::vector<std::uint32_t> out(std::size_t(dims.x) * dims.y * dims.z);
  download(mCtx, mSeedsA, out.data(), out.size() * 4);
  return out;
}

CoarseSdf CoarseSdfBuilder::build(const std::vector<glm::vec4>& corners, const GridSpec& spec,
                                  const CoarseSdfSettings& settings, bool keepSeeds) {
  const InstancedTriangles triangles = uploadWorldCorners(corners);
  if (!keepSeeds) return build(triangles, spec, settings);
  const Prepared p = prepare(triangles, spec, settings);
  gpu::CommandBuffer cmd(mCtx);
  mVoxelize.execute(cmd.handle(), nullptr, {triangles}, {mSeedsA, mDispatch, mPlaced, mLarge}, p.voxelize);
  cmd.submitAndWait();
  std::vector<std::uint32_t> seeds(spec.voxelCount());
  download(mCtx, mSeedsA, seeds.data(), seeds.size() * 4);
  std::array<std::uint32_t, kVoxelizeDispatchWords> words{};
  download(mCtx, mDispatch, words.data(), sizeof(words));
  CoarseSdf out = build(triangles, spec, settings);
  out.seeds = std::move(seeds);
  out.largeTriangles = words[kVoxelizeLargeCount];
  return out;
}

CoarseSdf CoarseSdfBuilder::build(const InstancedTriangles& triangles, const GridSpec& spec,
                                  const CoarseSdfSettings& settings) {
  const Prepared p = prepare(triangles, spec, settings);
  const std::uint64_t voxels = spec.voxelCount();
  CoarseSdf out;
  out.spec = spec;
  out.beta = p.beta;
  gpu::CommandBuffer cmd(mCtx);
  mProfiler.reset(cmd.handle());
  const gpu::Buffer& nearest = recordPasses(cmd.handle(), &mProfiler, triangles, p);
  keepGrid(p.keep, spec, settings, p.beta);
  mLastOverChange = false;
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
