#include "render/RenderPasses.h"

#include "util/Error.h"

#include <fmt/format.h>

#include <array>

namespace rtsdf {
using gpu::Buffer;
using namespace gpu::shared;

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

void ContactShadowPass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                                const Params& params) const {
  const GpuGBuffer& g = in.gbuffer;
  if (params.rays == 0u) throw Error("ContactShadowPass: no rays to trace");
  if (g.width != params.image.x || g.height != params.image.y)
    throw Error("ContactShadowPass: the image size is not the G-buffer's");
  gpu::ProfileScope scope(profiler, cmd, kName);
  std::array<gpu::Binding, kContactShadowBindingCount> b;
  in.bvh.bindTo(b);
  b[kContactShadowBindingPositions] = &g.position;
  b[kContactShadowBindingNormals] = &g.normal;
  b[kContactShadowBindingLights] = &in.lights;
  b[kContactShadowBindingVisibility] = &out.visibility;
  mPipeline.dispatch(cmd, b, &params, imageGroups(g.width, g.height));
  gpu::computeBarrier(cmd);
}

namespace {
std::vector<VkDescriptorType> sdfShadowTextureBindings() {
  std::vector<VkDescriptorType> types(kSdfShadowBindingCount, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
  types[kSdfShadowBindingField] = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  return types;
}
} // namespace

VolumeFillPass::VolumeFillPass(const gpu::VulkanContext& ctx) {
  if (gpu::SampledVolume::storageSupported(ctx)) {
    std::vector<VkDescriptorType> types(kVolumeFillBindingCount, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
    types[kVolumeFillBindingTexture] = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    mCompute = gpu::ComputePipeline(ctx, "volume_fill.comp", types, sizeof(glm::ivec4));
  }
}

VolumeFillPass::Method VolumeFillPass::defaultMethod(const gpu::VulkanContext& ctx) {
  return gpu::SampledVolume::storageSupported(ctx) && ctx.info().typeName != "cpu" ? Method::Compute
                                                                                   : Method::Transfer;
}

void VolumeFillPass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                             Method method) const {
  gpu::ProfileScope scope(profiler, cmd, kName);
  if (method == Method::Transfer) return out.texture.copyFrom(cmd, in.field);
  if (mCompute.name().empty())
    throw Error("VolumeFillPass: this device cannot store to R32_SFLOAT 3D textures (use the transfer method)");
  const glm::uvec3 d = out.texture.dims();
  if (in.field.size() < VkDeviceSize(d.x) * d.y * d.z * sizeof(float))
    throw Error(fmt::format("VolumeFillPass: buffer '{}' holds {} bytes, texture '{}' needs {}", in.field.name(),
                            in.field.size(), out.texture.name(), VkDeviceSize(d.x) * d.y * d.z * sizeof(float)));
  out.texture.beginShaderWrite(cmd);
  const glm::ivec4 dims(glm::ivec3(d), 0);
  std::array<gpu::Binding, kVolumeFillBindingCount> b;
  b[kVolumeFillBindingField] = &in.field;
  b[kVolumeFillBindingTexture] = &out.texture;
  mCompute.dispatch(cmd, b, &dims, {gpu::groupsFor(d.x, 64), d.y, d.z});
  out.texture.endShaderWrite(cmd);
}

SdfShadowPass::SdfShadowPass(const gpu::VulkanContext& ctx, bool umbra)
    : mBufferPipeline(ctx, umbra ? "sdf_shadow_umbra_buffer.comp" : "sdf_shadow_buffer.comp", kSdfShadowBindingCount,
                      sizeof(SdfShadowParams)),
      mBrickPipeline(ctx, umbra ? "sdf_shadow_umbra_bricks.comp" : "sdf_shadow_bricks.comp",
                     kSdfShadowBindingBrickCount, sizeof(SdfShadowParams)),
      mFill(ctx), mFillMethod(VolumeFillPass::defaultMethod(ctx)), mUmbra(umbra) {
  if (gpu::SampledVolume::supported(ctx))
    mTexturePipeline = gpu::ComputePipeline(ctx, umbra ? "sdf_shadow_umbra.comp" : "sdf_shadow.comp",
                                            sdfShadowTextureBindings(), sizeof(SdfShadowParams));
}

void SdfShadowPass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                            const Params& params) const {
  std::array<gpu::Binding, kSdfShadowBindingCount> b;
  b[kSdfShadowBindingPositions] = &in.gbuffer.position;
  b[kSdfShadowBindingNormals] = &in.gbuffer.normal;
  b[kSdfShadowBindingLights] = &in.lights;
  b[kSdfShadowBindingVisibility] = &out.visibility;
  const glm::uvec3 groups = imageGroups(in.gbuffer.width, in.gbuffer.height);
  if ((params.penumbra == gpu::shared::kPenumbraUmbra) != mUmbra)
    throw Error(fmt::format("SdfShadowPass: built for the {} estimates, asked for penumbra estimate {}",
                            mUmbra ? "umbra" : "single-march", params.penumbra));
  if (in.texture) {
    if (mTexturePipeline.name().empty())
      throw Error("SdfShadowPass: this device cannot sample the fine SDF as a filtered 3D texture");
    mFill.execute(cmd, profiler, {in.field}, {*in.texture}, mFillMethod);
    gpu::ProfileScope scope(profiler, cmd, kName);
    b[kSdfShadowBindingField] = in.texture;
    mTexturePipeline.dispatch(cmd, b, &params, groups);
  } else if (in.bricks) {
    gpu::ProfileScope scope(profiler, cmd, kName);
    std::array<gpu::Binding, kSdfShadowBindingBrickCount> bb;
    std::copy(b.begin(), b.end(), bb.begin());
    bb[kSdfShadowBindingField] = &in.bricks->coarse;
    bb[kSdfShadowBindingBrickSlots] = &in.bricks->slots;
    bb[kSdfShadowBindingBrickParams] = &in.bricks->params;
    bb[kSdfShadowBindingFineToCoarse] = &in.bricks->fineToCoarse;
    for (std::uint32_t k = 0; k < RTSDF_BRICK_PAGES; ++k)
      bb[kSdfShadowBindingValuePages + k] = in.bricks->pool.values[k];
    mBrickPipeline.dispatch(cmd, bb, &params, groups);
  } else {
    gpu::ProfileScope scope(profiler, cmd, kName);
    b[kSdfShadowBindingField] = &in.field;
    mBufferPipeline.dispatch(cmd, b, &params, groups);
  }
  gpu::computeBarrier(cmd);
}

