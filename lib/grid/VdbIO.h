#pragma once
/// @file VdbIO.h
/// @brief The OpenVDB bridge: level-set grids from blocks or dense arrays, dense sampling, fog grids for
///        Blender, metadata, and atomic .vdb write / checked .vdb read.
#include "grid/GridSpec.h"
#include "util/EnumNames.h"

#include <openvdb/openvdb.h>

#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace rtsdf {

/// @brief The smallest voxel size OpenVDB's linear transforms accept: their maps refuse a scale whose
///        determinant h^3 is below 3e-15 ("Non-zero scale values required"), i.e. h below about 1.44e-5.
double minVdbVoxelSize();

/// @brief OpenVDB transform of a cell-centred grid: scale h, translated to voxel (0,0,0)'s centre.
/// @throw Error naming the voxel size when it is below minVdbVoxelSize() (the scene's units are too small
///        for OpenVDB at this resolution: scale the scene up or lower the resolution).
openvdb::math::Transform::Ptr makeTransform(const GridSpec& spec);

/// @brief Fills one 8x8x8 block of a level set. @a origin is the block's first voxel; @a values and
///        @a active hold 512 entries in OpenVDB leaf order (z fastest: offset = (x*8 + y)*8 + z, local
///        coordinates). Voxels outside the grid must be left inactive. Returns false when the block has
///        no active voxel (it is then not stored).
using LevelSetBlockFn = std::function<bool(const glm::ivec3& origin, float* values, bool* active)>;

/// @brief Build a sparse level set by calling @a fill for every 8^3 block of @a spec in parallel (TBB).
/// @param band the narrow band's half-width in world units: background = band, inactive voxels are ±band.
/// @note Blocks with no active voxel become tiles whose sign comes from openvdb::tools::signedFloodFill.
openvdb::FloatGrid::Ptr buildLevelSet(const GridSpec& spec, float band, const LevelSetBlockFn& fill);

/// @brief Sparse level set from a dense field (x fastest, GridSpec::linear order): voxels with
///        |value| <= band are active, the rest inactive at ±band.
openvdb::FloatGrid::Ptr denseToLevelSet(const std::vector<float>& dense, const GridSpec& spec, float band);

/// @brief Sparse level set from its active voxels alone, e.g. a band compacted on the GPU: each (GridSpec::linear
///        index, value) is active, in any order and without repeats; every other voxel is inactive at ±band, its
///        sign from openvdb::tools::signedFloodFill.
/// @throw Error when an index lies outside @a spec.
openvdb::FloatGrid::Ptr activeVoxelsToLevelSet(std::vector<std::pair<std::uint64_t, float>> voxels,
                                               const GridSpec& spec, float band);

/// @brief Sample a grid at every voxel of @a spec (inactive voxels give their stored ±background).
/// @note The grid's transform must equal makeTransform(spec).
std::vector<float> levelSetToDense(const openvdb::FloatGrid& grid, const GridSpec& spec);

/// @brief Mark @a grid as rtsdf's level set: class GRID_LEVEL_SET, name "surface", the cell-centred
///        transform of @a spec, and rtsdf:* metadata with the grid layout and the @a settings that made it.
void stampLevelSet(openvdb::FloatGrid& grid, const GridSpec& spec, const std::map<std::string, std::string>& settings);

/// @brief The grid layout recorded by stampLevelSet (dims and origin), checked against the transform.
/// @throw Error when the metadata is missing or inconsistent (a .vdb not written by rtsdf).
GridSpec gridSpecOf(const openvdb::FloatGrid& grid);

/// @brief A fog volume named "density" (0 outside, rising to 1 inside) so Blender shows the level set.
openvdb::FloatGrid::Ptr makeFogGrid(const openvdb::FloatGrid& levelSet);

/// @brief Compression of a written .vdb file.
enum class VdbCompression {
  None,  ///< raw values
  Zip,   ///< zlib
  Blosc  ///< Blosc LZ4 (OpenVDB's fastest; the default)
};
template <> struct EnumNames<VdbCompression> {
  static constexpr const char* kSetting = "compression";
  static constexpr std::pair<const char*, VdbCompression> kValues[] = {
      {"blosc", VdbCompression::Blosc}, {"zip", VdbCompression::Zip}, {"none", VdbCompression::None}};
};

/// @brief Options of writeVdb.
struct VdbWriteOptions {
  VdbCompression compression = VdbCompression::Blosc;
  bool halfFloat = false; ///< store float grids as 16-bit halves (smaller files, ~3 significant digits)
};

/// @brief Write @a grids to @a path atomically (temporary file, then rename).
/// @throw Error naming the file on any failure; no partial file is left behind.
void writeVdb(const std::filesystem::path& path, const openvdb::GridPtrVec& grids, const VdbWriteOptions& options = {});

/// @brief Read every grid of a .vdb file.
/// @throw Error naming the file when it is missing, not a regular file, larger than half the memory available,
///        or not a readable .vdb (see readVdbBytes).
openvdb::GridPtrVec readVdb(const std::filesystem::path& path);

/// @brief Read every grid of a .vdb held in memory, defensively: the header, metadata tables and grid
///        descriptors are walked first (every length bounded by the bytes, every grid ending inside them), then
///        OpenVDB reads through a stream that throws at its first read past the end.
/// @param name what errors call the bytes (the file's path).
/// @throw Error naming @a name, the problem and its byte offset, on one short line.
openvdb::GridPtrVec readVdbBytes(const std::string& bytes, const std::string& name);

/// @brief Read the level set of a .vdb: the float grid named "surface", else the only float level set.
/// @throw Error naming the file when there is no such grid.
openvdb::FloatGrid::Ptr readLevelSet(const std::filesystem::path& path);

} // namespace rtsdf
