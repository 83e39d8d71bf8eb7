#pragma once
/// @file GpuSceneBvh.h
/// @brief The scene's two-level BVH in GPU buffers: bottom levels uploaded once, the top level re-uploaded
///        whenever the instances move. Bound in this order by every shader that includes bvh_traverse.glsl.
#include "bvh/Bvh.h"
#include "gpu/Resources.h"
#include "scene/Scene.h"

#include <array>

namespace rtsdf {

class GpuSceneBvh {
public:
  /// @brief Build and upload the bottom levels of @a scene's meshes. @a scene must outlive this object.
  GpuSceneBvh(const gpu::VulkanContext& ctx, const Scene& scene);
  /// @brief Rebuild and upload the top level for the instance transforms at @a time seconds (no-op when the
  ///        time is the one last uploaded).
  void update(double time);
  /// @brief The six buffers bvh_traverse.glsl reads, in binding order: BLAS nodes, triangle corners, triangle
  ///        ids, TLAS nodes, TLAS slots, instances.
  std::array<const gpu::Buffer*, 6> buffers() const;
  const MeshBvhs& meshes() const { return mMeshes; }
  /// @brief The top level as last uploaded (for the CPU side of G-buffer normals and tests).
  const InstanceBvh& top() const { return mTop; }

private:
  const gpu::VulkanContext& mCtx;
  const Scene& mScene;
  MeshBvhs mMeshes;
  InstanceBvh mTop;
  double mTime = 0.0;
  bool mHaveTop = false;
  gpu::Buffer mBlasNodes, mCorners, mTriangleIds, mTlasNodes, mTlasSlots, mInstances;
};

} // namespace rtsdf
