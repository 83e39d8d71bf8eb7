#include "render/gbuffer/GBufferPass.h"

#include "util/Error.h"

#include <array>

namespace rtsdf {
using gpu::Buffer;
using namespace gpu::shared;

void GpuGBuffer::reserve(const gpu::VulkanContext& ctx, int w, int h) {
  const VkDeviceSize bytes = VkDeviceSize(w) * VkDeviceSize(h) * sizeof(glm::vec4);
  gpu::reserve(ctx, position, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, Buffer::Memory::Device, "G-buffer positions");
  gpu::reserve(ctx, normal, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, Buffer::Memory::Device, "G-buffer normals");
  width = w;
  height = h;
}

void GBufferPass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                          const Params& camera) const {
  const GpuGBuffer& g = out.gbuffer;
  if (g.width != camera.size.x || g.height != camera.size.y)
    throw Error("GBufferPass: the G-buffer is not reserved for the camera's image size");
  gpu::ProfileScope scope(profiler, cmd, kName);
  std::array<gpu::Binding, kGBufferBindingCount> b;
  in.bvh.bindTo(b);
  b[kGBufferBindingPositions] = &g.position;
  b[kGBufferBindingNormals] = &g.normal;
  mPipeline.dispatch(cmd, b, &camera, imageGroups(g.width, g.height));
  gpu::computeBarrier(cmd);
}

} // namespace rtsdf
