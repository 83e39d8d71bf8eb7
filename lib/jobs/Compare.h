#pragma once
/// @file Compare.h
/// @brief Two level-set .vdb files compared on the voxels active in both.
#include "metrics/FieldError.h"

#include <cstdint>
#include <filesystem>
#include <string>

namespace rtsdf {

/// @brief The comparison of two files.
struct FileComparison {
  FieldError error;                 ///< |A - B| in voxels and sign disagreement
  std::uint64_t activeA = 0, activeB = 0;
  double voxelSize = 0.0;
  /// @brief The lines `rtsdf compare` prints.
  std::string report(const std::filesystem::path& a, const std::filesystem::path& b) const;
};

/// @brief Read the level sets of @a a and @a b and compare them (metrics/FieldError.h).
/// @throw Error naming the files when either cannot be read or the grids cannot be compared.
FileComparison compareFiles(const std::filesystem::path& a, const std::filesystem::path& b);

} // namespace rtsdf
