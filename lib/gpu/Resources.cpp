#include "gpu/Resources.h"

#include "gpu/VulkanError.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

namespace rtsdf::gpu {

namespace {
// The wrappers are move-only through their UniqueHandle members alone (no hand-written copy, move or destructor).
template <class W>
constexpr bool kMoveOnly = !std::is_copy_constructible_v<W> && !std::is_copy_assignable_v<W> &&
                           std::is_nothrow_move_constructible_v<W> && std::is_nothrow_move_assignable_v<W>;
static_assert(kMoveOnly<Buffer> && kMoveOnly<SampledVolume> && kMoveOnly<CommandBuffer> && kMoveOnly<ComputePipeline>);

/// Allocate @a memory of a type with @a props for an object with requirements @a req (@a what names it in errors),
/// charging its bytes to the context in @a charge where it is device-local.
void allocate(const VulkanContext& ctx, UniqueHandle<vkFreeMemory>& memory, DeviceMemoryCharge& charge,
              const VkMemoryRequirements& req, VkMemoryPropertyFlags props, const std::string& what) {
  VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  ai.allocationSize = req.size;
  ai.memoryTypeIndex = ctx.memoryType(req.memoryTypeBits, props);
  memory.create(ctx, vkAllocateMemory, ai, fmt::format("allocating {} MiB for {}", req.size >> 20, what));
  if (props & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT) charge = DeviceMemoryCharge(ctx, req.size);
}
} // namespace

// ---------------------------------------------------------------------------------------------- Buffer

Buffer::Buffer(const VulkanContext& ctx, VkDeviceSize bytes, VkBufferUsageFlags usage, Memory memory, std::string name)
    : mSize(bytes), mName(std::move(name)) {
  if (bytes == 0) throw Error(fmt::format("buffer '{}': size must be positive", mName));
  if ((usage & VK_BUFFER_USAGE_STORAGE_BUFFER_BIT) && bytes > ctx.info().maxStorageBufferRange)
    throw Error(fmt::format("buffer '{}': {} MiB exceeds {}'s maxStorageBufferRange of {} MiB", mName, bytes >> 20,
                            ctx.info().name, ctx.info().maxStorageBufferRange >> 20));
  VkBufferCreateInfo ci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  ci.size = bytes;
  ci.usage = usage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  ci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  // On a throw below, the members already made are destroyed (and uncounted) by their UniqueHandles.
  mBuffer.create(ctx, vkCreateBuffer, ci, fmt::format("creating buffer '{}'", mName));
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(ctx.device(), mBuffer.get(), &req);
  const VkMemoryPropertyFlags props = memory == Memory::Host
                                          ? VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT
                                          : VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
  allocate(ctx, mMemory, mCharge, req, props, fmt::format("buffer '{}'", mName));
  check(vkBindBufferMemory(ctx.device(), mBuffer.get(), mMemory.get(), 0),
        fmt::format("binding buffer '{}'", mName).c_str());
  if (memory == Memory::Host)
    check(vkMapMemory(ctx.device(), mMemory.get(), 0, VK_WHOLE_SIZE, 0, &mMapped),
          fmt::format("mapping buffer '{}'", mName).c_str());
}

// --------------------------------------------------------------------------------------- CommandBuffer

CommandBuffer::CommandBuffer(const VulkanContext& ctx) : mCtx(&ctx) {
  VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pci.queueFamilyIndex = ctx.queueFamily();
  pci.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
  mPool.create(ctx, vkCreateCommandPool, pci, "creating a command pool");
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = mPool.get();
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  check(vkAllocateCommandBuffers(ctx.device(), &ai, &mCmd), "allocating a command buffer");
  mFence.create(ctx, vkCreateFence, fci, "creating a fence");
  begin();
}

CommandBuffer::~CommandBuffer() {
  // The pool must not be destroyed while the GPU runs its buffer; an error here has nowhere to go.
  if (mPending && mFence.get() != VK_NULL_HANDLE) vkWaitForFences(mCtx->device(), 1, mFence.address(), VK_TRUE, std::uint64_t(600e9));
}

void CommandBuffer::begin() {
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(mCmd, &bi), "beginning a command buffer");
  mRecording = true;
}

void CommandBuffer::submit(VkSemaphore wait, VkPipelineStageFlags waitStage, VkSemaphore signal) {
  if (!mRecording) throw Error("command buffer submitted twice");
  mRecording = false;
  check(vkEndCommandBuffer(mCmd), "ending a command buffer");
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &mCmd;
  if (wait != VK_NULL_HANDLE) {
    si.waitSemaphoreCount = 1;
    si.pWaitSemaphores = &wait;
    si.pWaitDstStageMask = &waitStage;
  }
  if (signal != VK_NULL_HANDLE) {
    si.signalSemaphoreCount = 1;
    si.pSignalSemaphores = &signal;
  }
  check(vkQueueSubmit(mCtx->queue(), 1, &si, mFence.get()), "submitting to the compute queue");
  mPending = true;
}

