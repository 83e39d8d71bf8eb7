#include "sdf/SdfPipeline.h"

#include "grid/VdbIO.h"
#include "gpu/shared/Refine.h"
#include "sdf/RefinePasses.h"
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

void PipelineSettings::validate() const {
  if (coarseRes < 1 || coarseRes > 1024)
    throw SettingError("coarse resolution", fmt::format("coarse resolution {} is out of range [1, 1024]", coarseRes));
  if (fineRes < coarseRes || fineRes > 1024)
    throw SettingError("fine resolution", fmt::format("fine resolution {} must be in [the coarse resolution ({}), "
                                                      "1024]", fineRes, coarseRes));
  if (!std::isfinite(band) || band < 0.0)
    throw SettingError("band", fmt::format("band {} must be finite and >= 0", band));
  if (!(alpha >= 0.0 && alpha <= 1.0)) throw SettingError("alpha", fmt::format("alpha {} must be in [0, 1]", alpha));
  if (rays < 0 || rays > 1024) throw SettingError("rays", fmt::format("rays {} is out of range [0, 1024]", rays));
  if (std::isnan(beta) || std::isinf(beta)) throw SettingError("beta", fmt::format("beta {} must be finite", beta));
  if (!std::isfinite(padding)) throw SettingError("padding", fmt::format("padding {} must be finite", padding));
  if (settleFrames == 0 || settleFrames > 1000000)
    throw SettingError("settle frames", fmt::format("settle frames {} must be in [1, 1000000] (or < 0: by the "
                                                    "refinement mode)", settleFrames));
  if (refreshPeriod > 1000000)
    throw SettingError("refresh period", fmt::format("refresh period {} must be in [0, 1000000] (or < 0: by the "
                                                     "refinement mode)", refreshPeriod));
}

int settleFramesFor(const PipelineSettings& s) {
  if (s.fullRecompute) return 0;
  if (s.settleFrames > 0) return s.settleFrames;
  if (s.mode == RefineMode::Closest) return s.rays == 0 ? 1 : 4;
  return 32;
}

int refreshPeriodFor(const PipelineSettings& s) {
  if (s.refreshPeriod >= 0) return s.refreshPeriod;
  return s.mode == RefineMode::Closest ? 0 : 8;
}

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

double defaultPadding(const Bounds& bounds, double band) { return std::min(band, 0.25 * bounds.maxExtent()); }

double pipelinePadding(const Bounds& bounds, const PipelineSettings& s) {
  if (s.padding < 0.0) return defaultPadding(bounds, s.band);
  // A margin wider than the scene models mostly empty space (and at 1e30 overflows the grid's size).
  const double longest = bounds.maxExtent();
  if (longest > 0.0 && s.padding > longest)
    throw SettingError("padding", fmt::format("padding {:g} is more than the scene's longest side ({:g}): at most "
                                              "{:g}", s.padding, longest, longest));
  return s.padding;
}

void requireBandWithin(const GridSpec& grid, double band) {
  const double d = grid.diagonal();
  if (band > d)
    throw SettingError("band", fmt::format("band {:g} is longer than the grid's diagonal ({:g}): every voxel would be "
                                           "in it; at most {:g} (for an exact field everywhere, ask for the full "
                                           "domain)", band, d, d));
}

void requireBetaWithin(const GridSpec& coarse, double beta) {
  const double d = coarse.diagonal();
  if (beta > d)
    throw SettingError("beta", fmt::format("beta {:g} is longer than the coarse grid's diagonal ({:g}): the shell "
                                           "would swallow every voxel; at most {:g} (default: half a coarse voxel, "
                                           "{:g})", beta, d, d, 0.5 * coarse.voxelSize));
}

