#include "sdf/cascade/CascadeMemory.h"

#include "sdf/cascade/CascadeScene.h"
#include "sdf/mask/MaskParams.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace rtsdf {

PipelineSettings levelSettings(const PipelineSettings& s, int level) {
  PipelineSettings out = s;
  out.cascades = 1;
  out.cascadeExtent = -1.0;
  out.padding = 0.0;
  // A band in voxels stays so: each level's pipeline resolves it against its own fine voxel, 2^level times level 0's.
  out.band = s.band.inVoxels() ? s.band : Length(std::ldexp(double(s.band), level));
  return out;
}

PipelineMemory CascadeMemory::total() const {
  PipelineMemory t;
  if (levels.empty()) return t;
  t.coarse = levels.back().coarse;
  t.fine = levels.back().fine;
  for (const PipelineMemory& m : levels)
    if (m.largestBuffer >= t.largestBuffer) {
      t.largestBuffer = m.largestBuffer;
      t.largestBufferName = m.largestBufferName;
    }
  t.deviceBytes = deviceBytes;
  t.hostBytes = hostBytes;
  return t;
}

std::string CascadeMemory::describe() const {
  std::string t = fmt::format("{} levels: device {}, host {}", levels.size(), formatMiB(deviceBytes),
                              formatMiB(hostBytes));
  for (std::size_t i = 0; i < levels.size(); ++i)
    t += fmt::format("; L{} fine voxel {:.4g}, {} triangles, device {}", i, levels[i].fine.voxelSize, triangles[i],
                     formatMiB(levels[i].deviceBytes));
  return t;
}

std::uint64_t cascadeScrollScratchBytes(const CascadeLayout& layout, const PipelineSettings& s) {
  if (layout.levels.empty() || layout.shape.fineRes % layout.shape.coarseRes != 0) return 0;
  return scrollScratchBytesFor(layout.levels[0].coarse, layout.levels[0].fine, s.fineStorage);
}

CascadeMemory estimateCascadeMemory(const Scene& scene, const CascadeLayout& layout, const PipelineSettings& s) {
  CascadeMemory m;
  for (const CascadeLevel& level : layout.levels) {
    const PipelineSettings ls = levelSettings(s, level.index);
    const double margin = levelCutMargin(layout.shape, level, ls.band.sceneUnits(level.fine.voxelSize));
    const SceneGpuSize geometry = sceneGpuSize(levelScene(scene, level.box(), margin));
    m.levels.push_back(estimatePipelineMemory(level.grids(), withLengthsResolved(ls, level.fine.voxelSize), geometry));
    m.triangles.push_back(geometry.instanceTriangles);
    m.deviceBytes += m.levels.back().deviceBytes;
    m.hostBytes = std::max(m.hostBytes, m.levels.back().hostBytes);
  }
  m.scrollScratchBytes = cascadeScrollScratchBytes(layout, s);
  m.deviceBytes += m.scrollScratchBytes;
  return m;
}

} // namespace rtsdf
