#include "render/sdfshadow/SdfShadowPass.h"

#include "util/Error.h"

#include <fmt/format.h>
#include <algorithm>
#include <array>

namespace rtsdf {
using gpu::Buffer;
using namespace gpu::shared;

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

VolumeUpdatePass::VolumeUpdatePass(const gpu::VulkanContext& ctx) {
  if (gpu::SampledVolume::storageSupported(ctx)) {
    std::vector<VkDescriptorType> types(kVolumeUpdateBindingCount, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
    types[kVolumeUpdateBindingTexture] = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    mBlocks = gpu::ComputePipeline(ctx, "volume_update_blocks.comp", types, sizeof(Params));
    mRefined = gpu::ComputePipeline(ctx, "volume_update_refined.comp", types, sizeof(Params));
  }
}

void VolumeUpdatePass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                               const Params& params) const {
  if (!available())
    throw Error("VolumeUpdatePass: this device cannot store to R32_SFLOAT 3D textures (fill the whole texture)");
  if (in.writes.extent != DenseFineWrites::Extent::Listed)
    throw Error("VolumeUpdatePass: the frame's writes are not listed (fill the whole texture)");
  const glm::uvec3 d = out.texture.dims();
  if (in.field.size() < VkDeviceSize(d.x) * d.y * d.z * sizeof(float) || glm::uvec3(params.fineDims) != d)
    throw Error(fmt::format("VolumeUpdatePass: buffer '{}' ({} bytes, grid {}x{}x{}) does not fill texture '{}'",
                            in.field.name(), in.field.size(), params.fineDims.x, params.fineDims.y,
                            params.fineDims.z, out.texture.name()));
  gpu::ProfileScope scope(profiler, cmd, kName);
  gpu::computeBarrier(cmd); // the lists' dispatches, read indirectly
  out.texture.beginShaderWrite(cmd, true);
  std::array<gpu::Binding, kVolumeUpdateBindingCount> b;
  b[kVolumeUpdateBindingField] = &in.field;
  b[kVolumeUpdateBindingTexture] = &out.texture;
  // Every binding is bound; a list the frame did not write is never read (its dispatch is not recorded).
  const DenseFineWrites& w = in.writes;
  const gpu::Buffer& any = in.field;
  b[kVolumeUpdateBindingBlockList] = w.blockList ? w.blockList : &any;
  b[kVolumeUpdateBindingFineBegins] = w.blockFineBegins ? w.blockFineBegins : &any;
  b[kVolumeUpdateBindingRefineList] = w.refineList ? w.refineList : &any;
  b[kVolumeUpdateBindingMaskCounts] = w.maskCounts ? w.maskCounts : &any;
  b[kVolumeUpdateBindingFineRanges] = w.fineRanges ? w.fineRanges : &any;
  if (w.blockList && w.blockFineBegins) mBlocks.dispatchIndirect(cmd, b, &params, *w.blockList);
  if (w.refineList && w.maskCounts && w.fineRanges) mRefined.dispatchIndirect(cmd, b, &params, *w.maskCounts);
  out.texture.endShaderWrite(cmd);
}

SdfShadowPass::SdfShadowPass(const gpu::VulkanContext& ctx, bool umbra)
    : mBufferPipeline(ctx, umbra ? "sdf_shadow_umbra_buffer.comp" : "sdf_shadow_buffer.comp", kSdfShadowBindingCount,
                      sizeof(SdfShadowParams)),
      mBrickPipeline(ctx, umbra ? "sdf_shadow_umbra_bricks.comp" : "sdf_shadow_bricks.comp",
                     kSdfShadowBindingBrickCount, sizeof(SdfShadowParams)),
      mCascade4Pipeline(ctx, umbra ? "sdf_shadow_umbra_cascade4.comp" : "sdf_shadow_cascade4.comp",
                        kSdfShadowBindingCascadeCount, sizeof(SdfShadowParams)),
      mCascadePipeline(ctx, umbra ? "sdf_shadow_umbra_cascade.comp" : "sdf_shadow_cascade.comp",
                       kSdfShadowBindingCascadeCount, sizeof(SdfShadowParams)),
      mFill(ctx), mUpdate(ctx), mFillMethod(VolumeFillPass::defaultMethod(ctx)), mUmbra(umbra) {
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
    // Only where the whole fill is shader stores too (a GPU): there the update stores a part of the same texels. A
    // CPU device's whole fill is one copy command, a memcpy, which lavapipe ran in 1.2 ms against the update's
    // 1.3-1.45 for the moving teapot's frames at render's grid (docs/results.md).
    const bool update = in.fillOnly && in.fillOnly->extent == DenseFineWrites::Extent::Listed &&
                        mFillMethod == VolumeFillPass::Method::Compute && mUpdate.available();
    if (in.fillTexture && update)
      mUpdate.execute(cmd, profiler, {in.field, *in.fillOnly}, {*in.texture}, in.fillOnly->params);
    else if (in.fillTexture)
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
  } else if (in.cascade) {
    const std::size_t levels = in.cascade->fields.size();
    if (levels == 0 || levels > RTSDF_MAX_CASCADE_LEVELS || levels != params.cascadeLevels)
      throw Error(fmt::format("SdfShadowPass: {} cascade level field(s) given for {} level(s) (at most {})", levels,
                              params.cascadeLevels, RTSDF_MAX_CASCADE_LEVELS));
    gpu::ProfileScope scope(profiler, cmd, kName);
    std::array<gpu::Binding, kSdfShadowBindingCascadeCount> cb;
    std::copy(b.begin(), b.end(), cb.begin());
    cb[kSdfShadowBindingField] = in.cascade->fields[0]; // unread: the levels' own bindings hold the field
    cb[kSdfShadowBindingCascadeLevels] = &in.cascade->levels;
    for (std::size_t k = 0; k < RTSDF_MAX_CASCADE_LEVELS; ++k)
      cb[kSdfShadowBindingCascadeFields + k] = in.cascade->fields[k < levels ? k : 0];
    (levels <= 4 ? mCascade4Pipeline : mCascadePipeline).dispatch(cmd, cb, &params, groups);
  } else {
    gpu::ProfileScope scope(profiler, cmd, kName);
    b[kSdfShadowBindingField] = &in.field;
    mBufferPipeline.dispatch(cmd, b, &params, groups);
  }
  gpu::computeBarrier(cmd);
}

} // namespace rtsdf
