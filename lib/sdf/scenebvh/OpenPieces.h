#pragma once
/// @file OpenPieces.h
/// @brief The open meshes of a scene as the GPU sees them: per leaf-ordered triangle whether its mesh is open, of
///        several pieces, and which of its edges and corners lie on the rim (the exact field's WindingRegions), and
///        per bottom-level BVH node its triangles' dipole. Where the exact field signs a point by the winding number
///        (windingSigns), the refinement does too (open_winding.glsl); OpenWindingCpu is its CPU copy.
#include "bvh/Bvh.h"
#include "scene/Scene.h"
#include "sdf/scenebvh/OpenPieceParams.h"

#include <cstdint>
#include <vector>

namespace rtsdf {

/// @brief Per leaf-ordered triangle its open-mesh flags, per bottom-level node its dipole.
struct SceneOpenPieces {
  std::vector<std::uint32_t> flagsOfLeaf;              ///< per leaf-ordered triangle (MeshBvhs): kOpen* flags
  std::vector<gpu::shared::WindingNode> windingNodes;  ///< per node of MeshBvhs::nodes
  bool any() const;                                    ///< whether some mesh is open
};

/// @brief The open-mesh flags of @a scene's meshes (open: not watertight, as the exact field's; rim and pieces as
///        WindingRegions and connectedPieces find them) and the dipoles of @a meshes' nodes.
SceneOpenPieces sceneOpenPieces(const Scene& scene, const MeshBvhs& meshes);

/// @brief The dipoles of @a meshes' bottom-level nodes: each node's area-weighted centroid, the ball about it holding
///        its box, and its triangles' summed vector area (object space).
std::vector<gpu::shared::WindingNode> windingNodes(const MeshBvhs& meshes);

/// @brief CPU copy of open_winding.glsl for @a scene at one moment: the same bottom levels, flags, dipoles and top
///        level as GpuSceneBvh builds.
class OpenWindingCpu {
public:
  /// @param frameOrigin the world point the positions asked about are measured from (as GpuSceneBvh's).
  OpenWindingCpu(const Scene& scene, double time, const glm::dvec3& frameOrigin = glm::dvec3(0.0));
  /// @brief Whether the winding number signs @a p, whose nearest surface is triangle @a triangle (the mesh's index)
  ///        of instance @a instance (windingSigns of its flags and the feature nearest to @a p).
  bool windingSigns(const glm::vec3& p, std::uint32_t instance, std::uint32_t triangle) const;
  /// @brief The winding number of instance @a instance's mesh at @a p (open_winding.glsl's walk: far nodes by their
  ///        dipoles, the rest triangle by triangle, in object space; near 1/2 a second walk with farther clusters;
  ///        still within kWindingExactBand of 1/2, every triangle: WindingExactPass).
  float windingNumber(const glm::vec3& p, std::uint32_t instance) const;
  /// @brief The same summing every triangle's solid angle (no dipole).
  float windingNumberExact(const glm::vec3& p, std::uint32_t instance) const;
  const SceneOpenPieces& pieces() const { return mPieces; }

private:
  /// One walk at object-space @a po: clusters farther than @a ratio radii by their dipoles.
  float windingWalk(const glm::vec3& po, std::uint32_t instance, float ratio) const;

  const Scene& mScene;
  MeshBvhs mMeshes;
  SceneOpenPieces mPieces;
  InstanceBvh mTop;
  std::vector<std::vector<std::uint32_t>> mLeafOfTriangle; ///< per mesh, per triangle: its leaf-ordered index
};

} // namespace rtsdf
