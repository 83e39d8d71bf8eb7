#include "jobs/TileBake.h"

#include "grid/VdbIO.h"
#include "jobs/JobSupport.h"
#include "reference/ExactSdf.h"
#include "scene/SceneGeometry.h"
#include "sdf/PipelineSettings.h"
#include "util/Error.h"

#include <fmt/format.h>
#include <openvdb/tools/SignedFloodFill.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace rtsdf {

void TileBakeOptions::validate() const {
  bake.validate();
  if (bake.method != BakeMethod::Exact)
    throw SettingError("bake method", fmt::format("a tiled bake uses the exact method (not {}): its tiles must be "
                                                  "baked the same way as the whole grid", toString(bake.method)));
  if (bake.grid) throw SettingError("grid", "a tiled bake samples the scene's own grid");
  if (bake.fullDomain) throw SettingError("full domain", "a tiled bake bakes a narrow band (its tiles' leaves)");
  if (tiles < 1 || tiles > 4096) throw SettingError("tiles", fmt::format("tiles {} must be in [1, 4096]", tiles));
  if (tile < 0 || tile >= tiles) throw SettingError("tile", fmt::format("tile {} must be in [0, {})", tile, tiles));
}

GridSpec tiledBakeGrid(const Scene& scene, const BakeOptions& o) {
  const SceneGeometry geo = buildSceneGeometry(scene, o.time);
  const GridSpec spec = GridSpec::fromBounds(geo.bounds, o.resolution, pipelinePadding(geo.bounds, o.pipeline));
  requireBandWithin(spec, o.pipeline.band);
  return spec;
}

std::vector<openvdb::CoordBBox> tileBoxes(const GridSpec& spec, int tiles) {
  const int axis = spec.dims.x >= spec.dims.y && spec.dims.x >= spec.dims.z ? 0 : spec.dims.y >= spec.dims.z ? 1 : 2;
  const int leaves = (spec.dims[axis] + 7) / 8;
  std::vector<openvdb::CoordBBox> boxes;
  for (int t = 0; t < tiles; ++t) {
    // Whole leaves, as even as they divide: leaves [first, last) of the axis.
    const int first = int(std::int64_t(leaves) * t / tiles), last = int(std::int64_t(leaves) * (t + 1) / tiles);
    openvdb::Coord lo(0, 0, 0), hi(spec.dims.x - 1, spec.dims.y - 1, spec.dims.z - 1);
    lo[axis] = 8 * first;
    hi[axis] = std::min(8 * last, spec.dims[axis]) - 1;
    boxes.emplace_back(lo, hi); // empty when last == first
  }
  return boxes;
}

BakeResult bakeTile(const Scene& scene, const TileBakeOptions& o) {
  o.validate();
  const SceneGeometry geo = buildSceneGeometry(scene, o.bake.time);
  BakeResult r;
  r.spec = tiledBakeGrid(scene, o.bake);
  ExactSdfOptions opt;
  opt.band = o.bake.pipeline.band;
  opt.sign = o.bake.sign;
  opt.progress = false;
  opt.window = tileBoxes(r.spec, o.tiles)[std::size_t(o.tile)];
  const auto t0 = std::chrono::steady_clock::now();
  r.grid = !opt.window.empty() ? exactSignedDistance(geo, r.spec, opt, &r.exact)
                                : buildLevelSet(r.spec, float(opt.band), [](const glm::ivec3&, float*, bool*) { return false; });
  r.seconds = secondsSince(t0);
  // The whole bake's metadata (bakeOnGrid), and the tiling: the merged grid keeps the first tile's.
  stampLevelSet(*r.grid, r.spec,
                {{"method", "exact"}, {"scene", o.bake.scene}, {"resolution", std::to_string(o.bake.resolution)},
                 {"band", fmt::format("{}", o.bake.pipeline.band)},
                 {"padding", fmt::format("{}", pipelinePadding(geo.bounds, o.bake.pipeline))},
                 {"time", fmt::format("{}", o.bake.time)}, {"sign", toString(o.bake.sign)},
                 {"tiles", std::to_string(o.tiles)}, {"version", detail::version()}});
  r.sceneSummary = detail::meshSummary(scene);
  return r;
}

openvdb::FloatGrid::Ptr mergeTiles(const std::vector<openvdb::FloatGrid::Ptr>& tiles) {
  if (tiles.empty()) throw Error("merge tiles: no tile to merge");
  openvdb::FloatGrid::Ptr merged = tiles.front()->copyWithNewTree();
  for (const openvdb::FloatGrid::Ptr& tile : tiles) {
    if (tile->transform() != merged->transform() || tile->background() != merged->background())
      throw Error("merge tiles: the tiles come from different bakes (transform or band differ)");
    // MERGE_NODES moves the tile's child nodes and ignores its tiles, whose signs were flood-filled from that
    // tile's leaves alone; the flood fill below signs them from every leaf, as the whole bake does.
    merged->tree().merge(tile->tree(), openvdb::MERGE_NODES);
  }
  openvdb::tools::signedFloodFill(merged->tree());
  return merged;
}

namespace {

/// Values and tiles of @a a that @a b does not hold (value or active state), by visiting every value of a.
std::uint64_t valuesNotIn(const openvdb::FloatGrid& a, const openvdb::FloatGrid& b) {
  const auto bAccess = b.getConstAccessor();
  std::uint64_t differ = 0;
  for (auto it = a.tree().cbeginValueAll(); it; ++it) {
    const openvdb::Coord c = it.getCoord();
    if (bAccess.getValue(c) != *it || bAccess.isValueOn(c) != it.isValueOn()) ++differ;
  }
  return differ;
}

} // namespace

std::uint64_t countDifferentValues(const openvdb::FloatGrid& a, const openvdb::FloatGrid& b) {
  std::uint64_t differ = valuesNotIn(a, b) + valuesNotIn(b, a);
  if (a.transform() != b.transform() || a.background() != b.background()) ++differ;
  return differ;
}

} // namespace rtsdf
