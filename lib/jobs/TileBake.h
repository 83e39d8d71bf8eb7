#pragma once
/// @file TileBake.h
/// @brief One scene's exact bake split into tiles that separate processes or machines bake on their own: the
///        whole bake's grid cut into slabs of whole 8^3 leaves, each tile's distances and signs computed exactly
///        as the whole bake computes them, and the tiles merged back into the very level set of the whole bake.
#include "jobs/Bake.h"

#include <openvdb/openvdb.h>

#include <cstdint>
#include <vector>

namespace rtsdf {

/// @brief One tile of a tiled bake.
struct TileBakeOptions {
  BakeOptions bake;  ///< the whole bake's settings (scene, resolution, band, padding, sign, time); method exact
  int tiles = 8;     ///< tiles the grid is cut into, in [1, 4096]
  int tile = 0;      ///< the tile to bake, in [0, tiles)
  /// @throw SettingError naming "tiles", "tile" or "bake method" (only the exact method bakes by tiles), or
  ///        a setting of the bake.
  void validate() const;
};

/// @brief The grid of the whole bake of @a scene with @a options (the voxels bake() samples for the exact method).
/// @throw As bake().
GridSpec tiledBakeGrid(const Scene& scene, const BakeOptions& options);

/// @brief @a spec's voxels cut into @a tiles slabs along its longest axis, each a whole number of 8^3 leaves
///        (boxes of index space; a slab is empty when there are fewer leaves along that axis than tiles).
std::vector<openvdb::CoordBBox> tileBoxes(const GridSpec& spec, int tiles);

/// @brief Bake tile @a options.tile: the exact distances of the whole bake's leaves inside its box, signed by the
///        whole scene's rule (every triangle is loaded; only the leaves of the box are evaluated). The result's
///        grid holds that tile's leaves only, on the whole bake's transform; no active voxel is not an error.
/// @throw As bake(), SettingError from options.validate().
BakeResult bakeTile(const Scene& scene, const TileBakeOptions& options);

/// @brief Merge the tiles of one bake (bakeTile results, in any order) with OpenVDB's tree merge (MERGE_NODES:
///        the tiles' leaves are disjoint) and flood-fill the signs of the whole tree again, so that the result
///        equals the whole bake voxel for voxel, inactive values included.
/// @param tiles the tile grids; they are emptied (their nodes move into the result)
/// @throw Error when @a tiles is empty or their transforms differ.
openvdb::FloatGrid::Ptr mergeTiles(const std::vector<openvdb::FloatGrid::Ptr>& tiles);

/// @brief The voxels and tiles where @a a and @a b differ in value or active state (0: the same level set).
std::uint64_t countDifferentValues(const openvdb::FloatGrid& a, const openvdb::FloatGrid& b);

} // namespace rtsdf