GridSpec coarseGridOver(const GridSpec& fine, const Bounds& bounds, int coarseRes, double padding) {
  GridSpec c;
  // The fine and coarse voxel (0,0,0) share their corner: the ray mask maps coarse to fine voxels by index.
  c.origin = fine.origin;
  c.voxelSize = GridSpec::fromBounds(bounds, coarseRes, padding).voxelSize;
  const glm::dvec3 ext = glm::dvec3(fine.dims) * fine.voxelSize;
  for (int a = 0; a < 3; ++a) c.dims[a] = std::max(1, int(std::ceil(ext[a] / c.voxelSize - 1e-9)));
  return c;
}

std::pair<GridSpec, GridSpec> pipelineGrids(const Bounds& bounds, const PipelineSettings& s) {
  s.validate();
  const double padding = pipelinePadding(bounds, s);
  const GridSpec fine = GridSpec::fromBounds(bounds, s.fineRes, padding);
  const GridSpec coarse = coarseGridOver(fine, bounds, s.coarseRes, padding);
  // No band limit here: a ray-mask band beyond the grid masks every voxel, a knob's legitimate extreme.
  requireBetaWithin(coarse, s.beta);
  for (int a = 0; a < 3; ++a)
    if (fine.dims[a] > gpu::shared::kMaxSeedAxis)
      throw SettingError("fine resolution", fmt::format("fine grid {}: more than {} voxels along an axis (lower the "
                                                        "fine resolution)", fine.describe(), gpu::shared::kMaxSeedAxis));
  return {coarse, fine};
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
  const std::uint64_t coarseBuf = nc * 4, fineBuf = nf * 4;
  if (fineBuf >= coarseBuf) { m.largestBuffer = fineBuf; m.largestBufferName = "fine SDF"; }
  else { m.largestBuffer = coarseBuf; m.largestBufferName = "coarse SDF"; }
  // Seeds A/B, the coarse SDF, the compacted band (8 bytes per voxel) and the refinement state (8 bytes per
  // voxel); fine SDF, votes and the list of voxels to refine; the BVH (nodes of 32 bytes, at most two per
  // triangle, corners 48 bytes and ids 4 bytes per triangle), whose mesh-space corners VoxelizePass places in
  // voxel space (48 bytes per triangle).
  m.deviceBytes = 7 * coarseBuf + 3 * fineBuf + triangles * (64 + 48 + 4 + 48) + 4096;
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
  const char* lower = need.largestBufferName == "fine SDF" ? "fine resolution" : "coarse resolution";
  if (limits.maxStorageBufferRange && need.largestBuffer > limits.maxStorageBufferRange)
    throw SettingError(lower, fmt::format("SdfPipeline: {}: buffer '{}' needs {}, more than {}'s "
                                          "maxStorageBufferRange of {}: lower the {}", grids, need.largestBufferName,
                                          mib(need.largestBuffer), limits.deviceName,
                                          mib(limits.maxStorageBufferRange), lower));
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
  UpsamplePass upsample;
  std::unique_ptr<RefinePass> refine; // RayRefinePass or ClosestRefinePass, by the mode
  gpu::GpuProfiler profiler;
  gpu::CommandBuffer frameCmd;        // every frame's, restarted per frame (its pool's memory is reused)
  Buffer fine, votes;                 // per fine voxel: the SDF (the refinement's history under the mask), votes
  Buffer coarseState;                 // per coarse voxel: last frame in the band, refinements in a row
  Buffer movedBoxes;                  // MovedBox per moving instance, written into the frame's command buffer
  Buffer fineRanges, fineToCoarse;    // maskFineRanges() and maskCoarseOfFine() of the grids, uploaded once
  Buffer counts;                      // the refinement's indirect dispatch, then the mask's counters
  Buffer countsReadback;              // the counts, copied at the end of each frame for its statistics
  Buffer mask, coarseList;            // the compacted fine voxels and coarse band voxels (band > 0 only)
  Gpu(const gpu::VulkanContext& ctx, RefineMode mode)
      : coarse(ctx), compact(ctx), maskDispatch(ctx), upsample(ctx),
        refine(mode == RefineMode::Rays ? std::unique_ptr<RefinePass>(std::make_unique<RayRefinePass>(ctx))
                                        : std::make_unique<ClosestRefinePass>(ctx)),
        profiler(ctx), frameCmd(ctx) {}
};