void CommandBuffer::wait(double timeoutSeconds) {
  if (!mPending) return;
  const VkResult r =
      vkWaitForFences(mCtx->device(), 1, mFence.address(), VK_TRUE, std::uint64_t(timeoutSeconds * 1e9));
  if (r == VK_TIMEOUT)
    throw VulkanError(r, fmt::format("waiting for the GPU ({} s without completion)", timeoutSeconds));
  check(r, "waiting for the GPU");
  mPending = false;
}

void CommandBuffer::submitAndWait(double timeoutSeconds) {
  submit();
  wait(timeoutSeconds);
}

void CommandBuffer::restart() {
  wait(); // a pool whose buffer is pending must not be reset; a recording one may (the buffer returns to initial)
  check(vkResetFences(mCtx->device(), 1, mFence.address()), "resetting a fence");
  check(vkResetCommandPool(mCtx->device(), mPool.get(), 0), "resetting a command pool");
  begin();
}

// ------------------------------------------------------------------------------------- ComputePipeline

ComputePipeline::ComputePipeline(const VulkanContext& ctx, const std::string& shader, std::uint32_t storageBuffers,
                                 std::uint32_t pushConstantBytes)
    : ComputePipeline(ctx, shader, std::vector<VkDescriptorType>(storageBuffers, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER),
                      pushConstantBytes) {}

ComputePipeline::ComputePipeline(const VulkanContext& ctx, const std::string& shader,
                                 std::vector<VkDescriptorType> types, std::uint32_t pushConstantBytes)
    : mCtx(&ctx), mName(shader), mTypes(std::move(types)), mPushBytes(pushConstantBytes) {
  for (VkDescriptorType t : mTypes)
    if (t != VK_DESCRIPTOR_TYPE_STORAGE_BUFFER && t != VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER &&
        t != VK_DESCRIPTOR_TYPE_STORAGE_IMAGE)
      throw Error(fmt::format("{}: unsupported descriptor type {}", shader, int(t)));
  std::string key = fmt::format("compute pipeline {} push {}", shader, pushConstantBytes);
  for (VkDescriptorType t : mTypes) key += fmt::format(" {}", int(t));
  mCompiled = std::static_pointer_cast<const Compiled>(ctx.shared(key, [this] { return compile(); }));
}

