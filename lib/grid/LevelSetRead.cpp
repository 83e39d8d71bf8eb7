// The level set of a .vdb, chosen and checked before anything measures it: a fog volume, a double grid, a frustum
// transform or NaN voxels read as a level set give numbers that look like results (100% of signs "disagree", a
// max error of 0 over NaN voxels), so each is refused naming the file, the grid and what is wrong.
#include "grid/VdbIO.h"

#include "util/Error.h"
#include "util/Memory.h"
#include "util/Text.h"

#include <fmt/format.h>
#include <openvdb/tools/Diagnostics.h>

#include <cmath>

namespace rtsdf {
namespace fs = std::filesystem;
using openvdb::FloatGrid;

namespace {

std::string className(openvdb::GridClass c) {
  switch (c) {
  case openvdb::GRID_LEVEL_SET: return "level set";
  case openvdb::GRID_FOG_VOLUME: return "fog volume";
  case openvdb::GRID_STAGGERED: return "staggered grid";
  default: return "grid of unknown class";
  }
}

/// "'surface' (float level set)": how a grid is listed in errors.
std::string describeGrid(const openvdb::GridBase& g) {
  return fmt::format("'{}' ({} {})", oneLine(g.getName(), 60), g.valueType(), className(g.getGridClass()));
}

std::string listGrids(const openvdb::GridPtrVec& grids) {
  std::string list;
  for (std::size_t i = 0; i < grids.size() && i < 6; ++i) list += (i ? ", " : "") + describeGrid(*grids[i]);
  if (grids.size() > 6) list += fmt::format(" and {} more", grids.size() - 6);
  return list;
}

/// The grid named @a name, or the one candidate: named "surface" or of class level set; the only grid when none is.
openvdb::GridBase::Ptr chooseGrid(const openvdb::GridPtrVec& grids, const fs::path& path, const std::string& name) {
  const std::string file = path.string();
  if (grids.empty()) throw Error(fmt::format("{}: the file holds no grid", file));
  openvdb::GridPtrVec chosen;
  for (const auto& g : grids)
    if (name.empty() ? g->getName() == "surface" || g->getGridClass() == openvdb::GRID_LEVEL_SET : g->getName() == name)
      chosen.push_back(g);
  if (chosen.empty() && name.empty() && grids.size() == 1) chosen = grids;
  if (chosen.empty())
    throw Error(name.empty() ? fmt::format("{}: no level set: no grid named 'surface' and none of class level set "
                                           "(grids: {})", file, listGrids(grids))
                             : fmt::format("{}: no grid named '{}' (grids: {})", file, oneLine(name, 60),
                                           listGrids(grids)));
  if (chosen.size() > 1)
    throw SettingError("grid", name.empty() ? fmt::format("{} holds {} candidate level sets: {}: name the one to read",
                                                          file, chosen.size(), listGrids(chosen))
                                            : fmt::format("{} holds {} grids named '{}': {}", file, chosen.size(),
                                                          oneLine(name, 60), listGrids(chosen)));
  return chosen.front();
}

/// Class, value type, transform and background: what a level set is before its values are looked at.
FloatGrid::Ptr requireLevelSetShape(const openvdb::GridBase::Ptr& g, const std::string& where) {
  if (g->getGridClass() != openvdb::GRID_LEVEL_SET)
    throw Error(fmt::format("{} is a {}, not a level set (a signed distance field of class level set)", where,
                            className(g->getGridClass())));
  FloatGrid::Ptr f = openvdb::gridPtrCast<FloatGrid>(g);
  if (!f) throw Error(fmt::format("{} holds {} values: rtsdf reads level sets of float values", where, g->valueType()));
  const openvdb::math::Transform& xf = f->transform();
  if (!xf.isLinear()) {
    const bool frustum = xf.mapType() == openvdb::math::NonlinearFrustumMap::mapType();
    throw Error(fmt::format("{} has a {} transform, not a linear one: its voxels have no single size", where,
                            frustum ? "frustum" : xf.mapType()));
  }
  if (!f->hasUniformVoxels()) {
    const openvdb::Vec3d s = f->voxelSize();
    throw Error(fmt::format("{} has voxels of {:.6g} x {:.6g} x {:.6g}, not cubes: distances in voxels would depend "
                            "on the direction", where, s.x(), s.y(), s.z()));
  }
  if (!(std::isfinite(f->background()) && f->background() > 0.0f))
    throw Error(fmt::format("{} has the background {} (a level set's is its band's half-width: positive, finite)",
                            where, f->background()));
  return f;
}

/// NaN or infinite values (voxels and tiles, active or not: sampling may read either).
void requireFiniteValues(const FloatGrid& f, const std::string& where) {
  openvdb::tools::Diagnose<FloatGrid> diagnose(f);
  openvdb::tools::CheckFinite<FloatGrid, FloatGrid::ValueAllCIter> check;
  if (diagnose.check(check, /*updateMask=*/false, /*checkVoxels=*/true, /*checkTiles=*/true,
                     /*checkBackground=*/true).empty())
    return;
  throw Error(fmt::format("{} holds {} values that are NaN or infinite", where, diagnose.failureCount()));
}

/// Active tiles become their voxels, within memory: a tile of the top level stands for 4096^3 voxels.
void expandActiveTiles(FloatGrid& f, const std::string& where) {
  if (f.tree().activeTileCount() == 0) return;
  const std::uint64_t voxels = f.activeVoxelCount();
  const double bytes = double(voxels) * (sizeof(float) + 0.25); // values, masks and node pointers
  const std::uint64_t available = availableHostMemory();
  // At most half the memory, and at most 2^27 voxels (about 0.5 GiB): a level set's band is voxels; tiles that
  // stand for more are a corrupt or hostile file, not a field to compare.
  constexpr std::uint64_t kMostTileVoxels = std::uint64_t(1) << 27;
  if (voxels > kMostTileVoxels)
    throw Error(fmt::format("{} has active tiles standing for {} voxels, more than the {} a level set's band can "
                            "hold", where, voxels, kMostTileVoxels));
  if (available && bytes > 0.5 * double(available))
    throw Error(fmt::format("{} has active tiles standing for {} voxels ({:.1f} GiB as voxels), more than half the "
                            "memory available ({:.1f} GiB)", where, voxels, bytes / 1073741824.0,
                            double(available) / 1073741824.0));
  f.tree().voxelizeActiveTiles();
}

} // namespace

FloatGrid::Ptr readLevelSet(const fs::path& path, const std::string& gridName) {
  const openvdb::GridPtrVec grids = readVdb(path);
  const openvdb::GridBase::Ptr g = chooseGrid(grids, path, gridName);
  const std::string where = fmt::format("{}: grid '{}'", path.string(), oneLine(g->getName(), 60));
  FloatGrid::Ptr f = requireLevelSetShape(g, where);
  requireFiniteValues(*f, where);
  expandActiveTiles(*f, where);
  return f;
}

} // namespace rtsdf
