#pragma once
/// @file Compare.h
/// @brief Two level sets of the same space compared in the first one's voxels: read from two .vdb files (any
///        transforms: B is resampled when its voxels differ), or one file against an anchor (the exact field or
///        OpenVDB's meshToLevelSet) baked on its own voxels and band.
#include "metrics/FieldError.h"
#include "util/EnumNames.h"
#include "util/JobControl.h"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace rtsdf {

/// @brief The anchors a level set can be measured against.
enum class CompareAnchor {
  Exact,  ///< the exact field (Embree closest points, the exact bake's sign rule)
  OpenVdb ///< OpenVDB's meshToLevelSet
};
template <> struct EnumNames<CompareAnchor> {
  static constexpr const char* kSetting = "anchor";
  static constexpr std::pair<const char*, CompareAnchor> kValues[] = {{"exact", CompareAnchor::Exact},
                                                                      {"openvdb", CompareAnchor::OpenVdb}};
};

/// @brief What to compare.
struct CompareOptions {
  std::filesystem::path a;              ///< the level set measured (its voxels are the unit)
  std::filesystem::path b;              ///< the level set it is compared with; empty when @a against is set
  std::optional<CompareAnchor> against; ///< bake this anchor on A's voxels and band instead of reading B
  /// The anchor's scene (.json or mesh); empty: the one A's metadata records, found by its absolute path
  /// (rtsdf:scene), else by its path relative to A (rtsdf:scene_relative), else (files of older versions) as
  /// written and beside A. The anchor is baked at A's rtsdf:time (0 when absent).
  std::string scene;
  /// The grid to read from each file; empty: the one candidate (readLevelSet: "surface" or the only level set).
  std::string grid;
  /// @throw SettingError unless exactly one of @a b and @a against is given, or when @a scene is given without
  ///        @a against.
  void validate() const;
};

/// @brief The comparison of two level sets.
struct FileComparison {
  FieldError error;                 ///< |A - B| in A's voxels and sign disagreement
  std::uint64_t activeA = 0, activeB = 0;
  double voxelSize = 0.0;           ///< A's voxel size, the unit of the error
  std::string alignment;            ///< how B was read at A's voxels ("" for the same voxels)
  std::string nameA, nameB;         ///< the files, or what was baked for B
  /// One line when A and B look like fields of different scenes (they record different scenes, or their active
  /// voxels' boxes do not overlap): their differences then measure the scenes, not a method; also logged as a
  /// warning. Empty otherwise.
  std::string warning;
  /// A file of cascade levels (CascadeBake.h) against an anchor: each level compared on its own voxels, finest
  /// first; the fields above are level 0's.
  std::vector<FileComparison> levels;
  /// @brief The lines `rtsdf compare` prints (one block per level for cascades).
  std::string report() const;
};

/// @brief Compare as @a options say (metrics/FieldError.h's compareFields on the two level sets).
/// @details Each file's level set is read and checked by readLevelSet (class, float values, a uniform linear
///          transform, finite values; active tiles count as their voxels) and compared in its scene's frame (a file
///          written with --up z is turned back).
/// @throw SettingError on contradictory options or, naming "grid", when a file holds several candidate level
///        sets; Error naming the file when one cannot be read or holds no level set or a grid that is not one
///        (readLevelSet says why), when either level set has no active voxel, when they do not overlap or share no
///        defined voxel, and as bake() does for the anchor (its scene missing or bad); SettingError "anchor" when A
///        holds cascade levels and B is a file (levels are compared against an anchor); Interrupted when
///        @a control asks to stop.
FileComparison compare(const CompareOptions& options, const JobControl& control = {});

/// @brief compare() of two files.
FileComparison compareFiles(const std::filesystem::path& a, const std::filesystem::path& b);

} // namespace rtsdf
