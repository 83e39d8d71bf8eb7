#pragma once
/// @file MeshJob.h
/// @brief The surface of a .vdb level set as a triangle mesh file: OpenVDB's volumeToMesh at an isovalue, written
///        by assimp's exporter (OBJ, PLY or STL, by the output's extension) atomically.
#include "util/Bounds.h"
#include "util/JobControl.h"
#include "util/Knobs.h"

#include <cstdint>
#include <filesystem>
#include <string>

namespace rtsdf {

/// @brief What to mesh and where to write it.
struct MeshOptions {
  std::filesystem::path input;  ///< the .vdb whose level set is meshed
  std::filesystem::path output; ///< .obj, .ply or .stl (the extension picks the format)
  double isovalue = 0.0;        ///< the level meshed, in scene units: 0 is the surface itself
  double adaptivity = 0.0;      ///< 0: every voxel's polygon; up to 1: flat regions merged into fewer polygons
  std::string grid;             ///< the grid to read (readLevelSet); empty: "surface" or the only level set
  /// @throw SettingError naming the setting out of range (knob table); Error naming the output when its extension
  ///        is not one of .obj, .ply, .stl.
  void validate() const;
};

/// @brief The knobs of a mesh (docs/settings.md).
template <> struct KnobTable<MeshOptions> {
  using S = MeshOptions;
  static constexpr auto kKnobs = std::make_tuple(
      knob("isovalue", &S::isovalue, "--isovalue", KnobRange::finite(),
           "The level meshed, in scene units (0: the surface; a level set's values are distances)"),
      knob("adaptivity", &S::adaptivity, "--adaptivity", KnobRange::closed(0.0, 1.0),
           "0: one polygon per surface voxel; up to 1: flat regions merged into fewer, larger polygons"),
      knob("grid", &S::grid, "--grid", KnobRange::any(),
           "The grid to mesh (default: the one named 'surface' or the only level set)"));
};

/// @brief A written mesh.
struct MeshResult {
  std::uint64_t vertices = 0, triangles = 0;
  Bounds bounds;            ///< of the vertices, in the grid's world space (turned when the file is Z-up)
  double voxelSize = 0.0;   ///< the level set's
  std::string upAxis = "y"; ///< the file's up axis (rtsdf:up): the mesh stands as the grid does
  std::string report(const MeshOptions& options) const; ///< the lines `rtsdf mesh` prints
};

/// @brief Mesh the level set of options.input at options.isovalue and write it to options.output atomically.
/// @details The triangles face outward (counter-clockwise seen from outside: OpenVDB's polygons wind the other
///          way and are reversed); quads are split in two.
/// @throw SettingError as MeshOptions::validate; Error as readLevelSet (naming the file and what is wrong), when the
///        isovalue crosses no voxel (an empty mesh), when the output cannot be written (nothing is left behind) or
///        would replace the input; Interrupted when @a control asks to stop before writing.
MeshResult meshLevelSet(const MeshOptions& options, const JobControl& control = {});

} // namespace rtsdf
