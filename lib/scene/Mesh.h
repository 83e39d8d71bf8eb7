#pragma once
/// @file Mesh.h
/// @brief Indexed triangle meshes, their validation and their topology.
#include "util/Bounds.h"

#include <glm/glm.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace rtsdf {

/// @brief An indexed triangle mesh in its own (object) space.
struct Mesh {
  std::string name;                  ///< name used in messages (scene key or file stem)
  std::string source;                ///< file it came from, or "<box>" for built-in shapes
  std::vector<glm::vec3> positions;
  std::vector<glm::uvec3> triangles; ///< counter-clockwise seen from outside
};

/// @brief The bounds of @a mesh's positions in its own space (empty for a mesh without positions).
Bounds positionBounds(const Mesh& mesh);

/// @brief What orientation repair (repairOrientation, scene/MeshRepair.h) changed in a mesh.
struct OrientationRepair {
  std::size_t reorientedTriangles = 0; ///< triangles whose corner order was reversed
  std::size_t piecesTurnedOutward = 0; ///< closed pieces that faced inward (negative volume) and were turned
  std::size_t pieces = 0;              ///< connected pieces (joined by edges two triangles share)
  std::size_t closedPieces = 0;        ///< pieces without a boundary or non-manifold edge
};

/// @brief What validation found and did to a mesh.
struct MeshReport {
  std::size_t inputTriangles = 0;
  std::size_t inputVertices = 0;
  std::size_t degenerateDropped = 0; ///< zero-area triangles (repeated index, collinear points, !hasFloatArea)
  std::size_t weldedVertices = 0;    ///< vertices merged because they had identical positions
  std::size_t triangles = 0;         ///< kept
  std::size_t boundaryEdges = 0;     ///< edges used by one triangle (open mesh)
  std::size_t nonManifoldEdges = 0;  ///< edges used by more than two triangles
  std::size_t misorientedEdges = 0;  ///< edges whose two triangles traverse it in the same direction (after repair)
  OrientationRepair orientation;     ///< what the orientation repair changed
  /// @brief Closed, manifold and consistently oriented: the pseudo-normal sign is exact for it.
  bool watertight() const { return boundaryEdges == 0 && nonManifoldEdges == 0 && misorientedEdges == 0; }
};

/// @brief Whether triangle (a, b, c) has an area float arithmetic can use: its float normal's squared length
///        is finite and a normal number (>= FLT_MIN). Thinner triangles (a sliver 1e-20 high) are degenerate:
///        their barycentrics are all rounding, a GPU flushing denormals sees zero area, and Embree never hits
///        them. validateMesh and buildSceneGeometry use this one test, so the rasterized coarse SDF and the
///        BVH see the same triangles.
bool hasFloatArea(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c);

/// @brief The largest vertex coordinate magnitude rtsdf accepts, in mesh and in scene units. Beyond it a
///        triangle's squared normal overflows float (its area test, its pseudo-normal), and a float holds
///        the position only to 64 units or worse: scale such a model down.
inline constexpr double kMaxCoordinate = 1e9;

/// @brief Validate a mesh in place: errors for what cannot be repaired, counted drops for what can.
/// @param mesh the mesh; on return it holds only finite, non-degenerate triangles over welded vertices, oriented
///        by solid (repairOrientation: consistent per piece, closed pieces outward).
/// @return the counts of what was found and dropped, and the mesh's topology.
/// @throw Error naming the mesh's source file and object when a vertex coordinate is NaN or Inf or beyond
///        ±kMaxCoordinate, when a
///        triangle index is out of range, or when no triangle is left (empty mesh).
/// @note Zero-area triangles (repeated indices, collinear points, or too thin for float: hasFloatArea) are
///       dropped and counted: Embree never hits them, and they carry no surface.
MeshReport validateMesh(Mesh& mesh);

/// @brief Edge topology of a mesh (boundary, non-manifold and mis-oriented edge counts).
void analyzeTopology(const Mesh& mesh, MeshReport& report);

/// @brief A closed axis-aligned box mesh (12 triangles, outward facing) centred at the origin.
/// @param size full extents along x, y, z; each must be positive and finite.
Mesh makeBoxMesh(const glm::vec3& size, std::string name = "box");

/// @brief A closed icosphere mesh (outward facing) centred at the origin: an icosahedron whose triangles are
///        split in four @a subdivisions times, every new vertex pushed out onto the sphere.
/// @param radius the radius of the vertices; must be positive and finite.
/// @param subdivisions 0 (the icosahedron) .. 7; the mesh has 20 * 4^subdivisions triangles and
///        10 * 4^subdivisions + 2 vertices.
/// @note The triangles lie inside the sphere: the largest gap (at face centres) shrinks about 4x with every
///       subdivision (0.0011 x radius at 4, 0.00007 x radius at 6).
/// @throw Error when the radius is not positive and finite or the subdivisions are out of range.
Mesh makeSphereMesh(float radius, int subdivisions, std::string name = "sphere");

/// @brief A closed torus (outward facing) around the y axis, centred at the origin: major radius @a R, minor
///        radius @a r, @a rings x @a sides quads, each split in two. No checks: for generated test and benchmark
///        meshes.
Mesh makeTorusMesh(float R, float r, int rings, int sides, std::string name = "torus");

/// @brief @a mesh with every triangle split in four at its edge midpoints, @a levels times: the same surface
///        with 4^levels times the triangles (how the benchmarks make a large mesh from a bundled one).
/// @throw Error when @a levels is outside [0, 6].
Mesh subdivideMesh(const Mesh& mesh, int levels);

/// @brief @a mesh with @a holes holes cut in it, reproducibly: the triangles with a vertex within @a radius of
///        a hole centre are dropped; the centres are @a holes vertices evenly spaced through the vertex list.
///        Unused vertices are kept.
Mesh cutHoles(const Mesh& mesh, int holes, float radius);

} // namespace rtsdf