namespace {
const VkBufferUsageFlags kStorage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
} // namespace

SdfPipeline::SdfPipeline(const gpu::VulkanContext& ctx, const Scene& scene, const Bounds& bounds,
                         const PipelineSettings& s)
    : mCtx(ctx), mScene(scene), mSettings(s) {
  // Everything is checked before anything is allocated.
  std::uint64_t triangles = 0;
  for (const Instance& inst : scene.instances) triangles += scene.meshes.at(inst.mesh).triangles.size();
  const PipelineMemory need = estimatePipelineMemory(bounds, s, triangles);
  checkPipelineMemory(need, memoryLimits(ctx.info()));
  mCoarseSpec = need.coarse;
  mFineSpec = need.fine;
  mBvh = std::make_unique<GpuSceneBvh>(ctx, scene, frameOrigin());
  mGpu = std::make_unique<Gpu>(ctx, s.mode);
  const std::size_t fineBytes = mFineSpec.voxelCount() * 4;
  mGpu->fine = Buffer(ctx, fineBytes, kStorage, Buffer::Memory::Device, "fine SDF");
  mGpu->votes = Buffer(ctx, fineBytes, kStorage, Buffer::Memory::Device, "fine sign votes");
  mGpu->coarseState = Buffer(ctx, mCoarseSpec.voxelCount() * 8, kStorage, Buffer::Memory::Device,
                             "coarse refinement state");
  const std::vector<int> fineToCoarse = maskCoarseOfFine(mCoarseSpec, mFineSpec);
  gpu::reserveAndUpload(ctx, mGpu->fineToCoarse, fineToCoarse.data(), fineToCoarse.size() * sizeof(int), kStorage,
                        "ray mask fine-to-coarse table");
  mGpu->movedBoxes = Buffer(ctx, RTSDF_MAX_MOVED_BOXES * sizeof(gpu::shared::MovedBox),
                            kStorage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, Buffer::Memory::Device, "moved instance boxes");
  for (const Mesh& mesh : scene.meshes) mMeshBounds.push_back(positionBounds(mesh));
  using gpu::shared::kMaskCountWords;
  mGpu->counts = Buffer(ctx, kMaskCountWords * 4, kStorage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                        VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT, Buffer::Memory::Device,
                        "ray mask counts");
  mGpu->countsReadback = Buffer(ctx, kMaskCountWords * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT, Buffer::Memory::Host,
                                "ray mask counts (readback)");
  if (s.band > 0.0) {
    // Each fine voxel lies under one coarse voxel: the lists can never hold more than the grids.
    const std::vector<glm::ivec2> ranges = maskFineRanges(mCoarseSpec, mFineSpec);
    gpu::reserveAndUpload(ctx, mGpu->fineRanges, ranges.data(), ranges.size() * sizeof(glm::ivec2), kStorage,
                          "ray mask fine ranges");
    mGpu->mask = Buffer(ctx, fineBytes, kStorage, Buffer::Memory::Device, "ray mask (fine voxels)");
    mGpu->coarseList = Buffer(ctx, mCoarseSpec.voxelCount() * 8, kStorage, Buffer::Memory::Device,
                              "ray mask (coarse voxels)");
  }
  gpu::CommandBuffer cmd(ctx);
  // No voxel has been in the band: last frame + 1 must differ from the first frame number (1).
  vkCmdFillBuffer(cmd.handle(), mGpu->coarseState.handle(), 0, VK_WHOLE_SIZE, 0xFFFFFFFFu);
  vkCmdFillBuffer(cmd.handle(), mGpu->fine.handle(), 0, VK_WHOLE_SIZE, 0u);
  vkCmdFillBuffer(cmd.handle(), mGpu->votes.handle(), 0, VK_WHOLE_SIZE, 0u);
  vkCmdFillBuffer(cmd.handle(), mGpu->movedBoxes.handle(), 0, VK_WHOLE_SIZE, 0u);
  cmd.submitAndWait();
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
  p.fineCapacity = std::uint32_t(mGpu->mask.size() / 4);
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
  return p;
}

