#include "jobs/CascadeBake.h"

#include "jobs/JobSupport.h"
#include "render/Renderer.h"
#include "scene/SceneGeometry.h"
#include "sdf/cascade/CascadeMemory.h"
#include "sdf/cascade/CascadeSet.h"
#include "util/Error.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <map>

namespace rtsdf {

std::string cascadeGridName(int level) { return fmt::format("surface_L{}", level); }

glm::dvec3 cascadeCentre(const Scene& scene, double time) {
  if (scene.hasCamera) return scene.cameraAt(time).position;
  return buildSceneGeometry(scene, time).bounds.center();
}

BakeResult bakeCascades(const BakeOptions& o, const Scene& scene, const JobControl& control) {
  return runOnDevice(deviceContextOptions(o.device), [&](const gpu::VulkanContext& ctx) {
    const glm::dvec3 centre = cascadeCentre(scene, o.time);
    const CascadeShape shape = cascadeShapeFor(buildSceneGeometry(scene, o.time).bounds, centre, o.pipeline);
    CascadeSet set(ctx, scene, CascadeLayout::around(centre, shape), o.pipeline);
    const RenderSettings image; // the levels above 0 refine near the camera's view of render's default image
    if (scene.hasCamera) set.setView(scene.cameraAt(o.time), double(image.width) / image.height);
    spdlog::info("cascades: {} levels around ({:.6g}, {:.6g}, {:.6g}), level 0 {:.6g} wide; {}", shape.levels,
                 centre.x, centre.y, centre.z, shape.levelZeroExtent, set.memory().describe());
    BakeResult r;
    const auto t0 = std::chrono::steady_clock::now();
    for (int f = 0; f < o.frames; ++f) {
      control.checkStop();
      r.levelFrames = set.runFrame(o.time);
      for (const FrameStats& level : r.levelFrames) r.cutVoxels += level.cutVoxels;
      control.report("refining", std::uint64_t(f + 1), std::uint64_t(o.frames));
    }
    r.seconds = secondsSince(t0);
    throwOnValidationErrors(ctx);
    for (int i = 0; i < set.levels(); ++i) {
      BakeOptions level = o;
      level.pipeline = set.level(i).settings();
      openvdb::FloatGrid::Ptr grid = fineLevelSet(set.level(i), level, o.time);
      grid->setName(cascadeGridName(i));
      grid->insertMeta("rtsdf:cascade_level", openvdb::Int32Metadata(i));
      grid->insertMeta("rtsdf:cascades", openvdb::Int32Metadata(set.levels()));
      grid->insertMeta("rtsdf:cascade_centre", openvdb::Vec3DMetadata(openvdb::Vec3d(centre.x, centre.y, centre.z)));
      r.levels.push_back(grid);
    }
    r.grid = r.levels.front();
    r.spec = set.level(0).fineSpec();
    r.coarseSpec = set.level(0).coarseSpec();
    r.lastFrame = r.levelFrames.front();
    r.device = ctx.info().name;
    warnOfCutWalks(r.cutVoxels, r.device);
    return r;
  });
}

std::vector<openvdb::FloatGrid::Ptr> cascadeLevelGrids(const openvdb::GridPtrVec& grids) {
  std::map<int, openvdb::FloatGrid::Ptr> byLevel;
  for (const auto& g : grids) {
    const std::string name = g->getName();
    if (name.rfind("surface_L", 0) != 0) continue;
    const std::string digits = name.substr(9);
    if (digits.empty() || digits.size() > 2 || digits.find_first_not_of("0123456789") != std::string::npos) continue;
    auto f = openvdb::gridPtrCast<openvdb::FloatGrid>(g);
    if (!f || f->getGridClass() != openvdb::GRID_LEVEL_SET)
      throw Error(fmt::format("grid '{}' is named as a cascade level but is not a float level set", name));
    byLevel[std::stoi(digits)] = f;
  }
  std::vector<openvdb::FloatGrid::Ptr> levels;
  for (const auto& [level, grid] : byLevel) {
    if (level != int(levels.size()))
      throw Error(fmt::format("cascade levels must be 0..K-1 without gaps: '{}' follows {} level(s)",
                              cascadeGridName(level), levels.size()));
    levels.push_back(grid);
  }
  return levels;
}

std::string cascadeReport(const BakeResult& r) {
  std::string t;
  for (std::size_t i = 0; i < r.levels.size(); ++i) {
    const GridSpec spec = gridSpecOf(*r.levels[i]);
    const auto band = r.levels[i]->getMetadata<openvdb::DoubleMetadata>("rtsdf:band");
    const FrameStats* st = i < r.levelFrames.size() ? &r.levelFrames[i] : nullptr;
    t += fmt::format("level {:<5}'{}': {}, band {}, mask {} coarse voxels, {} active voxels\n", i,
                     cascadeGridName(int(i)), spec.describe(),
                     band ? fmt::format("{:.6g} = {:.2f} voxels", band->value(), band->value() / spec.voxelSize) : "?",
                     st ? st->maskCoarseVoxels : 0, r.levels[i]->activeVoxelCount());
  }
  return t;
}

} // namespace rtsdf
