#pragma once
/// @file GpuSceneBvh.h
/// @brief The scene on the GPU: its two-level BVH (bottom levels uploaded once, the top level re-sent whenever the
///        instances move) and the placement of every instance's triangles for VoxelizePass (the same mesh-space
///        corners and transforms). Every shader that includes bvh_traverse.glsl reads the BVH at the bindings
///        bvh/GpuBvhLayout.h names (kBvhBinding*).
#include "bvh/Bvh.h"
#include "gpu/Resources.h"
#include "bvh/GpuBvhLayout.h"
#include "scene/Scene.h"
#include "sdf/coarse/CoarseSdf.h"
#include "sdf/scenebvh/ClosedPieces.h"
#include "sdf/scenebvh/OpenPieces.h"

#include <array>
#include <optional>

namespace rtsdf {

class GpuSceneBvh {
public:
  /// @brief Build and upload the bottom levels of @a scene's meshes. @a scene must outlive this object.
  /// @param frameOrigin the world point the top level measures from (buildInstanceBvh): every query and answer
  ///        of a shader that traverses this BVH is in world - frameOrigin.
  GpuSceneBvh(const gpu::VulkanContext& ctx, const Scene& scene, const glm::dvec3& frameOrigin = glm::dvec3(0.0));
  /// @brief Rebuild and upload the top level for the instance transforms at @a time seconds (no-op when the
  ///        time is the one last uploaded), waiting for the upload.
  void update(double time);
  /// @brief The same recorded into @a cmd (vkCmdUpdateBuffer: no staging buffer, no wait), between barriers that
  ///        order it after the earlier passes that read the top level and before the later ones. The host's work
  ///        grows with the instances only.
  void recordUpdate(VkCommandBuffer cmd, double time);
  /// @brief The next update uploads whatever its time: a recorded update was never submitted (its frame threw).
  void forgetUpload() { mHaveTop = false; }
  /// @brief Every instance's triangles for VoxelizePass, placed by the transforms of the last update, measured from
  ///        seedOrigin().
  InstancedTriangles instancedTriangles() const;
  /// @brief The world point instancedTriangles() measures from: the frame origin unless setSeedOrigin() gave another.
  glm::dvec3 seedOrigin() const { return mSeedOrigin.value_or(mFrameOrigin); }
  /// @brief From the next update on, place the voxelization's triangles from @a origin (the world's origin for a
  ///        grid on the world's seed lattice: CoarseSdfSettings::seedLatticeCell); none: from the frame origin.
  void setSeedOrigin(const std::optional<glm::dvec3>& origin) {
    mSeedOrigin = origin;
    mHaveTop = false;
  }
  /// @brief The host copy of instancedTriangles()'s instances (for the CPU copy, placeInstanceCorners).
  const std::vector<gpu::shared::VoxelizeInstance>& voxelizeInstances() const { return mVoxelizeInstances; }
  /// @brief Put the six buffers bvh_traverse.glsl reads at their bindings (kBvhBinding*) of a pass's set.
  template <std::size_t N> void bindTo(std::array<gpu::Binding, N>& set) const {
    using namespace gpu::shared;
    static_assert(N >= kBvhBindingCount, "a BVH pass binds the six BVH buffers first");
    set[kBvhBindingBlasNodes] = &mBlasNodes;
    set[kBvhBindingCorners] = &mCorners;
    set[kBvhBindingTriangleIds] = &mTriangleIds;
    set[kBvhBindingTlasNodes] = &mTlasNodes;
    set[kBvhBindingTlasSlots] = &mTlasSlots;
    set[kBvhBindingInstances] = &mInstances;
  }
  /// @brief Per leaf-ordered triangle its closed piece, or kOpenPiece (SceneClosedPieces::pieceOfLeaf).
  const gpu::Buffer& pieceOf() const { return mPieceOf; }
  /// @brief The closed pieces that overlap another this frame (a uvec4 whose x is their count, then
  ///        gpu::shared::UnionPiece each; overlappingClosedPieces), re-sent with the top level.
  const gpu::Buffer& unionPieces() const { return mUnionPieces; }
  /// @brief The host copy of unionPieces()'s list as last uploaded (empty: no closed pieces overlap).
  const std::vector<gpu::shared::UnionPiece>& unionList() const { return mUnionList; }
  const SceneClosedPieces& closedPieces() const { return mPieces; }
  /// @brief Per leaf-ordered triangle its open-mesh flags (SceneOpenPieces::flagsOfLeaf: 0 on closed meshes).
  const gpu::Buffer& openFlags() const { return mOpenFlags; }
  /// @brief Per bottom-level node its triangles' dipole (SceneOpenPieces::windingNodes).
  const gpu::Buffer& windingNodes() const { return mWindingNodes; }
  const SceneOpenPieces& openPieces() const { return mOpen; }
  /// @brief Per instance (the scene's order) uvec2(its mesh's first leaf-ordered triangle, triangle count).
  const gpu::Buffer& instanceTriangles() const { return mInstanceTriangles; }
  const MeshBvhs& meshes() const { return mMeshes; }
  /// @brief The top level as last uploaded (for the CPU side of G-buffer normals and tests).
  const InstanceBvh& top() const { return mTop; }
  /// @brief The world point of the BVH's (0, 0, 0).
  const glm::dvec3& frameOrigin() const { return mFrameOrigin; }
  /// @brief From the next update on, list only the overlapping closed pieces whose boxes meet @a box (the BVH's frame;
  ///        empty: every one, the default): the points insideAnotherPiece is asked about lie in it (a pipeline's fine
  ///        grid), and each piece listed costs every one of them a test.
  void setUnionReach(const Bounds& box) {
    mUnionReach = box;
    mHaveTop = false;
  }
  /// @brief Measure from @a origin from the next update on (a pipeline whose grids scrolled): the bottom levels are
  ///        in their meshes' own space and stay; the top level is rebuilt by the next update, whatever its time.
  void setFrameOrigin(const glm::dvec3& origin) {
    mFrameOrigin = origin;
    mHaveTop = false;
  }

private:
  const gpu::VulkanContext& mCtx;
  const Scene& mScene;
  glm::dvec3 mFrameOrigin;
  std::optional<glm::dvec3> mSeedOrigin; ///< setSeedOrigin
  MeshBvhs mMeshes;
  InstanceBvh mTop;
  double mTime = 0.0;
  bool mHaveTop = false;
  std::uint32_t mTriangleCount = 0; ///< every instance's triangles together
  std::vector<gpu::shared::VoxelizeInstance> mVoxelizeInstances;
  SceneClosedPieces mPieces;
  SceneOpenPieces mOpen;
  std::vector<gpu::shared::UnionPiece> mUnionList;
  Bounds mUnionReach; ///< setUnionReach (empty: every piece)
  std::vector<glm::uvec4> mUnionUpload; ///< the header and the list as uploaded (kept alive for vkCmdUpdateBuffer)
  gpu::Buffer mBlasNodes, mCorners, mTriangleIds, mTlasNodes, mTlasSlots, mInstances, mVoxelizeBuf;
  gpu::Buffer mPieceOf, mUnionPieces, mOpenFlags, mWindingNodes, mInstanceTriangles;
};

} // namespace rtsdf
