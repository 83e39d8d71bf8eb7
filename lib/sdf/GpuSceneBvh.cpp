#include "sdf/GpuSceneBvh.h"

namespace rtsdf {

namespace {
constexpr VkBufferUsageFlags kStorage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
} // namespace

GpuSceneBvh::GpuSceneBvh(const gpu::VulkanContext& ctx, const Scene& scene, const glm::dvec3& frameOrigin)
    : mCtx(ctx), mScene(scene), mFrameOrigin(frameOrigin), mMeshes(buildMeshBvhs(scene)) {
  gpu::reserveAndUpload(ctx, mBlasNodes, mMeshes.nodes.data(), mMeshes.nodes.size() * sizeof(gpu::shared::BvhNode),
                        kStorage, "BLAS nodes");
  gpu::reserveAndUpload(ctx, mCorners, mMeshes.corners.data(), mMeshes.corners.size() * sizeof(glm::vec4), kStorage,
                        "BLAS triangles");
  gpu::reserveAndUpload(ctx, mTriangleIds, mMeshes.triangleIds.data(), mMeshes.triangleIds.size() * 4, kStorage,
                        "triangle ids");
}

void GpuSceneBvh::update(double time) {
  if (mHaveTop && time == mTime) return;
  mTop = buildInstanceBvh(mScene, mMeshes, time, mFrameOrigin);
  gpu::reserveAndUpload(mCtx, mTlasNodes, mTop.nodes.data(), mTop.nodes.size() * sizeof(gpu::shared::BvhNode),
                        kStorage, "TLAS nodes");
  gpu::reserveAndUpload(mCtx, mTlasSlots, mTop.slots.data(), mTop.slots.size() * 4, kStorage, "TLAS slots");
  gpu::reserveAndUpload(mCtx, mInstances, mTop.instances.data(),
                        mTop.instances.size() * sizeof(gpu::shared::BvhInstance), kStorage, "instances");
  mTime = time;
  mHaveTop = true;
}

} // namespace rtsdf
