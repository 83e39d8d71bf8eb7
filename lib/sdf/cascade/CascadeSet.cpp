#include "sdf/cascade/CascadeSet.h"

#include "sdf/cascade/CascadeScene.h"
#include "sdf/pipeline/GridShift.h"

#include "util/Error.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>

namespace rtsdf {

CascadeSet::CascadeSet(const gpu::VulkanContext& ctx, const Scene& scene, const CascadeLayout& layout,
                       const PipelineSettings& s)
    : mCtx(ctx), mScene(scene), mSettings(s), mLayout(layout) {
  s.validate();
  mMemory = estimateCascadeMemory(scene, layout, s);
  checkPipelineMemory(mMemory.total(), memoryLimits(ctx.info()));
  for (int i = 0; i < int(layout.levels.size()); ++i) mLevels.push_back(buildLevel(i));
  if (mMemory.scrollScratchBytes > 0)
    mScrollScratch = gpu::Buffer(ctx, mMemory.scrollScratchBytes, gpu::kStorage, gpu::Buffer::Memory::Device,
                                 "cascade scroll scratch");
}

CascadeSet::~CascadeSet() = default;

std::unique_ptr<Scene> CascadeSet::cutScene(int i) const {
  const CascadeLevel& level = mLayout.levels.at(std::size_t(i));
  const PipelineSettings settings = levelSettings(mSettings, i);
  const double margin = levelCutMargin(mLayout.shape, level, settings.band.sceneUnits(level.fine.voxelSize));
  auto scene = std::make_unique<Scene>(rtsdf::levelScene(mScene, level.box(), margin));
  if (scene->instances.empty()) {
    // Nothing near this level: one instance far outside keeps the pipeline's buffers non-empty; it lies beyond the
    // margin, so every voxel stays out of the band, as with no geometry at all.
    const Instance& first = mScene.instances.at(0);
    scene->meshes.push_back(mScene.meshes.at(first.mesh));
    scene->instances.push_back(first);
    scene->instances.back().mesh = 0;
  }
  return scene;
}

CascadeSet::Level CascadeSet::buildLevel(int i) const {
  const CascadeLevel& level = mLayout.levels.at(std::size_t(i));
  Level out;
  const PipelineSettings settings = levelSettings(mSettings, i);
  out.sceneBox = level.box();
  out.scene = cutScene(i);
  out.pipeline = std::make_unique<SdfPipeline>(mCtx, *out.scene, level.grids(), settings);
  applyView(i, *out.pipeline);
  spdlog::info("cascade level {}: coarse {}, fine {}, {} of {} instances", i, level.coarse.describe(),
               level.fine.describe(), out.scene->instances.size(), mScene.instances.size());
  return out;
}

void CascadeSet::applyView(int i, SdfPipeline& level) const {
  if (i == 0 || !mView || mSettings.cascadeViewMargin < 0.0) return;
  const double margin = mSettings.cascadeViewMargin * level.coarseSpec().voxelSize;
  const ViewReach reach = viewReachOf(mView->first, mView->second, margin);
  level.setViewReach(&reach);
}

void CascadeSet::setView(const Camera& camera, double aspect) {
  viewReachOf(camera, aspect, 0.0); // throws on a camera without a view direction
  mView = std::make_pair(camera, aspect);
  for (int i = 1; i < levels(); ++i) // a lost level takes the view when it is built again
    if (!mLevels[std::size_t(i)].lost) applyView(i, *mLevels[std::size_t(i)].pipeline);
}

void CascadeSet::rebuildLostLevels(std::vector<int>* rebuilt) {
  for (int i = 0; i < levels(); ++i) {
    Level& level = mLevels[std::size_t(i)];
    if (!level.lost) continue;
    level = freshLevel(i); // a level that fails again stays lost (and holds nothing)
    if (rebuilt) rebuilt->push_back(i);
  }
}

CascadeSet::Level CascadeSet::freshLevel(int i) {
  if (mFailNextBuild) {
    mFailNextBuild = false;
    throw Error(fmt::format("CascadeSet: a failure injected into building level {} (CascadeFaults)", i));
  }
  return buildLevel(i);
}

std::vector<FrameStats> CascadeSet::runFrame(double time) {
  rebuildLostLevels(nullptr);
  std::vector<FrameStats> stats;
  for (Level& level : mLevels) stats.push_back(level.pipeline->runFrame(time));
  return stats;
}

bool CascadeSet::scrollLevel(int i, bool& recut) {
  Level& level = mLevels.at(std::size_t(i));
  const CascadeLevel& to = mLayout.levels.at(std::size_t(i));
  recut = false;
  if (!mScrollScratch || !scrollShift({level.pipeline->coarseSpec(), level.pipeline->fineSpec()}, to.grids()))
    return false;
  const glm::dvec3 drift = glm::abs(to.box().min - level.sceneBox.min);
  // A whisker over the slack: the drift is a sum of whole moves, the slack a product of the same lengths.
  const double slack = levelSceneSlack(mLayout.shape, i) * (1.0 + 1e-9);
  if (drift.x <= slack && drift.y <= slack && drift.z <= slack) {
    level.pipeline->scroll(to.grids(), mScrollScratch);
    return true;
  }
  // Past the slack: the scene cut again around the new box; the old one goes once the pipeline has let it go.
  std::unique_ptr<Scene> scene = cutScene(i);
  level.pipeline->scroll(to.grids(), mScrollScratch, scene.get());
  level.scene = std::move(scene);
  level.sceneBox = to.box();
  recut = true;
  return true;
}

CascadeMove CascadeSet::moveTo(const glm::dvec3& camera, const glm::dvec3& lookAhead) {
  const CascadeLayout next = CascadeLayout::around(camera, mLayout.shape, lookAhead);
  const std::vector<glm::i64vec3> shift = next.shiftSince(mLayout);
  mLayout = next;
  CascadeMove move;
  for (int i = 0; i < levels(); ++i) {
    const bool lost = mLevels[std::size_t(i)].lost;
    if (shift[std::size_t(i)] == glm::i64vec3(0) && !lost) continue;
    if (!lost) move.moved.push_back(i);
    try {
      bool recut = false;
      if (!lost && scrollLevel(i, recut)) {
        if (recut) move.recut.push_back(i);
        continue;
      }
      Level& level = mLevels[std::size_t(i)];
      level = Level{}; // the old level's buffers go before the new one's are made
      level = freshLevel(i);
      move.rebuilt.push_back(i);
    } catch (...) {
      // This level's buffers may be partly moved, and the levels after it are not where the layout now puts them:
      // they are built again, from scratch, before the set is used next (runFrame, moveTo).
      for (int j = i; j < levels(); ++j)
        if (j == i || shift[std::size_t(j)] != glm::i64vec3(0)) loseLevel(j);
      throw;
    }
  }
  return move;
}

void CascadeSet::loseLevel(int i) {
  Level& level = mLevels[std::size_t(i)];
  level = Level{}; // its buffers go now: a device out of memory may need them for the rebuild
  level.lost = true;
}

const SdfPipeline& CascadeSet::level(int i) const {
  const Level& level = mLevels.at(std::size_t(i));
  if (level.lost)
    throw Error(fmt::format("CascadeSet: level {} was lost by a move that failed; it is built again by the next "
                            "runFrame or moveTo", i));
  return *level.pipeline;
}

const Scene& CascadeSet::levelScene(int i) const {
  level(i); // throws for a lost level
  return *mLevels[std::size_t(i)].scene;
}

FrameStats sumFrameStats(const std::vector<FrameStats>& levels) {
  FrameStats sum;
  sum.fieldChanged = false;
  for (const FrameStats& f : levels) {
    sum.time = f.time;
    sum.maskCoarseVoxels += f.maskCoarseVoxels;
    sum.maskFineVoxels += f.maskFineVoxels;
    sum.refinedFineVoxels += f.refinedFineVoxels;
    sum.cutVoxels += f.cutVoxels;
    sum.movedKeptVoxels += f.movedKeptVoxels;
    sum.nearHalfVoxels += f.nearHalfVoxels;
    sum.nearHalfKept += f.nearHalfKept;
    sum.upsampledFineVoxels += f.upsampledFineVoxels;
    sum.coarseRebuiltVoxels += f.coarseRebuiltVoxels;
    sum.coarseVoxelizedVoxels += f.coarseVoxelizedVoxels;
    sum.maskVisitedVoxels += f.maskVisitedVoxels;
    sum.activeBricks += f.activeBricks;
    sum.overflowBricks += f.overflowBricks;
    sum.poolBricks += f.poolBricks;
    sum.deviceBytes += f.deviceBytes;
    sum.movedInstances = std::max(sum.movedInstances, f.movedInstances);
    sum.hostMs += f.hostMs;
    sum.wallMs += f.wallMs;
    sum.passMs.insert(sum.passMs.end(), f.passMs.begin(), f.passMs.end());
    sum.fieldChanged = sum.fieldChanged || f.fieldChanged;
  }
  return sum;
}

} // namespace rtsdf
