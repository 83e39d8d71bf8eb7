#pragma once
/// @file ExactSdf.h
/// @brief The exact signed distance field of a scene: the CPU reference every other method is measured
///        against. Distance by Embree 3 closest-point queries (rtcPointQuery), in parallel with TBB.
#include "grid/GridSpec.h"
#include "scene/SceneGeometry.h"
#include "util/EnumNames.h"
#include "util/JobControl.h"

#include <openvdb/openvdb.h>

#include <memory>

namespace rtsdf {

/// @brief How the inside/outside sign of a point is decided.
enum class SignMethod {
  /// Pseudo-normal for points nearest to a watertight mesh. For an open mesh, the winding number where the
  /// closest feature touches the rim of its piece (a boundary, non-manifold or mis-oriented edge, or a vertex on
  /// one or where two fans of faces meet), and the pseudo-normal elsewhere, where it is the exact local side.
  /// On an open mesh of several pieces, point queries use the winding number everywhere, while bakes use it also
  /// near other pieces and rims and where it is a quarter or more off the pseudo-normal's side (WindingRegions,
  /// exactSignedDistance). Exact for closed meshes, robust for open ones, and fast (the default).
  Auto,
  /// Angle-weighted pseudo-normal at the closest feature (Baerentzen and Aanaes 2005): exact for closed,
  /// consistently oriented meshes; arbitrary near the holes of open ones.
  PseudoNormal,
  /// Generalized winding number of the nearest mesh, w >= 1/2 is inside (Jacobson et al. 2013, evaluated
  /// hierarchically as in Barill et al. 2018): robust everywhere, slower.
  WindingNumber
};

template <> struct EnumNames<SignMethod> {
  static constexpr const char* kSetting = "sign method";
  static constexpr std::pair<const char*, SignMethod> kValues[] = {
      {"auto", SignMethod::Auto}, {"pseudonormal", SignMethod::PseudoNormal}, {"winding", SignMethod::WindingNumber}};
};

/// @brief Exact signed distance queries against a scene's world-space triangles.
/// @note Points inside a mesh are negative. Closed pieces (of one mesh or of several) that pass through each
///       other are a union: a point inside any of them is inside, whichever surface is nearest.
class ExactDistanceField {
public:
  /// @throw Error when the scene has no triangles.
  /// @note @a geometry is referenced, not copied: it must outlive the field (a temporary leaves the queries
  ///       reading freed triangles).
  explicit ExactDistanceField(const SceneGeometry& geometry, SignMethod sign = SignMethod::Auto);
  ~ExactDistanceField();
  ExactDistanceField(const ExactDistanceField&) = delete;
  ExactDistanceField& operator=(const ExactDistanceField&) = delete;

  /// @brief Closest point query within @a maxDistance; returns false when no triangle is that close.
  struct Hit {
    float distance = 0.0f;   ///< unsigned
    glm::vec3 point{0.0f};   ///< closest point on the surface
    unsigned mesh = 0, triangle = 0;
    int feature = 0;         ///< TriangleFeature of the closest point
  };
  bool closest(const glm::vec3& p, float maxDistance, Hit& hit) const;

  /// @brief True when @a p is inside, given the closest-point query @a hit for it: inside the piece of the mesh
  ///        @a hit lies on (insideNearestPiece), or inside any other closed piece (parts that pass through each
  ///        other are a union; meshes are oriented by solid at load, validateMesh).
  bool inside(const glm::vec3& p, const Hit& hit) const;

  /// @brief inside() with the rule of the nearest surface given: its mesh's winding number when @a winding (and the
  ///        mesh has one), else the pseudo-normal at @a hit's feature.
  bool inside(const glm::vec3& p, const Hit& hit, bool winding) const;

  /// @brief The sign rule of the nearest surface alone: the pseudo-normal at @a hit's feature, or the winding number
  ///        of @a hit's mesh (usesWinding).
  bool insideNearestPiece(const glm::vec3& p, const Hit& hit) const;
  bool insideNearestPiece(const glm::vec3& p, const Hit& hit, bool winding) const;

  /// @brief Whether inside() decides @a p, whose closest-point query is @a hit, by the winding number (the rest by
  ///        the pseudo-normal): always for meshes signed by it and for open meshes of several pieces (a point
  ///        alone has no cell to check), for an open mesh of one piece where its rim needs it (WindingRegions).
  bool usesWinding(const glm::vec3& p, const Hit& hit) const;