void SdfPipeline::recordMask(VkCommandBuffer cmd, const gpu::shared::MaskParams& params) {
  Gpu& g = *mGpu;
  vkCmdFillBuffer(cmd, g.counts.handle(), 0, VK_WHOLE_SIZE, 0u);
  gpu::computeBarrier(cmd);
  // d = 0 refines nothing (not even voxels with c = 0): the counts stay zero, and so does the dispatch.
  if (mSettings.band > 0.0)
    g.compact.execute(cmd, &g.profiler, {g.coarse.distanceBuffer(), g.fineRanges, g.movedBoxes},
                      {g.counts, g.mask, g.coarseList, g.coarseState}, params);
  g.maskDispatch.execute(cmd, &g.profiler, {}, {g.counts}, {});
}

void SdfPipeline::recordCountsReadback(VkCommandBuffer cmd) const {
  const VkBufferCopy region{0, 0, gpu::shared::kMaskCountWords * 4};
  vkCmdCopyBuffer(cmd, mGpu->counts.handle(), mGpu->countsReadback.handle(), 1, &region);
  VkMemoryBarrier toHost{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  toHost.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  toHost.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &toHost, 0, nullptr, 0,
                       nullptr);
}

SdfPipeline::MaskCounts SdfPipeline::maskCounts() const {
  waitForFrame();
  std::uint32_t words[gpu::shared::kMaskCountWords];
  std::memcpy(words, mGpu->countsReadback.mapped(), sizeof(words));
  MaskCounts n;
  n.refinedFine = words[gpu::shared::kMaskCountFine];
  n.maskedFine = words[gpu::shared::kMaskCountMaskedFine];
  n.coarse = words[gpu::shared::kMaskCountCoarse];
  // Each fine voxel lies under one coarse voxel and each coarse voxel is appended once: more would be a bug.
  if (n.refinedFine > n.maskedFine || n.maskedFine > mFineSpec.voxelCount() || n.coarse > mCoarseSpec.voxelCount())
    throw Error(fmt::format("ray mask: the GPU counted {} fine voxels to refine of {} under {} coarse voxels, more "
                            "than the grids hold ({} and {})", n.refinedFine, n.maskedFine, n.coarse,
                            mFineSpec.voxelCount(), mCoarseSpec.voxelCount()));
  return n;
}

std::vector<std::uint32_t> SdfPipeline::refinedVoxels() const {
  std::vector<std::uint32_t> list(mFrame && mSettings.band > 0.0 ? maskCounts().refinedFine : 0);
  download(mCtx, mGpu->mask, list.data(), list.size() * 4);
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
  g.upsample.execute(cmd, &g.profiler, {g.coarse.distanceBuffer(), g.fineToCoarse}, {g.fine}, p);
  if (mSettings.band > 0.0)
    g.refine->execute(cmd, &g.profiler, {*mBvh, g.mask, g.counts, g.coarse.distanceBuffer()}, {g.fine, g.votes}, p);
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
  const auto t1 = Clock::now();
  stats.hostMs += std::chrono::duration<double, std::milli>(t1 - t0).count();
  stats.wallMs = std::chrono::duration<double, std::milli>(t1 - mSubmitStart).count();
  return stats;
}

void SdfPipeline::waitForFrame() const { mGpu->frameCmd.wait(); }

const gpu::Buffer& SdfPipeline::fineBuffer() const { return mGpu->fine; }
const gpu::Buffer& SdfPipeline::coarseBuffer() const { return mGpu->coarse.distanceBuffer(); }

std::vector<float> SdfPipeline::fineField() const {
  waitForFrame();
  std::vector<float> out(mFineSpec.voxelCount());
  download(mCtx, mGpu->fine, out.data(), out.size() * 4);
  return out;
}

} // namespace rtsdf
