#pragma once
/// @file ClosedPieces.h
/// @brief The closed pieces of a scene's meshes as the GPU sees them: each leaf-ordered triangle's piece, each closed
///        piece's box in its mesh's space, and, per frame, the pieces whose world boxes overlap another closed
///        piece's (of the same or another instance: the union holds across instances, moving ones included). The
///        refinement signs a point inside any of them as inside (piece_union.glsl); insideAnotherPieceCpu is its CPU
///        copy. The same rule as the exact field's (reference/PieceUnion.h), by ray parity instead of winding trees.
#include "bvh/Bvh.h"
#include "scene/Scene.h"
#include "sdf/scenebvh/PieceUnionParams.h"
#include "util/Bounds.h"

#include <cstdint>
#include <vector>

namespace rtsdf {

/// @brief Per mesh of a scene: which closed piece each of its leaf-ordered triangles lies on, and the pieces' boxes.
struct SceneClosedPieces {
  struct Box {
    std::uint32_t piece = 0;
    glm::vec3 lo{0.0f}, hi{0.0f}; ///< object space
  };
  std::vector<std::uint32_t> pieceOfLeaf;     ///< per leaf-ordered triangle (MeshBvhs): its piece, or kOpenPiece
  std::vector<std::vector<Box>> closedBoxes;  ///< per mesh: its closed pieces
  std::vector<std::uint32_t> leafBegin, leafEnd; ///< per mesh: its leaf-ordered triangles
  /// @brief Every instance's closed pieces together (the most a frame's overlap list can hold).
  std::size_t instancedClosedPieces(const Scene& scene) const;
};

/// @brief The pieces of every mesh of @a scene (meshPieces, on the repaired, welded triangles) in @a meshes' leaf
///        order.
SceneClosedPieces sceneClosedPieces(const Scene& scene, const MeshBvhs& meshes);

/// @brief The closed pieces of @a top's instances whose world boxes (their object boxes placed by the instance's
///        transform) touch or overlap another closed piece's: the only ones that can hold a point whose nearest
///        surface is another piece's (the exact field's rule, PieceUnion). Empty when none overlap.
/// @param reach where not empty (the BVH's frame), only the pieces whose world boxes meet it: the points the list is
///        asked about lie in it, and every piece costs each of them a test (overlaps are found among all pieces).
std::vector<gpu::shared::UnionPiece> overlappingClosedPieces(const Scene& scene, const SceneClosedPieces& pieces,
                                                             const InstanceBvh& top, const Bounds& reach = {});

/// @brief CPU copy of piece_union.glsl's insideAnotherPiece: whether @a p (the BVH's frame) lies inside a piece of
///        @a list other than piece @a skipPiece of instance slot @a skipSlot, by the majority of three rays' crossing
///        parities (every triangle of the piece tested: the same crossings as the GPU's walk).
bool insideAnotherPieceCpu(const Scene& scene, const MeshBvhs& meshes, const SceneClosedPieces& pieces,
                           const InstanceBvh& top, const std::vector<gpu::shared::UnionPiece>& list,
                           const glm::vec3& p, std::uint32_t skipSlot, std::uint32_t skipPiece);

/// @brief The refinement's union rule on the CPU for @a scene at one moment: the same bottom levels, pieces, top
///        level and overlap list as GpuSceneBvh builds, asked through insideAnotherPieceCpu.
class ClosedPieceUnionCpu {
public:
  /// @param frameOrigin the world point the positions asked about are measured from (as GpuSceneBvh's).
  ClosedPieceUnionCpu(const Scene& scene, double time, const glm::dvec3& frameOrigin = glm::dvec3(0.0));
  /// @brief Whether @a p lies inside a closed piece that overlaps another, other than the piece of triangle
  ///        @a triangle (the mesh's index) of instance @a instance (its nearest surface; kOpenPiece: skip none).
  bool insideAnother(const glm::vec3& p, std::uint32_t instance, std::uint32_t triangle) const;
  /// @brief Whether @a p lies inside any closed piece that overlaps another (rays mode: no nearest piece).
  bool insideAny(const glm::vec3& p) const { return insideAnother(p, kNoInstance, 0); }
  const std::vector<gpu::shared::UnionPiece>& list() const { return mList; }
  static constexpr std::uint32_t kNoInstance = 0xFFFFFFFFu;

private:
  const Scene& mScene;
  MeshBvhs mMeshes;
  SceneClosedPieces mPieces;
  InstanceBvh mTop;
  std::vector<gpu::shared::UnionPiece> mList;
  std::vector<std::vector<std::uint32_t>> mPieceOfTriangle; ///< per mesh, per triangle: its piece or kOpenPiece
};

} // namespace rtsdf