ShadowMapPass::ShadowMapPass(const gpu::VulkanContext& ctx)
    : mBuild(ctx, "shadow_map.comp", kShadowMapBindingCount, sizeof(ShadowMapParams)),
      mLookup(ctx, "shadow_lookup.comp", kShadowLookupBindingCount, sizeof(ShadowMapParams)) {}

void ShadowMapPass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                            const Params& maps) const {
  if (maps.empty()) return;
  {
    gpu::ProfileScope scope(profiler, cmd, kBuildName);
    std::array<gpu::Binding, kShadowMapBindingCount> b;
    in.bvh.bindTo(b);
    b[kShadowMapBindingLights] = &in.lights;
    b[kShadowMapBindingDepth] = &out.depth;
    for (const ShadowMapParams& m : maps) {
      const std::uint32_t n = std::uint32_t(m.info.x);
      const std::uint32_t faces = std::uint32_t(m.info.z) == kLightSphere ? 6u : 1u;
      mBuild.dispatch(cmd, b, &m, {gpu::groupsFor(n, 8), gpu::groupsFor(n, 8), faces});
    }
    gpu::computeBarrier(cmd);
  }
  gpu::ProfileScope scope(profiler, cmd, kLookupName);
  std::array<gpu::Binding, kShadowLookupBindingCount> b;
  b[kShadowLookupBindingPositions] = &in.gbuffer.position;
  b[kShadowLookupBindingNormals] = &in.gbuffer.normal;
  b[kShadowLookupBindingDepth] = &out.depth;
  b[kShadowLookupBindingLights] = &in.lights;
  b[kShadowLookupBindingMaps] = &in.maps;
  b[kShadowLookupBindingVisibility] = &out.visibility;
  mLookup.dispatch(cmd, b, &maps[0], imageGroups(in.gbuffer.width, in.gbuffer.height));
  gpu::computeBarrier(cmd);
}

void TaaPass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                      const Params& params) const {
  gpu::ProfileScope scope(profiler, cmd, kName);
  std::array<gpu::Binding, kTaaBindingCount> b;
  b[kTaaBindingCurrent] = &in.current;
  b[kTaaBindingHistory] = &out.history;
  mPipeline.dispatch(cmd, b, &params, imageGroups(params.image.x, params.image.y));
  gpu::computeBarrier(cmd);
}

ComposePass::ComposePass(const gpu::VulkanContext& ctx)
    : ComputePass(ctx, "compose.comp", kComposeBindingCount, 0),
      mParams(ctx, sizeof(ComposeParams), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, Buffer::Memory::Device,
              "compose parameters") {}

void ComposePass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                          const Params& params) const {
  if (in.gbuffer.width != params.image.x || in.gbuffer.height != params.image.y)
    throw Error(fmt::format("ComposePass: a {}x{} picture from a {}x{} G-buffer", params.image.x, params.image.y,
                            in.gbuffer.width, in.gbuffer.height));
  gpu::ProfileScope scope(profiler, cmd, kName);
  gpu::recordUpload(cmd, mParams, &params, sizeof(params));
  gpu::computeBarrier(cmd);
  std::array<gpu::Binding, kComposeBindingCount> b;
  b[kComposeBindingPositions] = &in.gbuffer.position;
  b[kComposeBindingNormals] = &in.gbuffer.normal;
  b[kComposeBindingVisibility] = &in.visibility;
  b[kComposeBindingLights] = &in.lights;
  b[kComposeBindingFine] = &in.fine;
  b[kComposeBindingCoarse] = &in.coarse;
  b[kComposeBindingOverlay] = &in.overlay;
  b[kComposeBindingParams] = &mParams;
  b[kComposeBindingOutput] = &out.pixels;
  mPipeline.dispatch(cmd, b, nullptr, imageGroups(params.image.x, params.image.y));
  gpu::computeBarrier(cmd);
}

} // namespace rtsdf
