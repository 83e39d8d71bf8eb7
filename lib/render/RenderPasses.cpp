#include "render/RenderPasses.h"

#include "util/Error.h"

namespace rtsdf {
using gpu::Buffer;

namespace {
glm::uvec3 imageGroups(int w, int h) { return {gpu::groupsFor(std::uint64_t(w), 8), gpu::groupsFor(std::uint64_t(h), 8), 1u}; }
} // namespace

void GpuGBuffer::reserve(const gpu::VulkanContext& ctx, int w, int h) {
  const VkDeviceSize bytes = VkDeviceSize(w) * VkDeviceSize(h) * sizeof(glm::vec4);
  gpu::reserve(ctx, position, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, Buffer::Memory::Device, "G-buffer positions");
  gpu::reserve(ctx, normal, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, Buffer::Memory::Device, "G-buffer normals");
  width = w;
  height = h;
}

GBufferPass::GBufferPass(const gpu::VulkanContext& ctx)
    : mPipeline(ctx, "gbuffer.comp", 8, sizeof(gpu::shared::CameraParams)) {}

void GBufferPass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const GpuSceneBvh& bvh,
                          const gpu::shared::CameraParams& camera, GpuGBuffer& out) const {
  if (out.width != camera.size.x || out.height != camera.size.y)
    throw Error("GBufferPass: the G-buffer is not reserved for the camera's image size");
  gpu::ProfileScope scope(profiler, cmd, kName);
  const auto b = bvh.buffers();
  mPipeline.dispatch(cmd, {b[0], b[1], b[2], b[3], b[4], b[5], &out.position, &out.normal}, &camera,
                     imageGroups(out.width, out.height));
  gpu::computeBarrier(cmd);
}

SdfShadowPass::SdfShadowPass(const gpu::VulkanContext& ctx)
    : mBufferPipeline(ctx, "sdf_shadow_buffer.comp", 5, sizeof(gpu::shared::SdfShadowParams)) {
  if (gpu::SampledVolume::supported(ctx))
    mTexturePipeline = gpu::ComputePipeline(
        ctx, "sdf_shadow.comp",
        {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
         VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
        sizeof(gpu::shared::SdfShadowParams));
}

void SdfShadowPass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const GpuGBuffer& gbuffer,
                            const Buffer& field, const gpu::SampledVolume* texture, const Buffer& lights,
                            const gpu::shared::SdfShadowParams& params, const Buffer& visibility) const {
  if (texture) {
    if (mTexturePipeline.name().empty())
      throw Error("SdfShadowPass: this device cannot sample the fine SDF as a filtered 3D texture");
    {
      gpu::ProfileScope scope(profiler, cmd, kCopyName);
      texture->copyFrom(cmd, field);
    }
    gpu::ProfileScope scope(profiler, cmd, kName);
    mTexturePipeline.dispatch(cmd, {&gbuffer.position, &gbuffer.normal, texture, &lights, &visibility}, &params,
                              imageGroups(gbuffer.width, gbuffer.height));
  } else {
    gpu::ProfileScope scope(profiler, cmd, kName);
    mBufferPipeline.dispatch(cmd, {&gbuffer.position, &gbuffer.normal, &field, &lights, &visibility}, &params,
                             imageGroups(gbuffer.width, gbuffer.height));
  }
  gpu::computeBarrier(cmd);
}

ShadowMapPass::ShadowMapPass(const gpu::VulkanContext& ctx)
    : mBuild(ctx, "shadow_map.comp", 8, sizeof(gpu::shared::ShadowMapParams)),
      mLookup(ctx, "shadow_lookup.comp", 6, sizeof(gpu::shared::ShadowMapParams)) {}

void ShadowMapPass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const GpuSceneBvh& bvh,
                            const GpuGBuffer& gbuffer, const Buffer& lights,
                            const std::vector<gpu::shared::ShadowMapParams>& maps, const Buffer& mapsBuffer,
                            const Buffer& depth, const Buffer& visibility) const {
  if (maps.empty()) return;
  const auto b = bvh.buffers();
  {
    gpu::ProfileScope scope(profiler, cmd, kBuildName);
    for (const gpu::shared::ShadowMapParams& m : maps) {
      const std::uint32_t n = std::uint32_t(m.info.x);
      const std::uint32_t faces = std::uint32_t(m.info.z) == gpu::shared::kLightSphere ? 6u : 1u;
      mBuild.dispatch(cmd, {b[0], b[1], b[2], b[3], b[4], b[5], &lights, &depth}, &m,
                      {gpu::groupsFor(n, 8), gpu::groupsFor(n, 8), faces});
    }
    gpu::computeBarrier(cmd);
  }
  gpu::ProfileScope scope(profiler, cmd, kLookupName);
  mLookup.dispatch(cmd, {&gbuffer.position, &gbuffer.normal, &depth, &lights, &mapsBuffer, &visibility}, &maps[0],
                   imageGroups(gbuffer.width, gbuffer.height));
  gpu::computeBarrier(cmd);
}

TaaPass::TaaPass(const gpu::VulkanContext& ctx) : mPipeline(ctx, "taa.comp", 2, sizeof(gpu::shared::TaaParams)) {}

void TaaPass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Buffer& current, const Buffer& history,
                      const gpu::shared::TaaParams& params) const {
  gpu::ProfileScope scope(profiler, cmd, kName);
  mPipeline.dispatch(cmd, {&current, &history}, &params, imageGroups(params.image.x, params.image.y));
  gpu::computeBarrier(cmd);
}

} // namespace rtsdf
