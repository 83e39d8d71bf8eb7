#include "sdf/SdfPipeline.h"

#include "grid/VdbIO.h"
#include "sdf/refine/RefineParams.h"
#include "sdf/refine/RefinePasses.h"
#include "sdf/refine/RefineCpu.h"
#include "scene/SceneGeometry.h"
#include "util/Error.h"
#include "util/Memory.h"

#include <fmt/format.h>
#include <openvdb/tree/LeafManager.h>
#include <tbb/parallel_sort.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <mutex>
#include <tuple>

namespace rtsdf {
using gpu::Buffer;
using gpu::shared::RefineParams;

std::vector<gpu::shared::MovedBox> movedInstanceBoxes(const Scene& scene, const std::vector<Bounds>& meshBounds,
                                                      double before, double after, const glm::dvec3& origin) {
  std::vector<gpu::shared::MovedBox> boxes;
  for (const Instance& inst : scene.instances) {
    const glm::dmat4 m0 = inst.matrixAt(before), m1 = inst.matrixAt(after);
    const Bounds& local = meshBounds.at(inst.mesh);
    if (m0 == m1 || local.empty()) continue;
    Bounds swept;
    for (int corner = 0; corner < 8; ++corner) {
      const glm::dvec4 p((corner & 1 ? local.max : local.min).x, (corner & 2 ? local.max : local.min).y,
                         (corner & 4 ? local.max : local.min).z, 1.0);
      swept.add(glm::dvec3(m0 * p) - origin);
      swept.add(glm::dvec3(m1 * p) - origin);
    }
    gpu::shared::MovedBox box{};
    for (int a = 0; a < 3; ++a) {
      box.lo[a] = std::nextafter(float(swept.min[a]), -INFINITY);
      box.hi[a] = std::nextafter(float(swept.max[a]), INFINITY);
    }
    if (boxes.size() < RTSDF_MAX_MOVED_BOXES) {
      boxes.push_back(box);
    } else { // the shader reads a bounded list: the rest share the last box
      boxes.back().lo = glm::min(boxes.back().lo, box.lo);
      boxes.back().hi = glm::max(boxes.back().hi, box.hi);
    }
  }
  return boxes;
}

namespace {
std::string mib(std::uint64_t bytes) { return fmt::format("{:.1f} MiB", double(bytes) / (1024.0 * 1024.0)); }
} // namespace

std::string PipelineMemory::describe() const {
  return fmt::format("coarse {}x{}x{}, fine {}x{}x{}: largest buffer '{}' {}, device {}, host {}", coarse.dims.x,
                     coarse.dims.y, coarse.dims.z, fine.dims.x, fine.dims.y, fine.dims.z, largestBufferName,
                     mib(largestBuffer), mib(deviceBytes), mib(hostBytes));
}

PipelineMemory estimatePipelineMemory(const Bounds& bounds, const PipelineSettings& s, std::uint64_t triangles) {
  PipelineMemory m;
  std::tie(m.coarse, m.fine) = pipelineGrids(bounds, s);
  const std::uint64_t nc = m.coarse.voxelCount(), nf = m.fine.voxelCount();
  const bool dense = s.fineStorage == FineStorage::Dense;
  const std::uint64_t coarseBuf = nc * 4, fineBuf = dense ? nf * 4 : 0;
  if (fineBuf >= 2 * coarseBuf) { m.largestBuffer = fineBuf; m.largestBufferName = "fine SDF"; }
  else { m.largestBuffer = 2 * coarseBuf; m.largestBufferName = "coarse band list"; }
  const glm::uvec3 bricks = (glm::uvec3(m.fine.dims) + glm::uvec3(RTSDF_BRICK - 1)) / glm::uvec3(RTSDF_BRICK);
  // Seeds A/B, the coarse SDF, the compacted band (8 bytes per voxel), the refinement state (8 bytes per voxel) and
  // the refine list; the dense fine SDF; per brick its stamp and slot; the BVH (nodes of 32 bytes, at most two per
  // triangle, corners 48 bytes and ids 4 bytes per triangle), whose mesh-space corners VoxelizePass places in
  // voxel space (48 bytes per triangle).
  m.deviceBytes = 8 * coarseBuf + fineBuf + std::uint64_t(bricks.x) * bricks.y * bricks.z * 8 +
                  triangles * (64 + 48 + 4 + 48) + 4096;
  // Read-backs with their staging copies: the coarse SDF, the compacted band (8 bytes per voxel) and its
  // OpenVDB mirror (4 bytes and a mask bit per voxel at worst); the fine mask list and the fine SDF.
  m.hostBytes = nc * 29 + nf * 16;
  return m;
}

MemoryLimits memoryLimits(const gpu::DeviceInfo& device) {
  MemoryLimits l;
  l.maxStorageBufferRange = device.maxStorageBufferRange;
  l.deviceBytes = device.deviceLocalBytes;
  l.hostBytes = availableHostMemory();
  l.unifiedMemory = device.type == VK_PHYSICAL_DEVICE_TYPE_CPU;
  l.deviceName = device.name;
  return l;
}

void checkPipelineMemory(const PipelineMemory& need, const MemoryLimits& limits) {
  const std::string grids = fmt::format("coarse grid {}x{}x{}, fine grid {}x{}x{}", need.coarse.dims.x,
                                        need.coarse.dims.y, need.coarse.dims.z, need.fine.dims.x, need.fine.dims.y,
                                        need.fine.dims.z);
  const bool fine = need.largestBufferName == "fine SDF";
  const char* lower = fine ? "fine resolution" : "coarse resolution";
  if (limits.maxStorageBufferRange && need.largestBuffer > limits.maxStorageBufferRange)
    throw SettingError(lower, fmt::format("SdfPipeline: {}: buffer '{}' needs {}, more than {}'s "
                                          "maxStorageBufferRange of {}: lower the {}{}", grids, need.largestBufferName,
                                          mib(need.largestBuffer), limits.deviceName,
                                          mib(limits.maxStorageBufferRange), lower,
                                          fine ? ", or keep the fine SDF sparse (fine storage 'sparse')" : ""));
  if (limits.deviceBytes && need.deviceBytes > limits.deviceBytes)
    throw SettingError("fine resolution", fmt::format("SdfPipeline: {}: the device buffers need {}, more than {}'s "
                                                      "{} heap: lower the fine (and coarse) resolution", grids,
                                                      mib(need.deviceBytes), limits.deviceName,
                                                      mib(limits.deviceBytes)));
  const std::uint64_t host = need.hostBytes + (limits.unifiedMemory ? need.deviceBytes : 0);
  if (limits.hostBytes && host > limits.hostBytes)
    throw SettingError("fine resolution", fmt::format("SdfPipeline: {}: needs {} of host memory{}, more than the {} "
                                                      "available: lower the fine (and coarse) resolution", grids,
                                                      mib(host), limits.unifiedMemory ? " (device buffers included)"
                                                                                      : "", mib(limits.hostBytes)));
}

RayMask buildRayMask(const std::vector<float>& coarse, const GridSpec& cs, const GridSpec& fs, double band) {
  RayMask mask;
  if (band <= 0.0) return mask; // d = 0: nothing is refined, the fine SDF is the upsampled coarse one
  // The mask needs index space only. Voxels too small for an OpenVDB transform (scenes in tiny units) are
  // mirrored on the same grid measured in voxels: values and band divided by h, transform of voxel size 1.
  if (cs.voxelSize >= minVdbVoxelSize()) {
    mask.coarse = denseToLevelSet(coarse, cs, float(band));
  } else {
    GridSpec unit = cs;
    unit.voxelSize = 1.0;
    unit.origin = cs.origin / cs.voxelSize;
    std::vector<float> scaled(coarse.size());
    for (std::size_t i = 0; i < coarse.size(); ++i) scaled[i] = float(double(coarse[i]) / cs.voxelSize);
    // The same voxels must be active: |c| <= band exactly as in world units.
    const float unitBand = float(double(band) / cs.voxelSize);
    for (std::size_t i = 0; i < coarse.size(); ++i)
      if ((std::fabs(coarse[i]) <= float(band)) != (std::fabs(scaled[i]) <= unitBand))
        scaled[i] = std::fabs(coarse[i]) <= float(band) ? std::copysign(unitBand, scaled[i])
                                                         : std::copysign(std::nextafter(unitBand, INFINITY), scaled[i]);
    mask.coarse = denseToLevelSet(scaled, unit, unitBand);
  }
  mask.coarseVoxels = mask.coarse->activeVoxelCount();
  // Fine voxels whose centres fall in each active coarse voxel, leaf by leaf in parallel.
  openvdb::tree::LeafManager<const openvdb::FloatTree> leaves(mask.coarse->tree());
  std::mutex m;
  const std::vector<glm::ivec2> ranges = maskFineRanges(cs, fs);
  leaves.foreach([&](const openvdb::FloatTree::LeafNodeType& leaf, std::size_t) {
    std::vector<std::uint32_t> local;
    for (auto it = leaf.cbeginValueOn(); it; ++it) {
      const openvdb::Coord c = it.getCoord();
      appendFineVoxelsUnder(ranges, cs.dims, {c.x(), c.y(), c.z()}, 0u, local);
    }
    std::lock_guard<std::mutex> lock(m);
    mask.fineVoxels.insert(mask.fineVoxels.end(), local.begin(), local.end());
  });
  tbb::parallel_sort(mask.fineVoxels.begin(), mask.fineVoxels.end());
  return mask;
}

double FrameStats::refineMs() const {
  return passTotal(RayRefinePass::kName) + passTotal(ClosestRefinePass::kName);
}

struct SdfPipeline::Gpu {
  CoarseSdfBuilder coarse;
  MaskCompactPass compact;
  MaskDispatchPass maskDispatch;
  BrickAllocPass brickAlloc;
  UpsamplePass upsample;
  std::unique_ptr<RefinePass> refine; // RayRefinePass or ClosestRefinePass, by the mode
  gpu::GpuProfiler profiler;
  gpu::CommandBuffer frameCmd;        // every frame's, restarted per frame (its pool's memory is reused)
  Buffer fine;                        // the dense fine SDF (FineStorage::Dense only)
  Buffer coarseState;                 // per coarse voxel: last frame in the band, refinements in a row
  Buffer movedBoxes;                  // MovedBox per moving instance, written into the frame's command buffer
  Buffer fineRanges, fineToCoarse;    // maskFineRanges() and maskCoarseOfFine() of the grids, uploaded once
  Buffer counts;                      // the refinement's indirect dispatch, then the mask's counters
  Buffer countsReadback;              // the mask's and the bricks' counts, copied at the end of each frame
  Buffer refineList, coarseList;      // the coarse voxels to refine and the coarse band voxels (band > 0 only)
  // The sparse fine state: per brick the last frame it was needed and its slot; the free slots and their count;
  // the pool's pages of values and votes (pages beyond the pool bound to the placeholder).
  Buffer brickNeeded, brickSlots, brickFree, brickCounts, placeholder;
  Buffer samplingParams; // the frame's RefineParams, for shading passes that sample the bricks (Sparse only)
  Buffer values[RTSDF_BRICK_PAGES], votes[RTSDF_BRICK_PAGES];
  Gpu(const gpu::VulkanContext& ctx, RefineMode mode, const ClosestRefinePass::Variant& closest)
      : coarse(ctx), compact(ctx), maskDispatch(ctx), brickAlloc(ctx), upsample(ctx),
        refine(mode == RefineMode::Rays ? std::unique_ptr<RefinePass>(std::make_unique<RayRefinePass>(ctx))
                                        : std::make_unique<ClosestRefinePass>(ctx, closest)),
        profiler(ctx), frameCmd(ctx) {}
  BrickPages pages() const {
    BrickPages p{};
    for (int k = 0; k < RTSDF_BRICK_PAGES; ++k) {
      p.values[k] = values[k] ? &values[k] : &placeholder;
      p.votes[k] = votes[k] ? &votes[k] : &placeholder;
    }
    return p;
  }
};

namespace {
const VkBufferUsageFlags kStorage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
const VkBufferUsageFlags kStorageFilled = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
const VkBufferUsageFlags kStorageRead = kStorageFilled | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
constexpr std::uint32_t kReadbackWords = gpu::shared::kMaskCountWords + gpu::shared::kBrickCountWords;
} // namespace

SdfPipeline::SdfPipeline(const gpu::VulkanContext& ctx, const Scene& scene, const Bounds& bounds,
                         const PipelineSettings& s)
    : mCtx(ctx), mScene(scene), mSettings(s) {
  const bool cpuShaders = s.shaderTarget == ShaderTarget::Device ? ctx.info().type == VK_PHYSICAL_DEVICE_TYPE_CPU
                                                                 : s.shaderTarget == ShaderTarget::Cpu;
  // The settings in effect (settings()): the target and the search resolved for this device.
  mSettings.shaderTarget = cpuShaders ? ShaderTarget::Cpu : ShaderTarget::Gpu;
  if (s.closestSearch == ClosestSearch::Auto)
    mSettings.closestSearch = cpuShaders ? ClosestSearch::Cell : ClosestSearch::Voxel;
  const bool cellSearch = s.mode == RefineMode::Closest && mSettings.closestSearch == ClosestSearch::Cell;
  // Everything is checked before anything is allocated (the brick pool, sized by the first frame's band, then).
  std::uint64_t triangles = 0;
  for (const Instance& inst : scene.instances) triangles += scene.meshes.at(inst.mesh).triangles.size();
  mMemory = estimatePipelineMemory(bounds, s, triangles);
  checkPipelineMemory(mMemory, memoryLimits(ctx.info()));
  mCoarseSpec = mMemory.coarse;
  mFineSpec = mMemory.fine;
  mRefineParts = refinePartsFor(longestFineRuns(mCoarseSpec, mFineSpec), cellSearch);
  // The refinement's invocations (refineParts per listed coarse voxel) are counted in 32 bits.
  if (double(mCoarseSpec.voxelCount()) * mRefineParts.total() > 4294967295.0)
    throw SettingError("coarse resolution", fmt::format("SdfPipeline: coarse grid {} over fine grid {}: too many "
                                                        "refinement invocations; lower the fine resolution or raise "
                                                        "the coarse one", mCoarseSpec.describe(),
                                                        mFineSpec.describe()));
  mBvh = std::make_unique<GpuSceneBvh>(ctx, scene, frameOrigin());
  mGpu = std::make_unique<Gpu>(ctx, s.mode, ClosestRefinePass::Variant{s.rays > 0, cellSearch, cpuShaders});
  if (s.fineStorage == FineStorage::Dense)
    mGpu->fine = Buffer(ctx, mFineSpec.voxelCount() * 4, kStorage, Buffer::Memory::Device, "fine SDF");
  mGpu->coarseState = Buffer(ctx, mCoarseSpec.voxelCount() * 8, kStorageFilled, Buffer::Memory::Device,
                             "coarse refinement state");
  const std::vector<int> fineToCoarse = maskCoarseOfFine(mCoarseSpec, mFineSpec);
  gpu::reserveAndUpload(ctx, mGpu->fineToCoarse, fineToCoarse.data(), fineToCoarse.size() * sizeof(int), kStorage,
                        "ray mask fine-to-coarse table");
  const std::vector<glm::ivec2> ranges = maskFineRanges(mCoarseSpec, mFineSpec);
  gpu::reserveAndUpload(ctx, mGpu->fineRanges, ranges.data(), ranges.size() * sizeof(glm::ivec2), kStorage,
                        "ray mask fine ranges");
  mGpu->movedBoxes = Buffer(ctx, RTSDF_MAX_MOVED_BOXES * sizeof(gpu::shared::MovedBox),
                            kStorageFilled, Buffer::Memory::Device, "moved instance boxes");
  for (const Mesh& mesh : scene.meshes) mMeshBounds.push_back(positionBounds(mesh));
  using gpu::shared::kMaskCountWords;
  mGpu->counts = Buffer(ctx, kMaskCountWords * 4, kStorageRead | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
                        Buffer::Memory::Device, "ray mask counts");
  mGpu->countsReadback = Buffer(ctx, kReadbackWords * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT, Buffer::Memory::Host,
                                "ray mask counts (readback)");
  const glm::ivec3 bd = brickDims();
  const std::uint64_t bricks = std::uint64_t(bd.x) * bd.y * bd.z;
  mGpu->brickNeeded = Buffer(ctx, bricks * 4, kStorageFilled, Buffer::Memory::Device, "brick stamps");
  mGpu->brickSlots = Buffer(ctx, bricks * 4, kStorageRead, Buffer::Memory::Device, "brick slots");
  mGpu->brickCounts = Buffer(ctx, gpu::shared::kBrickCountWords * 4, kStorageRead, Buffer::Memory::Device,
                             "brick counts");
  mGpu->placeholder = Buffer(ctx, 16, kStorage, Buffer::Memory::Device, "brick pool placeholder");
  mGpu->samplingParams = Buffer(ctx, sizeof(RefineParams), kStorageFilled, Buffer::Memory::Device,
                                "brick sampling parameters");
  if (s.band > 0.0) {
    // Each coarse voxel is appended at most once to each list.
    mGpu->refineList = Buffer(ctx, mCoarseSpec.voxelCount() * 4, kStorageRead, Buffer::Memory::Device,
                              "refine list (coarse voxels)");
    mGpu->coarseList = Buffer(ctx, mCoarseSpec.voxelCount() * 8, kStorageRead, Buffer::Memory::Device,
                              "ray mask (coarse voxels)");
  }
  gpu::CommandBuffer cmd(ctx);
  vkCmdFillBuffer(cmd.handle(), mGpu->brickNeeded.handle(), 0, VK_WHOLE_SIZE, 0u);
  vkCmdFillBuffer(cmd.handle(), mGpu->brickSlots.handle(), 0, VK_WHOLE_SIZE, gpu::shared::kNoBrick);
  vkCmdFillBuffer(cmd.handle(), mGpu->brickCounts.handle(), 0, VK_WHOLE_SIZE, 0u);
  // No voxel has been in the band: last frame + 1 must differ from the first frame number (1).
  vkCmdFillBuffer(cmd.handle(), mGpu->coarseState.handle(), 0, VK_WHOLE_SIZE, 0xFFFFFFFFu);
  if (mGpu->fine) vkCmdFillBuffer(cmd.handle(), mGpu->fine.handle(), 0, VK_WHOLE_SIZE, 0u);
  vkCmdFillBuffer(cmd.handle(), mGpu->movedBoxes.handle(), 0, VK_WHOLE_SIZE, 0u);
  cmd.submitAndWait();
}

glm::ivec3 SdfPipeline::brickDims() const { return (mFineSpec.dims + (RTSDF_BRICK - 1)) / RTSDF_BRICK; }

std::uint64_t SdfPipeline::firstPoolSize(double time) {
  if (mSettings.band <= 0.0) return 0; // nothing is refined
  checkInstancePlacement(mScene, mMeshBounds, time);
  // The coarse SDF of the first frame, once more: the pool is sized by the bricks under its band.
  gpu::CommandBuffer cmd(mCtx);
  CoarseSdfSettings cs;
  cs.method = mSettings.coarseMethod;
  cs.beta = mSettings.beta;
  mBvh->recordUpdate(cmd.handle(), time);
  mGpu->coarse.record(cmd.handle(), nullptr, mBvh->instancedTriangles(), mCoarseSpec.inFrame(frameOrigin()), cs);
  cmd.submitAndWait();
  std::vector<float> coarse(mCoarseSpec.voxelCount());
  download(mCtx, mGpu->coarse.distanceBuffer(), coarse.data(), coarse.size() * 4);
  const std::uint64_t active = bandBricksCpu(coarse, mCoarseSpec, mFineSpec, mSettings.band).size();
  return poolBricksFor(active, brickDims());
}

void SdfPipeline::preparePool(double time) {
  if (mAwaitingFinish) { // the previous frame's statistics are lost, but not a full pool
    const MaskCounts n = maskCounts();
    if (n.overflowBricks) mGrowTo = poolBricksFor(n.activeBricks, brickDims());
  }
  const glm::ivec3 bd = brickDims();
  if (mFrame == 0)
    allocatePool(mSettings.poolBricks > 0 ? std::min<std::uint64_t>(std::uint64_t(mSettings.poolBricks),
                                                                    std::uint64_t(bd.x) * bd.y * bd.z)
                                          : firstPoolSize(time));
  else if (mGrowTo)
    allocatePool(mGrowTo);
  mGrowTo = 0;
}

void SdfPipeline::allocatePool(std::uint64_t bricks) {
  const std::uint64_t brickBytes = gpu::shared::kBrickVoxels * 4;
  const std::uint64_t range = mCtx.info().maxStorageBufferRange;
  mPageBricks = std::max<std::uint64_t>(1, std::min<std::uint64_t>(std::max<std::uint64_t>(bricks, 1),
                                                                   range ? range / brickBytes : bricks));
  mPageBricks = std::min<std::uint64_t>(mPageBricks, 0xFFFFFFFFu / gpu::shared::kBrickVoxels);
  const std::uint64_t pages = (bricks + mPageBricks - 1) / mPageBricks;
  PipelineMemory need = mMemory;
  need.deviceBytes += bricks * (2 * brickBytes + 4);
  if (pages > RTSDF_BRICK_PAGES)
    throw SettingError("fine resolution", fmt::format("SdfPipeline: fine grid {}: the band needs {} bricks ({}), more "
                                                      "than {} pages of {}'s maxStorageBufferRange: lower the fine "
                                                      "resolution or the band", mFineSpec.describe(), bricks,
                                                      mib(bricks * 2 * brickBytes), RTSDF_BRICK_PAGES,
                                                      mCtx.info().name));
  checkPipelineMemory(need, memoryLimits(mCtx.info()));
  Gpu& g = *mGpu;
  g.frameCmd.wait();
  for (int k = 0; k < RTSDF_BRICK_PAGES; ++k) {
    const std::uint64_t first = std::uint64_t(k) * mPageBricks;
    const std::uint64_t n = first < bricks ? std::min(mPageBricks, bricks - first) : 0;
    g.values[k] = n ? Buffer(mCtx, n * brickBytes, kStorageFilled, Buffer::Memory::Device,
                             fmt::format("brick pool values {}", k)) : Buffer();
    g.votes[k] = n ? Buffer(mCtx, n * brickBytes, kStorageFilled, Buffer::Memory::Device,
                            fmt::format("brick pool votes {}", k)) : Buffer();
  }
  // Every slot free (the stack pops slot 0 first), no brick holding one, every coarse voxel new to the band.
  std::vector<std::uint32_t> stack(std::max<std::uint64_t>(bricks, 1), 0u);
  for (std::uint64_t k = 0; k < bricks; ++k) stack[k] = std::uint32_t(bricks - 1 - k);
  gpu::reserveAndUpload(mCtx, g.brickFree, stack.data(), stack.size() * 4, kStorage, "brick free stack");
  const std::uint32_t counts[gpu::shared::kBrickCountWords] = {std::uint32_t(bricks), 0, 0, 0};
  gpu::CommandBuffer cmd(mCtx);
  gpu::recordUpload(cmd.handle(), g.brickCounts, counts, sizeof(counts));
  vkCmdFillBuffer(cmd.handle(), g.brickSlots.handle(), 0, VK_WHOLE_SIZE, gpu::shared::kNoBrick);
  vkCmdFillBuffer(cmd.handle(), g.coarseState.handle(), 0, VK_WHOLE_SIZE, 0xFFFFFFFFu);
  for (int k = 0; k < RTSDF_BRICK_PAGES; ++k) {
    if (g.values[k]) vkCmdFillBuffer(cmd.handle(), g.values[k].handle(), 0, VK_WHOLE_SIZE, 0u);
    if (g.votes[k]) vkCmdFillBuffer(cmd.handle(), g.votes[k].handle(), 0, VK_WHOLE_SIZE, 0u);
  }
  cmd.submitAndWait();
  mPoolBricks = bricks;
}

SdfPipeline::~SdfPipeline() {
  // The buffers must outlive a frame still on the GPU; a failed wait has nowhere to go.
  try {
    if (mGpu) mGpu->frameCmd.wait();
  } catch (const std::exception&) {
  }
}

gpu::shared::MaskParams SdfPipeline::maskParams(std::uint32_t movedBoxes) const {
  gpu::shared::MaskParams p{};
  p.coarseDims = glm::ivec4(mCoarseSpec.dims, 0);
  p.band = float(mSettings.band);
  p.refineCapacity = std::uint32_t(mGpu->refineList.size() / 4);
  p.coarseCapacity = std::uint32_t(mGpu->coarseList.size() / 8);
  p.frame = mFrame;
  const GridSpec coarse = mCoarseSpec.inFrame(frameOrigin());
  p.coarseOriginH = glm::vec4(glm::vec3(coarse.origin), float(coarse.voxelSize));
  // movedWithinReach: the coarse bound of the distance (beta, half a coarse diagonal to the seed's surface and
  // half one to a fine centre of the cell), and a fine voxel for rounding.
  const double beta = mSettings.beta >= 0.0 ? mSettings.beta : 0.5 * mCoarseSpec.voxelSize;
  p.reachPad = float(beta + std::sqrt(3.0) * mCoarseSpec.voxelSize + mFineSpec.voxelSize);
  p.settleFrames = std::uint32_t(settleFramesFor(mSettings));
  p.refreshPeriod = std::uint32_t(refreshPeriodFor(mSettings));
  p.movedBoxes = movedBoxes;
  p.brickDims = glm::ivec4(brickDims(), mRefineParts.total());
  return p;
}

void SdfPipeline::recordMask(VkCommandBuffer cmd, const gpu::shared::MaskParams& params) {
  Gpu& g = *mGpu;
  vkCmdFillBuffer(cmd, g.counts.handle(), 0, VK_WHOLE_SIZE, 0u);
  // The brick counts' per-frame words (the free stack's top persists).
  vkCmdFillBuffer(cmd, g.brickCounts.handle(), 4, (gpu::shared::kBrickCountWords - 1) * 4, 0u);
  gpu::computeBarrier(cmd);
  // d = 0 refines nothing (not even voxels with c = 0): the counts stay zero, and so does the dispatch.
  if (mSettings.band > 0.0) {
    g.compact.execute(cmd, &g.profiler, {g.coarse.distanceBuffer(), g.fineRanges, g.movedBoxes},
                      {g.counts, g.refineList, g.coarseList, g.coarseState, g.brickNeeded}, params);
    const glm::ivec3 bd = brickDims();
    gpu::shared::BrickParams bp{};
    bp.bricks = std::uint32_t(bd.x * bd.y * bd.z);
    bp.frame = mFrame;
    g.brickAlloc.execute(cmd, &g.profiler, {g.brickNeeded}, {g.brickCounts, g.brickSlots, g.brickFree}, bp);
  }
  g.maskDispatch.execute(cmd, &g.profiler, {}, {g.counts}, params);
}

void SdfPipeline::recordCountsReadback(VkCommandBuffer cmd) const {
  const VkBufferCopy mask{0, 0, gpu::shared::kMaskCountWords * 4};
  vkCmdCopyBuffer(cmd, mGpu->counts.handle(), mGpu->countsReadback.handle(), 1, &mask);
  const VkBufferCopy bricks{0, gpu::shared::kMaskCountWords * 4, gpu::shared::kBrickCountWords * 4};
  vkCmdCopyBuffer(cmd, mGpu->brickCounts.handle(), mGpu->countsReadback.handle(), 1, &bricks);
  VkMemoryBarrier toHost{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  toHost.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  toHost.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &toHost, 0, nullptr, 0,
                       nullptr);
}

SdfPipeline::MaskCounts SdfPipeline::maskCounts() const {
  waitForFrame();
  std::uint32_t words[kReadbackWords];
  std::memcpy(words, mGpu->countsReadback.mapped(), sizeof(words));
  using namespace gpu::shared;
  MaskCounts n;
  n.refinedFine = words[kMaskCountFine];
  n.maskedFine = words[kMaskCountMaskedFine];
  n.coarse = words[kMaskCountCoarse];
  n.refineList = words[kMaskCountRefineList];
  n.activeBricks = words[kMaskCountWords + kBrickCountActive];
  n.overflowBricks = words[kMaskCountWords + kBrickCountOverflow];
  // Each fine voxel lies under one coarse voxel and each coarse voxel is appended once: more would be a bug.
  const glm::ivec3 bd = brickDims();
  if (n.refinedFine > n.maskedFine || n.maskedFine > mFineSpec.voxelCount() || n.coarse > mCoarseSpec.voxelCount() ||
      n.refineList > n.coarse || n.activeBricks > std::uint64_t(bd.x) * bd.y * bd.z ||
      n.overflowBricks > n.activeBricks)
    throw Error(fmt::format("ray mask: the GPU counted {} fine voxels to refine of {} under {} coarse voxels ({} "
                            "listed), {} bricks ({} without a slot), more than the grids hold ({}, {} and {})",
                            n.refinedFine, n.maskedFine, n.coarse, n.refineList, n.activeBricks, n.overflowBricks,
                            mFineSpec.voxelCount(), mCoarseSpec.voxelCount(), std::uint64_t(bd.x) * bd.y * bd.z));
  return n;
}

std::vector<std::uint32_t> SdfPipeline::refinedVoxels() const {
  std::vector<std::uint32_t> coarse(mFrame && mSettings.band > 0.0 ? maskCounts().refineList : 0);
  download(mCtx, mGpu->refineList, coarse.data(), coarse.size() * 4);
  const std::vector<glm::ivec2> ranges = maskFineRanges(mCoarseSpec, mFineSpec);
  const glm::ivec3 cd = mCoarseSpec.dims;
  std::vector<std::uint32_t> list;
  for (std::uint32_t entry : coarse) {
    const std::uint32_t i = entry & gpu::shared::kMaskFineCoords;
    const glm::ivec3 c(int(i % cd.x), int(i / cd.x % cd.y), int(i / cd.x / cd.y));
    appendFineVoxelsUnder(ranges, cd, c, entry & gpu::shared::kMaskFineFresh, list);
  }
  tbb::parallel_sort(list.begin(), list.end());
  return list;
}

std::vector<glm::uvec2> SdfPipeline::coarseState() const {
  waitForFrame();
  std::vector<glm::uvec2> state(mCoarseSpec.voxelCount());
  download(mCtx, mGpu->coarseState, state.data(), state.size() * 8);
  return state;
}

RayMask SdfPipeline::rayMask() const {
  RayMask mask;
  if (mFrame == 0 || mSettings.band <= 0.0) return mask;
  const std::uint32_t coarse = maskCounts().coarse;
  mask.coarseVoxels = coarse;
  std::vector<std::uint32_t> pairs(std::size_t(coarse) * 2);
  download(mCtx, mGpu->coarseList, pairs.data(), pairs.size() * 4);
  std::vector<std::pair<std::uint64_t, float>> voxels(coarse);
  for (std::size_t k = 0; k < coarse; ++k) {
    voxels[k].first = pairs[2 * k];
    std::memcpy(&voxels[k].second, &pairs[2 * k + 1], 4);
  }
  // The fine voxels under the band, from the same range tables MaskCompactPass reads (the GPU lists only those it
  // refines this frame).
  const std::vector<glm::ivec2> ranges = maskFineRanges(mCoarseSpec, mFineSpec);
  const glm::ivec3 cd = mCoarseSpec.dims;
  for (const auto& [index, value] : voxels) {
    const glm::ivec3 c(int(index % cd.x), int(index / cd.x % cd.y), int(index / cd.x / cd.y));
    appendFineVoxelsUnder(ranges, cd, c, 0u, mask.fineVoxels);
  }
  tbb::parallel_sort(mask.fineVoxels.begin(), mask.fineVoxels.end());
  if (mCoarseSpec.voxelSize >= minVdbVoxelSize()) {
    mask.coarse = activeVoxelsToLevelSet(std::move(voxels), mCoarseSpec, float(mSettings.band));
  } else {
    // Voxels too small for an OpenVDB transform: the same grid measured in voxels, as buildRayMask does.
    GridSpec unit = mCoarseSpec;
    unit.voxelSize = 1.0;
    unit.origin = mCoarseSpec.origin / mCoarseSpec.voxelSize;
    for (auto& v : voxels) v.second = float(double(v.second) / mCoarseSpec.voxelSize);
    mask.coarse = activeVoxelsToLevelSet(std::move(voxels), unit, float(mSettings.band / mCoarseSpec.voxelSize));
  }
  return mask;
}

std::vector<float> SdfPipeline::coarseField() const {
  waitForFrame();
  std::vector<float> out(mFrame ? mCoarseSpec.voxelCount() : 0);
  download(mCtx, mGpu->coarse.distanceBuffer(), out.data(), out.size() * 4);
  return out;
}

RefineParams SdfPipeline::refineParams() const {
  RefineParams p = refineGridParams(mCoarseSpec.inFrame(frameOrigin()), mFineSpec.inFrame(frameOrigin()));
  p.alpha = float(mSettings.alpha);
  p.rays = std::uint32_t(mSettings.rays);
  p.frame = mFrame;
  p.seed = mSettings.seed;
  p.beta = float(mSettings.beta >= 0.0 ? mSettings.beta : 0.5 * mCoarseSpec.voxelSize);
  p.band = float(mSettings.band);
  p.pageBricks = std::uint32_t(std::max<std::uint64_t>(mPageBricks, 1));
  p.refineParts = mRefineParts.total();
  p.brickDims = glm::ivec4(brickDims(), mRefineParts.count.x);
  p.partBox = glm::ivec4(mRefineParts.box, mRefineParts.count.y);
  p.fineDims.w = int(mPoolBricks);
  p.coarseDims.w = (mGpu->fine ? gpu::shared::kRefineWriteDense : 0) |
                   (mSettings.mode == RefineMode::Closest && mSettings.closestSearch == ClosestSearch::Cell
                        ? gpu::shared::kRefineCellSearch
                        : 0);
  return p;
}

FrameStats SdfPipeline::runFrame(double time) {
  submitFrame(time);
  return finishFrame();
}

void SdfPipeline::submitFrame(double time) {
  using Clock = std::chrono::steady_clock;
  Gpu& g = *mGpu;
  g.frameCmd.wait(); // one frame in flight: the previous one's buffers are this one's
  preparePool(time);
  const auto t0 = Clock::now();
  // The host's work grows with the instances only: the GPU places their triangles.
  checkInstancePlacement(mScene, mMeshBounds, time);
  ++mFrame;
  mSubmitted = FrameStats{};
  mSubmitted.time = time;
  CoarseSdfSettings cs;
  cs.method = mSettings.coarseMethod;
  cs.beta = mSettings.beta;
  // What moved since the previous frame (the first frame refines every voxel: all are new to the mask).
  mLastMovedBoxes = mFrame > 1 ? movedInstanceBoxes(mScene, mMeshBounds, mPreviousTime, time, frameOrigin())
                               : std::vector<gpu::shared::MovedBox>{};
  const std::vector<gpu::shared::MovedBox>& moved = mLastMovedBoxes;
  mPreviousTime = time;
  mSubmitted.movedInstances = moved.size();
  // One command buffer for the whole frame, reused frame after frame: nothing is read back inside it.
  g.frameCmd.restart();
  const VkCommandBuffer cmd = g.frameCmd.handle();
  g.profiler.reset(cmd);
  gpu::computeBarrier(cmd); // the previous frame's passes are done with what this one overwrites
  // The frame's only uploads, recorded with it: the moved boxes (at most RTSDF_MAX_MOVED_BOXES x 32 bytes; barrier:
  // recordMask's) and the instance transforms (recordUpdate).
  gpu::recordUpload(cmd, g.movedBoxes, moved.data(), moved.size() * sizeof(moved[0]));
  mBvh->recordUpdate(cmd, time);
  g.coarse.record(cmd, &g.profiler, mBvh->instancedTriangles(), mCoarseSpec.inFrame(frameOrigin()), cs);
  mLastMaskParams = maskParams(std::uint32_t(moved.size()));
  recordMask(cmd, mLastMaskParams);
  const RefineParams p = refineParams();
  const BrickPages pool = g.pages();
  if (mSettings.band > 0.0)
    g.refine->execute(cmd, &g.profiler,
                      {*mBvh, g.refineList, g.counts, g.coarse.distanceBuffer(), g.fineRanges, g.brickSlots},
                      {pool, g.fine ? g.fine : g.placeholder}, p);
  if (g.fine)
    g.upsample.execute(cmd, &g.profiler, {g.coarse.distanceBuffer(), g.fineToCoarse, g.brickSlots}, {g.fine}, p);
  // Shading that samples the bricks finds the grids here.
  gpu::recordUpload(cmd, g.samplingParams, &p, sizeof(p));
  gpu::computeBarrier(cmd);
  recordCountsReadback(cmd);
  g.frameCmd.submit();
  mSubmitStart = t0;
  mSubmitted.hostMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  mAwaitingFinish = true;
}

FrameStats SdfPipeline::finishFrame() {
  using Clock = std::chrono::steady_clock;
  if (!mAwaitingFinish) throw Error("SdfPipeline: finishFrame() without a submitted frame");
  mAwaitingFinish = false;
  mGpu->frameCmd.wait();
  const auto t0 = Clock::now();
  FrameStats stats = mSubmitted;
  stats.passMs = mGpu->profiler.results();
  const MaskCounts counts = maskCounts();
  stats.maskFineVoxels = counts.maskedFine;
  stats.maskCoarseVoxels = counts.coarse;
  stats.refinedFineVoxels = counts.refinedFine;
  stats.activeBricks = counts.activeBricks;
  stats.overflowBricks = counts.overflowBricks;
  stats.poolBricks = mPoolBricks;
  stats.deviceBytes = mMemory.deviceBytes + mPoolBricks * (2 * gpu::shared::kBrickVoxels * 4 + 4);
  if (counts.overflowBricks) mGrowTo = poolBricksFor(counts.activeBricks, brickDims());
  const auto t1 = Clock::now();
  stats.hostMs += std::chrono::duration<double, std::milli>(t1 - t0).count();
  stats.wallMs = std::chrono::duration<double, std::milli>(t1 - mSubmitStart).count();
  return stats;
}

void SdfPipeline::waitForFrame() const { mGpu->frameCmd.wait(); }

const gpu::Buffer& SdfPipeline::fineBuffer() const {
  if (!mGpu->fine)
    throw Error("SdfPipeline: the fine SDF is kept sparse (fine storage 'sparse'): there is no dense fine buffer");
  return mGpu->fine;
}
const gpu::Buffer& SdfPipeline::coarseBuffer() const { return mGpu->coarse.distanceBuffer(); }

GpuBrickField SdfPipeline::brickField() const {
  if (mGpu->fine)
    throw Error("SdfPipeline: the fine SDF is kept dense (fine storage 'dense'): its bricks hold only the band");
  return {mGpu->coarse.distanceBuffer(), mGpu->fineToCoarse, mGpu->brickSlots, mGpu->samplingParams, mGpu->pages()};
}

std::vector<std::uint32_t> SdfPipeline::brickSlots() const {
  waitForFrame();
  std::vector<std::uint32_t> slots(mGpu->brickSlots.size() / 4);
  download(mCtx, mGpu->brickSlots, slots.data(), slots.size() * 4);
  return slots;
}

std::vector<float> SdfPipeline::brickValues() const {
  waitForFrame();
  std::vector<float> values(mPoolBricks * gpu::shared::kBrickVoxels);
  std::size_t at = 0;
  for (const Buffer& page : mGpu->values) {
    if (!page) continue;
    download(mCtx, page, values.data() + at, page.size());
    at += page.size() / 4;
  }
  return values;
}

std::vector<float> SdfPipeline::fineField() const {
  waitForFrame();
  if (mGpu->fine) {
    std::vector<float> out(mFineSpec.voxelCount());
    download(mCtx, mGpu->fine, out.data(), out.size() * 4);
    return out;
  }
  if (mFrame == 0) return std::vector<float>(mFineSpec.voxelCount(), 0.0f);
  // The grids as the GPU sees them: the same upsampled values, bit for bit.
  return resolveFineCpu(coarseField(), mCoarseSpec.inFrame(frameOrigin()), mFineSpec.inFrame(frameOrigin()),
                        float(mSettings.band), brickSlots(), brickValues());
}

std::uint64_t poolBricksFor(std::uint64_t activeBricks, const glm::ivec3& brickDims) {
  const std::uint64_t all = std::uint64_t(brickDims.x) * brickDims.y * brickDims.z;
  return std::min(all, activeBricks + activeBricks / 2 + 64);
}

} // namespace rtsdf