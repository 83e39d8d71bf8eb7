#pragma once
/// @file CascadeLayout.h
/// @brief Where the cascade levels lie for a camera position (CascadeLayout): K boxes of the same coarse and fine
///        voxel counts, level i's voxels 2^i times level 0's, each centred on the camera and snapped to its own
///        coarse voxel, so a level moves by whole coarse voxels and its voxels never swim. Pure: no GPU, no scene.
#include "grid/GridSpec.h"
#include "sdf/PipelineSettings.h"
#include "util/Bounds.h"

#include <glm/glm.hpp>

#include <utility>
#include <vector>

namespace rtsdf {

/// @brief The shape every level shares: counts and level 0's size.
struct CascadeShape {
  int levels = 1;            ///< K
  int coarseRes = 128;       ///< coarse voxels along each axis of every level
  int fineRes = 256;         ///< fine voxels along each axis of every level
  double levelZeroExtent = 1.0; ///< level 0's side in scene units (level i's: 2^i times it)
  /// Coarse voxels a level moves by at a time: its centre snaps to multiples of this many coarse voxels. Whole bricks
  /// of the fine grid (levelMoveCells), so that a moved level scrolls its buffers (SdfPipeline::scroll).
  int moveCells = 1;
  /// @brief Level @a i's coarse voxel: levelZeroExtent / coarseRes * 2^i.
  double coarseVoxel(int i) const;
  /// @brief Level @a i's fine voxel: levelZeroExtent / fineRes * 2^i.
  double fineVoxel(int i) const;
  /// @brief The largest look-ahead along each axis (CascadeLayout::around) for which every level, snapped, still lies
  ///        a fine voxel of the next coarser level inside that level's faces (the march blends into it there):
  ///        E / 2 - 3/2 moveCells c_0 - 2 f_0 (E: level 0's side, c_0 and f_0 its voxels; 3/2 c_0 less for an odd
  ///        coarseRes), or 0 where that is negative.
  double maxLookAhead() const;
};

/// @brief The fewest coarse voxels that are whole bricks (RTSDF_BRICK fine voxels) of a level of @a coarseRes and
///        @a fineRes voxels a side: 8 / gcd(fineRes / coarseRes, 8), or 1 when fine voxels straddle coarse ones (a
///        level that moves is then rebuilt).
int levelMoveCells(int coarseRes, int fineRes);

/// @brief The shape @a s asks for over a scene of @a sceneBounds: s.cascades levels of s.coarseRes and s.fineRes
///        voxels; level 0's side s.cascadeExtent, or by default the scene's longest side / 2^(K - 1), so that the
///        outermost level spans the scene; levels move by levelMoveCells coarse voxels.
/// @throw SettingError as PipelineSettings::validate; Error when @a sceneBounds is empty and no extent is given.
CascadeShape cascadeShapeFor(const Bounds& sceneBounds, const PipelineSettings& s);

/// @brief The same for levels centred on @a centre (the camera): by default level 0's side is such that the
///        outermost level, snapped around @a centre, holds all of @a sceneBounds (twice the farthest distance from
///        @a centre to a face of the bounds, along an axis, plus half a move and half a coarse voxel each side for
///        the snapping).
/// @throw as the overload above.
CascadeShape cascadeShapeFor(const Bounds& sceneBounds, const glm::dvec3& centre, const PipelineSettings& s);

/// @brief One level: its coarse and fine grids (the same corner; the coarse covers the fine exactly).
struct CascadeLevel {
  int index = 0;
  GridSpec coarse, fine;
  glm::i64vec3 centreCell{0}; ///< the camera's nearest lattice point, in level coarse voxels from the origin (a
                              ///< multiple of CascadeShape::moveCells)
  /// @brief The level's box in world units.
  Bounds box() const;
  /// @brief The grids as SdfPipeline takes them (coarse, fine).
  std::pair<GridSpec, GridSpec> grids() const { return {coarse, fine}; }
};

/// @brief The levels around one camera position.
struct CascadeLayout {
  CascadeShape shape;
  glm::dvec3 camera{0.0};
  glm::dvec3 lookAhead{0.0}; ///< level i < K - 1 is centred on camera + lookAhead 2^i, the outermost on the camera
                             ///< (as clamped by around())
  std::vector<CascadeLevel> levels; ///< finest first
  /// @brief The layout for @a camera: level i's coarse voxel c_i, its centre the point nearest the camera of the
  ///        lattice of moveCells coarse voxels (m c_i round(camera / (m c_i))), its corner coarseRes / 2 coarse voxels
  ///        below that.
  /// @param lookAhead where given, level i below the outermost is centred on camera + lookAhead 2^i instead (levels
  ///        that reach further along the view than behind it), each component clamped to
  ///        CascadeShape::maxLookAhead() so that the levels nest; the outermost level stays on the camera.
  static CascadeLayout around(const glm::dvec3& camera, const CascadeShape& shape,
                              const glm::dvec3& lookAhead = glm::dvec3(0.0));
  /// @brief The finest level whose box holds @a p at least @a margin (scene units) inside its faces, or -1.
  int finestHolding(const glm::dvec3& p, double margin = 0.0) const;
  /// @brief Per level, the whole coarse voxels the level moved from @a before to this layout (a multiple of
  ///        moveCells: what the level scrolls by).
  std::vector<glm::i64vec3> shiftSince(const CascadeLayout& before) const;
};

} // namespace rtsdf