std::shared_ptr<ComputePipeline::Compiled> ComputePipeline::compile() const {
  const VulkanContext& ctx = *mCtx;
  const std::string& shader = mName;
  const std::uint32_t pushConstantBytes = mPushBytes;
  auto c = std::make_shared<Compiled>();
  c->module.reset(ctx, ctx.createShaderModule(shader));
  const std::uint32_t n = std::uint32_t(mTypes.size());
  std::vector<VkDescriptorSetLayoutBinding> bindings(n);
  for (std::uint32_t i = 0; i < n; ++i) bindings[i] = {i, mTypes[i], 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
  VkDescriptorSetLayoutCreateInfo lci{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  lci.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
  lci.bindingCount = n;
  lci.pBindings = bindings.data();
  c->setLayout.create(ctx, vkCreateDescriptorSetLayout, lci,
                      fmt::format("creating the descriptor set layout of {}", shader));
  VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, pushConstantBytes};
  VkPipelineLayoutCreateInfo pci{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  pci.setLayoutCount = 1;
  pci.pSetLayouts = c->setLayout.address();
  pci.pushConstantRangeCount = pushConstantBytes ? 1 : 0;
  pci.pPushConstantRanges = &range;
  c->layout.create(ctx, vkCreatePipelineLayout, pci, fmt::format("creating the pipeline layout of {}", shader));
  VkComputePipelineCreateInfo cci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  cci.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  cci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  cci.stage.module = c->module.get();
  cci.stage.pName = "main";
  cci.layout = c->layout.get();
  VkPipeline pipeline = VK_NULL_HANDLE; // vkCreateComputePipelines makes arrays: not create()'s shape
  check(vkCreateComputePipelines(ctx.device(), VK_NULL_HANDLE, 1, &cci, nullptr, &pipeline),
        fmt::format("creating the compute pipeline {}", shader).c_str());
  c->pipeline.reset(ctx, pipeline);
  return c;
}

void ComputePipeline::record(VkCommandBuffer cmd, const Binding* bindings, std::size_t count, const void* push,
                             const glm::uvec3* groups, const Buffer* indirect, VkDeviceSize offset) const {
  const glm::uvec3 limit = mCtx->info().maxWorkGroupCount;
  if (groups && (groups->x > limit.x || groups->y > limit.y || groups->z > limit.z))
    throw Error(fmt::format("{}: dispatch of {}x{}x{} work groups exceeds {}'s limit of {}x{}x{}", mName, groups->x,
                            groups->y, groups->z, mCtx->info().name, limit.x, limit.y, limit.z));
  const std::uint32_t n = std::uint32_t(mTypes.size());
  if (count != n) throw Error(fmt::format("{}: {} resources given for {} bindings", mName, count, n));
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, mCompiled->pipeline.get());
  std::vector<VkDescriptorBufferInfo> buffers(n);
  std::vector<VkDescriptorImageInfo> images(n);
  std::vector<VkWriteDescriptorSet> writes;
  for (std::uint32_t i = 0; i < n; ++i) {
    const Binding& b = bindings[i];
    VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstBinding = i;
    w.descriptorCount = 1;
    w.descriptorType = mTypes[i];
    if (mTypes[i] == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER) {
      if (!b.buffer || !*b.buffer) throw Error(fmt::format("{}: binding {} needs a storage buffer", mName, i));
      buffers[i] = {b.buffer->handle(), 0, VK_WHOLE_SIZE};
      w.pBufferInfo = &buffers[i];
    } else {
      if (!b.volume || !*b.volume)
        throw Error(fmt::format("{}: binding {} needs a volume ({})", mName, i,
                                mTypes[i] == VK_DESCRIPTOR_TYPE_STORAGE_IMAGE ? "a storage image" : "sampled"));
      images[i] = mTypes[i] == VK_DESCRIPTOR_TYPE_STORAGE_IMAGE
                      ? VkDescriptorImageInfo{VK_NULL_HANDLE, b.volume->view(), VK_IMAGE_LAYOUT_GENERAL}
                      : VkDescriptorImageInfo{b.volume->sampler(), b.volume->view(),
                                              VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
      w.pImageInfo = &images[i];
    }
    writes.push_back(w);
  }
  if (n) mCtx->pushDescriptorSet()(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, mCompiled->layout.get(), 0, n, writes.data());
  if (mPushBytes) vkCmdPushConstants(cmd, mCompiled->layout.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, mPushBytes, push);
  if (indirect)
    vkCmdDispatchIndirect(cmd, indirect->handle(), offset);
  else if (groups->x && groups->y && groups->z)
    vkCmdDispatch(cmd, groups->x, groups->y, groups->z);
}

// ---------------------------------------------------------------------------------------------- SampledVolume

namespace {
/// A layout change of a whole single-level colour image, with the accesses it orders.
VkImageMemoryBarrier imageBarrier(VkImage image, VkAccessFlags src, VkAccessFlags dst, VkImageLayout from,
                                  VkImageLayout to) {
  VkImageMemoryBarrier ib{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  ib.srcAccessMask = src;
  ib.dstAccessMask = dst;
  ib.oldLayout = from;
  ib.newLayout = to;
  ib.srcQueueFamilyIndex = ib.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  ib.image = image;
  ib.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  return ib;
}
} // namespace

bool SampledVolume::supported(const VulkanContext& ctx) {
  VkFormatProperties fp;
  vkGetPhysicalDeviceFormatProperties(ctx.physicalDevice(), VK_FORMAT_R32_SFLOAT, &fp);
  const VkFormatFeatureFlags need = VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT |
                                    VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT |
                                    VK_FORMAT_FEATURE_TRANSFER_DST_BIT;
  return (fp.optimalTilingFeatures & need) == need;
}

bool SampledVolume::storageSupported(const VulkanContext& ctx) {
  VkFormatProperties fp;
  vkGetPhysicalDeviceFormatProperties(ctx.physicalDevice(), VK_FORMAT_R32_SFLOAT, &fp);
  return supported(ctx) && (fp.optimalTilingFeatures & VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT);
}

SampledVolume::SampledVolume(const VulkanContext& ctx, glm::uvec3 dims, std::string name)
    : mDims(dims), mName(std::move(name)) {
  const std::uint32_t limit = ctx.info().maxImageDimension3D;
  if (dims.x == 0 || dims.y == 0 || dims.z == 0 || dims.x > limit || dims.y > limit || dims.z > limit)
    throw Error(fmt::format("volume '{}': {}x{}x{} voxels is empty or beyond {}'s maxImageDimension3D of {}", mName,
                            dims.x, dims.y, dims.z, ctx.info().name, limit));
  if (!supported(ctx))
    throw Error(fmt::format("volume '{}': {} cannot filter R32_SFLOAT 3D textures linearly (use buffer sampling)",
                            mName, ctx.info().name));
  VkImageCreateInfo ci{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  ci.imageType = VK_IMAGE_TYPE_3D;
  ci.format = VK_FORMAT_R32_SFLOAT;
  ci.extent = {dims.x, dims.y, dims.z};
  ci.mipLevels = 1;
  ci.arrayLayers = 1;
  ci.samples = VK_SAMPLE_COUNT_1_BIT;
  ci.tiling = VK_IMAGE_TILING_OPTIMAL;
  mStorage = storageSupported(ctx);
  ci.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
             (mStorage ? VK_IMAGE_USAGE_STORAGE_BIT : 0);
  ci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  ci.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  // On a throw below, the members already made are destroyed (and uncounted) by their UniqueHandles.
  mImage.create(ctx, vkCreateImage, ci, fmt::format("creating volume '{}'", mName));
  VkMemoryRequirements req;
  vkGetImageMemoryRequirements(ctx.device(), mImage.get(), &req);
  allocate(ctx, mMemory, mCharge, req, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, fmt::format("volume '{}'", mName));
  check(vkBindImageMemory(ctx.device(), mImage.get(), mMemory.get(), 0),
        fmt::format("binding volume '{}'", mName).c_str());
  VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  vi.image = mImage.get();
  vi.viewType = VK_IMAGE_VIEW_TYPE_3D;
  vi.format = VK_FORMAT_R32_SFLOAT;
  vi.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  mView.create(ctx, vkCreateImageView, vi, fmt::format("creating the view of '{}'", mName));
  // Texel centres at (i + 0.5) / dims, clamped to the edge texels: the same trilinear field as the buffer
  // path's sampleSdf (which clamps the continuous index to [0, dims - 1]).
  VkSamplerCreateInfo si{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  si.magFilter = VK_FILTER_LINEAR;
  si.minFilter = VK_FILTER_LINEAR;
  si.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
  si.addressModeU = si.addressModeV = si.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  si.maxLod = 0.0f;
  mSampler.create(ctx, vkCreateSampler, si, fmt::format("creating the sampler of '{}'", mName));
}

void SampledVolume::copyFrom(VkCommandBuffer cmd, const Buffer& src) const {
  const VkDeviceSize bytes = VkDeviceSize(mDims.x) * mDims.y * mDims.z * sizeof(float);
  if (src.size() < bytes)
    throw Error(fmt::format("volume '{}': buffer '{}' holds {} bytes, the volume needs {}", mName, src.name(),
                            src.size(), bytes));
  // Earlier shader writes of the buffer before the copy reads it; the old contents of the image (last frame's,
  // read by earlier shaders) are discarded: UNDEFINED -> TRANSFER_DST after those reads.
  VkBufferMemoryBarrier bb{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER};
  bb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  bb.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
  bb.srcQueueFamilyIndex = bb.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  bb.buffer = src.handle();
  bb.size = VK_WHOLE_SIZE;
  VkImageMemoryBarrier ib = imageBarrier(mImage.get(), VK_ACCESS_SHADER_READ_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                                         VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 1, &bb, 1, &ib);
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {mDims.x, mDims.y, mDims.z};
  vkCmdCopyBufferToImage(cmd, src.handle(), mImage.get(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
  ib = imageBarrier(mImage.get(), VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT,
                    VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 0, nullptr, 0,
                       nullptr, 1, &ib);
}

void SampledVolume::copyTo(VkCommandBuffer cmd, const Buffer& dst) const {
  const VkDeviceSize bytes = VkDeviceSize(mDims.x) * mDims.y * mDims.z * sizeof(float);
  if (dst.size() < bytes)
    throw Error(fmt::format("volume '{}': buffer '{}' holds {} bytes, the volume needs {}", mName, dst.name(),
                            dst.size(), bytes));
  VkImageMemoryBarrier ib = imageBarrier(
      mImage.get(), VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
      VK_ACCESS_TRANSFER_READ_BIT, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 0, nullptr, 1, &ib);
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {mDims.x, mDims.y, mDims.z};
  vkCmdCopyImageToBuffer(cmd, mImage.get(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, dst.handle(), 1, &region);
  ib = imageBarrier(mImage.get(), VK_ACCESS_TRANSFER_READ_BIT, VK_ACCESS_SHADER_READ_BIT,
                    VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER}; // the buffer's new contents, for later reads and transfers
  mb.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  mb.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_HOST_BIT,
                       0, 1, &mb, 0, nullptr, 1, &ib);
}

void SampledVolume::beginShaderWrite(VkCommandBuffer cmd, bool keep) const {
  if (!mStorage) throw Error(fmt::format("volume '{}': made without storage use, shaders cannot write it", mName));
  // Earlier writes of whatever the shaders read (a buffer) before they read it; the image's old contents, read
  // by earlier shaders, are discarded (UNDEFINED -> GENERAL after those reads) or kept (from SHADER_READ_ONLY).
  VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  mb.dstAccessMask = VK_ACCESS_SHADER_READ_BIT;
  const VkImageMemoryBarrier ib =
      imageBarrier(mImage.get(), VK_ACCESS_SHADER_READ_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                   keep ? VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL : VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &mb, 0, nullptr, 1, &ib);
}

void SampledVolume::endShaderWrite(VkCommandBuffer cmd) const {
  const VkImageMemoryBarrier ib = imageBarrier(mImage.get(), VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT,
                                               VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 0, nullptr,
                       0, nullptr, 1, &ib);
}

void computeBarrier(VkCommandBuffer cmd) {
  VkMemoryBarrier b{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  b.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  b.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT |
                    VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT |
                           VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT,
                       0, 1, &b, 0, nullptr, 0, nullptr);
}

void transferToHostBarrier(VkCommandBuffer cmd) {
  VkMemoryBarrier b{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  b.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  b.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &b, 0, nullptr, 0,
                       nullptr);
}

void reserve(const VulkanContext& ctx, Buffer& b, VkDeviceSize bytes, VkBufferUsageFlags usage, Buffer::Memory memory,
             const std::string& name) {
  const VkDeviceSize size = std::max<VkDeviceSize>(bytes, 16);
  if (!b || b.size() < size) b = Buffer(ctx, size, usage, memory, name);
}

void reserveAndUpload(const VulkanContext& ctx, Buffer& b, const void* data, std::size_t bytes,
                      VkBufferUsageFlags usage, const std::string& name) {
  reserve(ctx, b, bytes, usage, Buffer::Memory::Device, name);
  upload(ctx, b, data, bytes);
}

void upload(const VulkanContext& ctx, const Buffer& dst, const void* data, std::size_t bytes) {
  if (bytes > dst.size()) throw Error(fmt::format("upload of {} bytes into buffer '{}' of {}", bytes, dst.name(), dst.size()));
  if (bytes == 0) return;
  if (dst.mapped()) { std::memcpy(dst.mapped(), data, bytes); return; }
  Buffer staging(ctx, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, Buffer::Memory::Host, dst.name() + " (staging)");
  std::memcpy(staging.mapped(), data, bytes);
  CommandBuffer cmd(ctx);
  const VkBufferCopy region{0, 0, bytes};
  vkCmdCopyBuffer(cmd.handle(), staging.handle(), dst.handle(), 1, &region);
  cmd.submitAndWait();
}

void recordUpload(VkCommandBuffer cmd, const Buffer& dst, const void* data, std::size_t bytes) {
  if (bytes > dst.size() || bytes % 4)
    throw Error(fmt::format("recorded upload of {} bytes into buffer '{}' of {} (must fit and be a multiple of 4)",
                            bytes, dst.name(), dst.size()));
  constexpr std::size_t kPiece = 65536; // vkCmdUpdateBuffer's limit per call
  const auto* bytesIn = static_cast<const std::uint8_t*>(data);
  for (std::size_t offset = 0; offset < bytes; offset += kPiece)
    vkCmdUpdateBuffer(cmd, dst.handle(), offset, std::min(kPiece, bytes - offset), bytesIn + offset);
}

void download(const VulkanContext& ctx, const Buffer& src, void* data, std::size_t bytes) {
  if (bytes > src.size()) throw Error(fmt::format("download of {} bytes from buffer '{}' of {}", bytes, src.name(), src.size()));
  if (bytes == 0) return;
  if (src.mapped()) { std::memcpy(data, src.mapped(), bytes); return; }
  Buffer staging(ctx, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, Buffer::Memory::Host, src.name() + " (readback)");
  CommandBuffer cmd(ctx);
  const VkBufferCopy region{0, 0, bytes};
  vkCmdCopyBuffer(cmd.handle(), src.handle(), staging.handle(), 1, &region);
  cmd.submitAndWait();
  std::memcpy(data, staging.mapped(), bytes);
}

} // namespace rtsdf::gpu
