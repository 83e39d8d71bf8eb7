#include "sdf/GpuSceneBvh.h"

namespace rtsdf {
using gpu::Buffer;

namespace {
/// Grow @a b to @a bytes if needed, then upload.
void uploadGrow(const gpu::VulkanContext& ctx, Buffer& b, const void* data, std::size_t bytes, const char* name) {
  gpu::reserve(ctx, b, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, Buffer::Memory::Device, name);
  upload(ctx, b, data, bytes);
}
} // namespace

GpuSceneBvh::GpuSceneBvh(const gpu::VulkanContext& ctx, const Scene& scene)
    : mCtx(ctx), mScene(scene), mMeshes(buildMeshBvhs(scene)) {
  uploadGrow(ctx, mBlasNodes, mMeshes.nodes.data(), mMeshes.nodes.size() * sizeof(gpu::shared::BvhNode), "BLAS nodes");
  uploadGrow(ctx, mCorners, mMeshes.corners.data(), mMeshes.corners.size() * sizeof(glm::vec4), "BLAS triangles");
  uploadGrow(ctx, mTriangleIds, mMeshes.triangleIds.data(), mMeshes.triangleIds.size() * 4, "triangle ids");
}

void GpuSceneBvh::update(double time) {
  if (mHaveTop && time == mTime) return;
  mTop = buildInstanceBvh(mScene, mMeshes, time);
  uploadGrow(mCtx, mTlasNodes, mTop.nodes.data(), mTop.nodes.size() * sizeof(gpu::shared::BvhNode), "TLAS nodes");
  uploadGrow(mCtx, mTlasSlots, mTop.slots.data(), mTop.slots.size() * 4, "TLAS slots");
  uploadGrow(mCtx, mInstances, mTop.instances.data(), mTop.instances.size() * sizeof(gpu::shared::BvhInstance),
             "instances");
  mTime = time;
  mHaveTop = true;
}

} // namespace rtsdf
