#include "sdf/cascade/ToroidalLevelCpu.h"

#include "sdf/coarse/CoarseParams.h"
#include "util/Error.h"

#include <algorithm>
#include <cmath>

namespace rtsdf {

using Cell = glm::i64vec3;

namespace {

std::int64_t floorMod(std::int64_t a, std::int64_t n) { return ((a % n) + n) % n; }

/// Whether triangle @a t (world) touches world lattice cell @a cell of size @a h: the coarse voxelization's own
/// conservative test (CoarseParams.h), with corners taken relative to the cell's centre in double, so the answer
/// depends on the cell alone and not on where the level lies.
bool touches(const glm::dvec3* t, const Cell& cell, double h) {
  const glm::dvec3 centre = (glm::dvec3(cell) + 0.5) * h;
  const glm::vec3 a((t[0] - centre) / h), b((t[1] - centre) / h), c((t[2] - centre) / h);
  return gpu::shared::triangleOverlapsBox(a, b, c, 0.5f);
}

} // namespace

ToroidalLevelCpu::ToroidalLevelCpu(std::vector<glm::dvec3> triangles, int maxVoxels)
    : mTriangles(std::move(triangles)), mMaxVoxels(maxVoxels) {
  if (mTriangles.size() % 3 != 0) throw Error("toroidal level: 3 corners per triangle");
  if (maxVoxels < 1) throw Error("toroidal level: the distance clamp must be at least one voxel");
}

std::size_t ToroidalLevelCpu::slot(const Cell& w) const {
  const std::int64_t n = mN;
  return std::size_t((floorMod(w.z, n) * n + floorMod(w.y, n)) * n + floorMod(w.x, n));
}

void ToroidalLevelCpu::voxelize(const Cell& lo, const Cell& hi) {
  for (std::int64_t z = lo.z; z < hi.z; ++z)
    for (std::int64_t y = lo.y; y < hi.y; ++y)
      for (std::int64_t x = lo.x; x < hi.x; ++x) mSeed[slot({x, y, z})] = 0;
  for (std::size_t t = 0; t < mTriangles.size(); t += 3) {
    const glm::dvec3* tri = &mTriangles[t];
    const glm::dvec3 mn = glm::min(tri[0], glm::min(tri[1], tri[2])) / mVoxel;
    const glm::dvec3 mx = glm::max(tri[0], glm::max(tri[1], tri[2])) / mVoxel;
    // One cell of margin, as the GPU's range (voxelRangeLo/Hi); the overlap test decides.
    const Cell from = glm::max(Cell(glm::floor(mn)) - Cell(1), lo);
    const Cell to = glm::min(Cell(glm::floor(mx)) + Cell(2), hi);
    for (std::int64_t z = from.z; z < to.z; ++z)
      for (std::int64_t y = from.y; y < to.y; ++y)
        for (std::int64_t x = from.x; x < to.x; ++x) {
          std::uint8_t& s = mSeed[slot({x, y, z})];
          if (!s && touches(tri, {x, y, z}, mVoxel)) s = 1;
        }
  }
  const Cell n = glm::max(hi - lo, Cell(0));
  mVoxelized += std::uint64_t(n.x * n.y * n.z);
}

void ToroidalLevelCpu::transform(Cell lo, Cell hi) {
  lo = glm::max(lo, mCorner);
  hi = glm::min(hi, mCorner + Cell(mN));
  if (glm::any(glm::greaterThanEqual(lo, hi))) return;
  const std::int64_t r = mMaxVoxels, n = mN;
  const std::vector<std::uint8_t> local = seeds(); // the level's own order: no wrap-around in the inner loop
  for (std::int64_t z = lo.z; z < hi.z; ++z)
    for (std::int64_t y = lo.y; y < hi.y; ++y)
      for (std::int64_t x = lo.x; x < hi.x; ++x) {
        // The nearest seed within the clamp, among the level's own voxels.
        const Cell a = glm::max(Cell(x, y, z) - Cell(r), mCorner);
        const Cell b = glm::min(Cell(x, y, z) + Cell(r + 1), mCorner + Cell(mN));
        std::int64_t best = r * r;
        for (std::int64_t k = a.z; k < b.z; ++k)
          for (std::int64_t j = a.y; j < b.y; ++j)
            for (std::int64_t i = a.x; i < b.x; ++i)
              if (local[std::size_t(((k - mCorner.z) * n + (j - mCorner.y)) * n + (i - mCorner.x))]) {
                const Cell d = Cell(i, j, k) - Cell(x, y, z);
                best = std::min(best, d.x * d.x + d.y * d.y + d.z * d.z);
              }
        mDistance[slot({x, y, z})] = float(std::sqrt(double(best)));
      }
  const Cell size = hi - lo;
  mTransformed += std::uint64_t(size.x * size.y * size.z);
}

void ToroidalLevelCpu::rebuild(const CascadeLevel& level) {
  mVoxel = level.coarse.voxelSize;
  mN = level.coarse.dims.x;
  mCorner = level.centreCell - Cell(mN / 2);
  mSeed.assign(std::size_t(mN) * mN * mN, 0);
  mDistance.assign(mSeed.size(), 0.0f);
  mVoxelized = mTransformed = 0;
  voxelize(mCorner, mCorner + Cell(mN));
  transform(mCorner, mCorner + Cell(mN));
}

void ToroidalLevelCpu::moveTo(const CascadeLevel& level) {
  const Cell corner = level.centreCell - Cell(mN / 2);
  const Cell shift = corner - mCorner;
  if (level.coarse.voxelSize != mVoxel || level.coarse.dims.x != mN ||
      glm::any(glm::greaterThanEqual(glm::abs(shift), Cell(mN)))) {
    rebuild(level);
    return;
  }
  mVoxelized = mTransformed = 0;
  const Cell oldLo = mCorner, oldHi = mCorner + Cell(mN);
  mCorner = corner;
  const Cell lo = mCorner, hi = mCorner + Cell(mN);
  const std::int64_t r = mMaxVoxels;
  // Per axis: the slab that entered (new cells outside the old box), voxelized, and the cells whose nearest seeds
  // within the clamp changed: those within r of the entered slab, and those within r of the face the level left.
  for (int a = 0; a < 3; ++a) {
    if (shift[a] == 0) continue;
    Cell slabLo = lo, slabHi = hi;
    if (shift[a] > 0) slabLo[a] = oldHi[a];
    else slabHi[a] = oldLo[a];
    voxelize(slabLo, slabHi);
  }
  for (int a = 0; a < 3; ++a) {
    if (shift[a] == 0) continue;
    Cell enteredLo = lo, enteredHi = hi, leftLo = lo, leftHi = hi;
    if (shift[a] > 0) {
      enteredLo[a] = oldHi[a] - r;      // the slab and r cells before it
      leftHi[a] = lo[a] + r;            // r cells after the face moved past
    } else {
      enteredHi[a] = oldLo[a] + r;
      leftLo[a] = hi[a] - r;
    }
    transform(enteredLo, enteredHi);
    transform(leftLo, leftHi);
  }
}

std::vector<float> ToroidalLevelCpu::distances() const {
  std::vector<float> out;
  out.reserve(mDistance.size());
  for (std::int64_t z = 0; z < mN; ++z)
    for (std::int64_t y = 0; y < mN; ++y)
      for (std::int64_t x = 0; x < mN; ++x) out.push_back(mDistance[slot(mCorner + Cell(x, y, z))]);
  return out;
}

std::vector<std::uint8_t> ToroidalLevelCpu::seeds() const {
  std::vector<std::uint8_t> out;
  out.reserve(mSeed.size());
  for (std::int64_t z = 0; z < mN; ++z)
    for (std::int64_t y = 0; y < mN; ++y)
      for (std::int64_t x = 0; x < mN; ++x) out.push_back(mSeed[slot(mCorner + Cell(x, y, z))]);
  return out;
}

} // namespace rtsdf
