#include "sdf/cascade/CascadeLayout.h"

#include "sdf/mask/MaskParams.h"
#include "util/Error.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace rtsdf {

double CascadeShape::coarseVoxel(int i) const { return std::ldexp(levelZeroExtent / coarseRes, i); }

double CascadeShape::fineVoxel(int i) const { return std::ldexp(levelZeroExtent / fineRes, i); }

double CascadeShape::maxLookAhead() const {
  // Level i + 1's centre lies 2^i |lookAhead| from level i's (the outermost's too, on the camera), and each snaps by
  // up to half a move (moveCells of its coarse voxels; an odd count of coarse voxels puts the box's centre half a
  // voxel off its lattice point): level i's half side plus all that, plus level i + 1's fine voxel, must stay within
  // level i + 1's half side. Dividing by 2^i leaves level 0's lengths.
  const double offLattice = coarseRes % 2 ? 1.5 : 0.0;
  const double bound = 0.5 * levelZeroExtent - (1.5 * std::max(1, moveCells) + offLattice) * coarseVoxel(0) -
                       2.0 * fineVoxel(0);
  return std::max(0.0, bound);
}

int levelMoveCells(int coarseRes, int fineRes) {
  if (coarseRes <= 0 || fineRes % coarseRes != 0) return 1;
  return RTSDF_BRICK / std::gcd(fineRes / coarseRes, RTSDF_BRICK);
}

CascadeShape cascadeShapeFor(const Bounds& sceneBounds, const PipelineSettings& s) {
  s.validate();
  CascadeShape shape;
  shape.moveCells = levelMoveCells(s.coarseRes, s.fineRes);
  shape.levels = s.cascades;
  shape.coarseRes = s.coarseRes;
  shape.fineRes = s.fineRes;
  if (s.cascadeExtent > 0.0) {
    shape.levelZeroExtent = s.cascadeExtent;
  } else {
    if (!(sceneBounds.maxExtent() > 0.0))
      throw Error("cascades: the scene has no extent to size level 0 by (give the cascade extent)");
    shape.levelZeroExtent = std::ldexp(sceneBounds.maxExtent(), 1 - s.cascades);
  }
  return shape;
}

CascadeShape cascadeShapeFor(const Bounds& sceneBounds, const glm::dvec3& centre, const PipelineSettings& s) {
  CascadeShape shape = cascadeShapeFor(sceneBounds, s);
  if (s.cascadeExtent > 0.0) return shape;
  const glm::dvec3 reach = glm::max(centre - sceneBounds.min, sceneBounds.max - centre);
  const double radius = std::max({reach.x, reach.y, reach.z});
  // side = 2 radius + (moveCells + 1) coarse voxels of the outermost level (the snapping moves its centre by up to
  // half a move each way, and half a voxel each side to spare), its coarse voxel being side / coarseRes.
  const double outermost = 2.0 * radius * s.coarseRes / std::max(1, s.coarseRes - 1 - shape.moveCells);
  shape.levelZeroExtent = std::ldexp(outermost, 1 - s.cascades);
  return shape;
}

Bounds CascadeLevel::box() const { return fine.bounds(); }

CascadeLayout CascadeLayout::around(const glm::dvec3& camera, const CascadeShape& shape, const glm::dvec3& lookAhead) {
  CascadeLayout layout;
  layout.shape = shape;
  layout.camera = camera;
  const double reach = shape.maxLookAhead();
  layout.lookAhead = glm::clamp(lookAhead, glm::dvec3(-reach), glm::dvec3(reach));
  for (int i = 0; i < shape.levels; ++i) {
    const double c = shape.coarseVoxel(i);
    // The outermost level stays on the camera, so that it holds what the default extent sized it for (the whole
    // scene around the camera, behind it too); the finer ones reach ahead and still nest in it.
    const glm::dvec3 centre = i + 1 < shape.levels ? camera + std::ldexp(1.0, i) * layout.lookAhead : camera;
    CascadeLevel level;
    level.index = i;
    // The lattice point nearest the centre: the level moves only when the centre crosses half a move, and then by
    // whole moves of moveCells coarse voxels (a multiple of c in double: the same voxel centres before and after).
    const double move = c * std::max(1, shape.moveCells);
    for (int a = 0; a < 3; ++a)
      level.centreCell[a] = std::int64_t(std::floor(centre[a] / move + 0.5)) * std::max(1, shape.moveCells);
    const glm::dvec3 corner = glm::dvec3(level.centreCell - glm::i64vec3(shape.coarseRes / 2));
    level.coarse.origin = corner * c;
    level.coarse.voxelSize = c;
    level.coarse.dims = glm::ivec3(shape.coarseRes);
    level.fine.origin = level.coarse.origin;
    level.fine.voxelSize = shape.fineVoxel(i);
    level.fine.dims = glm::ivec3(shape.fineRes);
    layout.levels.push_back(level);
  }
  return layout;
}

int CascadeLayout::finestHolding(const glm::dvec3& p, double margin) const {
  for (const CascadeLevel& level : levels) {
    const Bounds b = level.box();
    if (glm::all(glm::greaterThanEqual(p, b.min + margin)) && glm::all(glm::lessThanEqual(p, b.max - margin)))
      return level.index;
  }
  return -1;
}

std::vector<glm::i64vec3> CascadeLayout::shiftSince(const CascadeLayout& before) const {
  if (before.levels.size() != levels.size())
    throw Error(fmt::format("cascades: a layout of {} levels cannot follow one of {}", levels.size(),
                            before.levels.size()));
  std::vector<glm::i64vec3> shift;
  for (std::size_t i = 0; i < levels.size(); ++i) shift.push_back(levels[i].centreCell - before.levels[i].centreCell);
  return shift;
}

} // namespace rtsdf
