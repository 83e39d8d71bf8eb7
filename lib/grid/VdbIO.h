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
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace rtsdf {

/// @brief The smallest voxel size OpenVDB's linear transforms accept: their maps refuse a scale whose
///        determinant h^3 is below 3e-15 ("Non-zero scale values required"), i.e. h below about 1.44e-5.
double minVdbVoxelSize();

/// @brief The axis that points up in a written .vdb. Scenes are Y-up (glTF, OBJ by custom); Blender is Z-up.
enum class UpAxis {
  Y, ///< as the scene is
  Z  ///< turned +90 degrees about X, (x, y, z) -> (x, -z, y), as Blender's glTF import turns a Y-up scene
};
template <> struct EnumNames<UpAxis> {
  static constexpr const char* kSetting = "up axis";
  static constexpr std::pair<const char*, UpAxis> kValues[] = {{"y", UpAxis::Y}, {"z", UpAxis::Z}};
};

/// @brief OpenVDB transform of a cell-centred grid: scale h, translated to voxel (0,0,0)'s centre, then turned so
///        that @a up points up (exactly: the turn's matrix holds only 0 and +-1).
/// @throw Error naming the voxel size when it is below minVdbVoxelSize() (the scene's units are too small
///        for OpenVDB at this resolution: scale the scene up or lower the resolution).
openvdb::math::Transform::Ptr makeTransform(const GridSpec& spec, UpAxis up = UpAxis::Y);

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

/// @brief One rtsdf:* metadata value: text, or a number stored as a number (Blender and OpenVDB's tools show it
///        as one). An int is stored as a 32-bit integer, a std::int64_t as a 64-bit one, a double as a double.
using MetaValue = std::variant<std::string, double, int, std::int64_t>;

/// @brief Mark @a grid as rtsdf's level set: class GRID_LEVEL_SET, name "surface", the cell-centred
///        transform of @a spec, and rtsdf:* metadata with the grid layout and the @a settings that made it.
void stampLevelSet(openvdb::FloatGrid& grid, const GridSpec& spec, const std::map<std::string, MetaValue>& settings);

/// @brief The scene's path as a file records it (rtsdf:scene): absolute, so that it is found from any folder
///        (writeVdb adds the path relative to the file); empty, or a name in angle brackets (a scene in memory),
///        as it is.
std::string recordedScenePath(const std::string& scene);

/// @brief The number a metadata entry holds: a number of any OpenVDB type, or text that is a number (files written
///        before numbers were stored as numbers); empty when absent or not a number.
std::optional<double> numberMeta(const openvdb::GridBase& grid, const std::string& key);

/// @brief The text a metadata entry holds (a number as OpenVDB prints it); empty when absent.
std::string stringMeta(const openvdb::GridBase& grid, const std::string& key);

/// @brief The up axis a grid was written with (rtsdf:up; Y when absent).
/// @throw Error naming the grid when rtsdf:up holds anything but "y" or "z".
UpAxis upAxisOf(const openvdb::GridBase& grid);

/// @brief @a grid in its scene's frame: itself when Y-up, else a copy sharing its tree whose transform undoes the
///        turn an --up z write added (exactly, so that it equals makeTransform of its layout again).
openvdb::FloatGrid::Ptr inSceneFrame(const openvdb::FloatGrid::Ptr& grid);

/// @brief The grid layout recorded by stampLevelSet (dims and origin), checked against the transform (turned as
///        rtsdf:up says).
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
  UpAxis up = UpAxis::Y;  ///< Z: every grid's transform turned so the scene stands upright in Z-up tools (Blender)
};

/// @brief Write @a grids to @a path atomically (temporary file, then rename).
/// @details The grids written are shallow copies (the trees are shared, the caller's grids are left as they are):
///          with options.up Z each transform is turned (makeTransform) and rtsdf:up = "z" recorded; a grid that
///          records its scene (rtsdf:scene, an absolute path) also gets rtsdf:scene_relative, the scene's path
///          relative to @a path's folder, so that the scene is found when both move together.
/// @throw Error naming the file on any failure; no partial file is left behind.
void writeVdb(const std::filesystem::path& path, const openvdb::GridPtrVec& grids, const VdbWriteOptions& options = {});

/// @brief Read every grid of a .vdb file.
/// @throw Error naming the file when it is missing, not a regular file, larger than half the memory available,
///        or not a readable .vdb (see readVdbBytes).
openvdb::GridPtrVec readVdb(const std::filesystem::path& path);

/// @brief Read every grid of a .vdb held in memory, defensively: the whole file is walked first as OpenVDB 10 reads
///        it (header, metadata, descriptors, transforms, topology and every chunk of values: each length bounded by
///        the bytes and by what the reader expects, each grid ending at its end offset), then OpenVDB reads through
///        a stream that throws at its first read past the end. Grids of types other than float, double, int32,
///        int64, vec3s/d/i, bool and mask (points, strings, ...) are refused.
/// @param name what errors call the bytes (the file's path).
/// @throw Error naming @a name, the problem and its byte offset, on one short line.
openvdb::GridPtrVec readVdbBytes(const std::string& bytes, const std::string& name);

/// @brief Read the level set of a .vdb, checked (LevelSetRead.cpp): the grid named @a gridName, else the one
///        candidate (a grid named "surface" or of class level set; the only grid when there is no candidate). It
///        must hold floats, be of class level set, have a linear transform with cubic voxels, a positive finite
///        background and finite values. Active tiles are turned into their voxels (tools that count or visit
///        active voxels leaf by leaf would skip them).
/// @throw SettingError("grid") naming the file and listing the candidates when there are several; Error naming
///        the file, the grid and what is wrong otherwise (no such grid, not a level set, not float, a frustum or
///        non-uniform transform, values that are NaN or infinite, tiles too large to expand in memory).
openvdb::FloatGrid::Ptr readLevelSet(const std::filesystem::path& path, const std::string& gridName = {});

} // namespace rtsdf
