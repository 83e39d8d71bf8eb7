#include "sdf/coarse/CoarseScroll.h"

#include <limits>

namespace rtsdf {

std::vector<CoarseVoxelBox> boxesOutside(const glm::ivec3& dims, const CoarseVoxelBox& kept) {
  return boxesOutside(CoarseVoxelBox{glm::ivec3(0), dims - 1}, kept);
}

std::vector<CoarseVoxelBox> boxesOutside(const CoarseVoxelBox& grid, const CoarseVoxelBox& kept) {
  if (kept.empty()) return grid.empty() ? std::vector<CoarseVoxelBox>{} : std::vector<CoarseVoxelBox>{grid};
  std::vector<CoarseVoxelBox> boxes;
  // Axis by axis: the slabs below and above the kept box, then the rest narrowed to its range on that axis.
  CoarseVoxelBox rest = grid;
  for (int a = 0; a < 3; ++a) {
    CoarseVoxelBox below = rest, above = rest;
    below.hi[a] = kept.lo[a] - 1;
    above.lo[a] = kept.hi[a] + 1;
    for (const CoarseVoxelBox& b : {below, above})
      if (!b.empty()) boxes.push_back(b);
    rest.lo[a] = kept.lo[a];
    rest.hi[a] = kept.hi[a];
  }
  return boxes;
}

std::optional<glm::ivec3> seedLatticeCell(const GridSpec& coarse) {
  const glm::dvec3 cells = glm::round(coarse.origin / coarse.voxelSize);
  // The triangles' cell coordinates are floats: within 2^17 cells of the lattice's origin they keep 1/64 of a voxel.
  const glm::dvec3 farthest = glm::abs(cells) + glm::dvec3(coarse.dims);
  if (glm::any(glm::greaterThan(farthest, glm::dvec3(kSeedLatticeCells)))) return std::nullopt;
  if (cells * coarse.voxelSize != coarse.origin) return std::nullopt;
  return glm::ivec3(cells);
}

std::vector<CoarseVoxelBox> scrollChanges(const glm::ivec3& dims, const glm::ivec3& shift) {
  const CoarseVoxelBox grid{glm::ivec3(0), dims - 1};
  auto bound = [](const std::vector<CoarseVoxelBox>& boxes) {
    CoarseVoxelBox b{glm::ivec3(std::numeric_limits<int>::max()), glm::ivec3(std::numeric_limits<int>::min())};
    for (const CoarseVoxelBox& c : boxes) b = {glm::min(b.lo, c.lo), glm::max(b.hi, c.hi)};
    return boxes.empty() ? CoarseVoxelBox{} : b;
  };
  // The old grid's voxels in the new one's coordinates: those outside it held the seeds that left.
  const CoarseVoxelBox old{-shift, dims - 1 - shift};
  const CoarseVoxelBox stayed{glm::max(old.lo, grid.lo), glm::min(old.hi, grid.hi)};
  return {bound(boxesOutside(grid, stayed)), bound(boxesOutside(old, stayed))};
}

CoarseVoxelBox keptByShift(const glm::ivec3& dims, const glm::ivec3& shift) {
  // v + shift in [0, dims): v in [-shift, dims - shift) within the grid.
  return {glm::max(-shift, glm::ivec3(0)), glm::min(dims - 1 - shift, dims - 1)};
}

std::vector<CoarseVoxelBox> scrollUpsampleBoxes(const glm::ivec3& dims, const glm::ivec3& shift) {
  const CoarseVoxelBox grid{glm::ivec3(0), dims - 1};
  const CoarseVoxelBox kept = keptByShift(dims, shift);
  if (kept.empty()) return {grid};
  std::vector<CoarseVoxelBox> boxes = boxesOutside(dims, kept);
  // Voxel v took v + shift's place: a grid moved up an axis (shift > 0) left its low face behind, and the reverse.
  for (int a = 0; a < 3; ++a) {
    if (shift[a] == 0) continue;
    CoarseVoxelBox face = grid;
    face.lo[a] = face.hi[a] = shift[a] > 0 ? 0 : dims[a] - 1;
    boxes.push_back(face);
  }
  return boxes;
}

} // namespace rtsdf