  /// @brief The per-voxel part of a bake's rule (exactSignedDistance): usesWinding, except that for open meshes of
  ///        several pieces only where WindingRegions needs it; the bake adds its cell and sub-block checks
  ///        (touchesRim, pseudoNormalHoldsNear).
  bool usesWindingInBand(const glm::vec3& p, const Hit& hit) const;

  /// @brief Whether @a mesh is open, of several pieces, and signed under SignMethod::Auto (by the winding number only
  ///        where needed). Bakes check more of such a mesh's points (pseudoNormalHoldsNear, touchesRim) than
  ///        usesWinding does: its holes and its other pieces may put the winding number a half off the nearest
  ///        surface's side. (One piece is left to usesWinding: its holes alone change no sign within 0.01%.)
  bool hasSeveralPieces(unsigned mesh) const;

  /// @brief Whether the winding number at @a c is within kPseudoNormalMargin of the side the pseudo-normal gives
  ///        @a c (@a hit: c's closest-point query): then the points near @a c (a few voxels) that usesWinding leaves
  ///        to the pseudo-normal, nearest to the same piece, have the winding number's sign. Farther from it the
  ///        holes and the other pieces of an open mesh may make the winding number a half or more off.
  bool pseudoNormalHoldsNear(const glm::vec3& c, const Hit& hit) const;

  /// @brief Whether @a a and @a b lie on the same piece of the same mesh (any piece of a mesh without regions).
  bool samePiece(const Hit& a, const Hit& b) const;

  /// @brief Whether triangle @a triangle of @a mesh, a mesh with winding regions, has an edge or a corner on the
  ///        rim: near it the winding number turns by a half within a few voxels.
  bool touchesRim(unsigned mesh, unsigned triangle) const;

  /// How far the winding number may be from the pseudo-normal's side for pseudoNormalHoldsNear.
  static constexpr double kPseudoNormalMargin = 0.25;

  /// @brief The signed distance at @a p (negative inside); +inf for an empty scene.
  float signedDistance(const glm::vec3& p) const;

  /// @brief Nearest hit of the ray @a origin + t @a direction, t in (0, tmax), by Embree's rtcIntersect1.
  /// @param t receives the hit distance (in units of @a direction); @param front whether the ray arrived on
  ///        the side the triangle's counter-clockwise normal points to.
  bool intersect(const glm::vec3& origin, const glm::vec3& direction, float tmax, float& t, bool& front) const;

  /// @brief Every triangle within @a radius of @a p, appended as (mesh << 32 | triangle).
  void collect(const glm::vec3& p, float radius, std::vector<std::uint64_t>& out) const;

  struct Impl;
  const Impl& impl() const { return *mImpl; }

private:
  std::unique_ptr<Impl> mImpl;
};

/// @brief Options of exactSignedDistance.
struct ExactSdfOptions {
  /// Half-width of the narrow band in world units: voxels with |d| <= band are active. A band that is
  /// not finite (or at least the grid's diagonal) gives the full-domain field: every voxel active.
  double band = 0.1;
  SignMethod sign = SignMethod::Auto;
  bool progress = true; ///< show a progress bar on stderr
  /// Progress ("exact SDF", blocks done of all, about every 1%) and stop requests, polled before each 8^3 block
  /// from the worker threads (the control must be thread-safe); a stop throws Interrupted. Null: neither.
  const JobControl* control = nullptr;
  /// Bake only the 8^3 blocks whose first voxel lies in this box of index space (one tile of a bake split
  /// across workers, jobs/TileBake.h); empty (the default): every block.
  openvdb::CoordBBox window;
};

/// @brief Counters of one exactSignedDistance run.
struct ExactSdfStats {
  std::uint64_t activeVoxels = 0;
  std::uint64_t evaluatedVoxels = 0;  ///< voxels whose distance was computed
  std::uint64_t windingQueries = 0;   ///< voxels signed by the winding number
  double seconds = 0.0;
};

/// @brief The exact signed distance of @a geometry sampled at the voxel centres of @a spec, as a sparse
///        OpenVDB level set (background = band; in full-domain mode every voxel is active).
/// @note Works block by block on OpenVDB's 8^3 leaves: one closest-point query per block culls blocks
///       farther than the band, then the triangles that can be nearest to any voxel of the block are
///       gathered once and tested per voxel (two levels: 8^3 and 4^3).
/// @throw Interrupted when options.control asks to stop.
openvdb::FloatGrid::Ptr exactSignedDistance(const SceneGeometry& geometry, const GridSpec& spec,
                                            const ExactSdfOptions& options, ExactSdfStats* stats = nullptr);

} // namespace rtsdf
