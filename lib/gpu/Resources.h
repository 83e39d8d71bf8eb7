#pragma once
/// @file Resources.h
/// @brief Move-only RAII owners of the Vulkan objects rtsdf's compute passes use: buffers, one-shot
///        command buffers, compute pipelines (push descriptors, push constants) and barriers.
#include "gpu/VulkanContext.h"

#include <glm/glm.hpp>

#include <array>
#include <cstddef>
#include <initializer_list>
#include <string>
#include <vector>

namespace rtsdf::gpu {

/// @brief A VkBuffer with its own memory. Every live Buffer is counted by its context (leak report).
class Buffer {
public:
  /// @brief Where the buffer's memory lives.
  enum class Memory {
    Device, ///< device-local (fast for the GPU; uploaded and read back through staging)
    Host    ///< host-visible and coherent, persistently mapped (staging, small uniforms, readback)
  };
  Buffer() = default;
  /// @throw VulkanError (with the VkResult) when creation or allocation fails, Error on a zero size or a
  ///        size beyond the device's maxStorageBufferRange for storage buffers.
  Buffer(const VulkanContext& ctx, VkDeviceSize bytes, VkBufferUsageFlags usage, Memory memory, std::string name);
  ~Buffer();
  Buffer(Buffer&& other) noexcept;
  Buffer& operator=(Buffer&& other) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  VkBuffer handle() const { return mBuffer; }
  VkDeviceSize size() const { return mSize; }
  const std::string& name() const { return mName; }
  /// @brief Host pointer of a Memory::Host buffer (nullptr for device memory).
  void* mapped() const { return mMapped; }
  explicit operator bool() const { return mBuffer != VK_NULL_HANDLE; }

private:
  void reset();
  const VulkanContext* mCtx = nullptr;
  VkBuffer mBuffer = VK_NULL_HANDLE;
  VkDeviceMemory mMemory = VK_NULL_HANDLE;
  VkDeviceSize mSize = 0;
  void* mMapped = nullptr;
  std::string mName;
};

/// @brief A 3D single-channel float texture (R32_SFLOAT, optimal tiling) with its view, its own memory and a
///        sampler (trilinear filtering, clamp to edge, normalized coordinates), for fields the shaders sample
///        with hardware filtering. Filled from a dense buffer by copyFrom(); counted by its context (leaks).
class SampledVolume {
public:
  SampledVolume() = default;
  /// @param dims voxels per axis; texel (i, j, k) is the buffer's value i + dims.x (j + dims.y k).
  /// @throw Error when a dimension is 0 or beyond maxImageDimension3D, or when the device cannot filter
  ///        R32_SFLOAT linearly (an optional feature); VulkanError (with the VkResult) when creation fails.
  SampledVolume(const VulkanContext& ctx, glm::uvec3 dims, std::string name);
  ~SampledVolume();
  SampledVolume(SampledVolume&& other) noexcept;
  SampledVolume& operator=(SampledVolume&& other) noexcept;
  SampledVolume(const SampledVolume&) = delete;
  SampledVolume& operator=(const SampledVolume&) = delete;

  /// @brief Record: copy @a src (dims.x * dims.y * dims.z floats, x fastest, written by earlier shaders or
  ///        transfers) into the texture and make it ready for sampling by later compute shaders.
  /// @throw Error when @a src is smaller than the texture.
  void copyFrom(VkCommandBuffer cmd, const Buffer& src) const;

  /// @brief Whether @a ctx's device filters R32_SFLOAT 3D textures linearly.
  static bool supported(const VulkanContext& ctx);

  VkImageView view() const { return mView; }
  VkSampler sampler() const { return mSampler; }
  glm::uvec3 dims() const { return mDims; }
  const std::string& name() const { return mName; }
  explicit operator bool() const { return mImage != VK_NULL_HANDLE; }

private:
  void reset();
  const VulkanContext* mCtx = nullptr;
  VkImage mImage = VK_NULL_HANDLE;
  VkDeviceMemory mMemory = VK_NULL_HANDLE;
  VkImageView mView = VK_NULL_HANDLE;
  VkSampler mSampler = VK_NULL_HANDLE;
  glm::uvec3 mDims{0};
  std::string mName;
};

/// @brief What a compute pipeline binds at one binding: a storage buffer or a sampled volume.
struct Binding {
  Binding() = default;                           ///< unset: a dispatch with an unset binding throws
  Binding(const Buffer* b) : buffer(b) {}        // NOLINT(google-explicit-constructor): {&a, &b} lists
  Binding(const SampledVolume* v) : volume(v) {} // NOLINT(google-explicit-constructor)
  const Buffer* buffer = nullptr;
  const SampledVolume* volume = nullptr;
};

/// @brief The bindings of one dispatch in binding order: a braced list {&a, &b}, or a std::array a pass fills
///        by the named binding indices of its shared header (gpu/shared/*.h), so no call binds by position.
/// @note A view: the list or array must outlive the call it is passed to (a braced list in the call does).
class BindingList {
public:
  BindingList(std::initializer_list<Binding> list) : mData(list.begin()), mSize(list.size()) {} // NOLINT
  template <std::size_t N>
  BindingList(const std::array<Binding, N>& array) : mData(array.data()), mSize(N) {} // NOLINT
  const Binding* begin() const { return mData; }
  const Binding* end() const { return mData + mSize; }
  std::size_t size() const { return mSize; }

private:
  const Binding* mData;
  std::size_t mSize;
};

/// @brief A primary command buffer from its own pool, begun on construction; submit() waits for it.
class CommandBuffer {
public:
  explicit CommandBuffer(const VulkanContext& ctx);
  ~CommandBuffer();
  CommandBuffer(CommandBuffer&& other) noexcept;
  CommandBuffer& operator=(CommandBuffer&&) = delete;
  CommandBuffer(const CommandBuffer&) = delete;
  CommandBuffer& operator=(const CommandBuffer&) = delete;

  VkCommandBuffer handle() const { return mCmd; }
  /// @brief End recording, submit to the context's queue and wait (with a timeout, never forever).
  /// @throw VulkanError on failure or when the GPU does not finish within @a timeoutSeconds.
  void submitAndWait(double timeoutSeconds = 600.0);

private:
  void destroy();
  const VulkanContext* mCtx = nullptr;
  VkCommandPool mPool = VK_NULL_HANDLE;
  VkCommandBuffer mCmd = VK_NULL_HANDLE;
  VkFence mFence = VK_NULL_HANDLE;
  bool mRecording = false;
};

/// @brief A compute pipeline from an embedded shader whose bindings 0..n-1 are storage buffers (or, where
///        given, combined image samplers), bound by push descriptors, with an optional push-constant block.
class ComputePipeline {
public:
  ComputePipeline() = default;
  /// @brief Bindings 0..storageBuffers-1 are all storage buffers.
  ComputePipeline(const VulkanContext& ctx, const std::string& shader, std::uint32_t storageBuffers,
                  std::uint32_t pushConstantBytes);
  /// @brief Binding i has descriptor type @a bindings[i]: VK_DESCRIPTOR_TYPE_STORAGE_BUFFER or
  ///        VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER (a SampledVolume).
  ComputePipeline(const VulkanContext& ctx, const std::string& shader, std::vector<VkDescriptorType> bindings,
                  std::uint32_t pushConstantBytes);
  ~ComputePipeline();
  ComputePipeline(ComputePipeline&& other) noexcept;
  ComputePipeline& operator=(ComputePipeline&& other) noexcept;
  ComputePipeline(const ComputePipeline&) = delete;
  ComputePipeline& operator=(const ComputePipeline&) = delete;

  /// @brief Record: bind, push @a buffers to bindings 0.. in order and @a push constants, dispatch @a groups.
  /// @note @a push must point at exactly the pushConstantBytes given at creation (or be null when 0).
  /// @throw Error when a binding's kind differs from the pipeline's layout.
  void dispatch(VkCommandBuffer cmd, BindingList bindings, const void* push,
                glm::uvec3 groups) const;
  /// @brief The same with the group counts read on the GPU from @a indirect (a VkDispatchIndirectCommand at
  ///        offset 0; the buffer needs VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT).
  void dispatchIndirect(VkCommandBuffer cmd, BindingList bindings, const void* push,
                        const Buffer& indirect) const;
  const std::string& name() const { return mName; }

private:
  void bind(VkCommandBuffer cmd, BindingList bindings, const void* push) const;
  void reset();
  const VulkanContext* mCtx = nullptr;
  std::string mName;
  std::vector<VkDescriptorType> mTypes;
  std::uint32_t mPushBytes = 0;
  VkShaderModule mModule = VK_NULL_HANDLE;
  VkDescriptorSetLayout mSetLayout = VK_NULL_HANDLE;
  VkPipelineLayout mLayout = VK_NULL_HANDLE;
  VkPipeline mPipeline = VK_NULL_HANDLE;
};

/// @brief Make every earlier shader and transfer write visible to every later shader and transfer access.
/// @note Between dependent dispatches (e.g. jump-flooding ping-pong). Proven by GPU == CPU tests, since the
///       validation layer misses dispatch-to-dispatch hazards on this driver version.
void computeBarrier(VkCommandBuffer cmd);

/// @brief (Re)create @a b when it is empty or smaller than @a bytes (at least 16); keeps it otherwise, so
///        per-frame buffers are allocated once.
void reserve(const VulkanContext& ctx, Buffer& b, VkDeviceSize bytes, VkBufferUsageFlags usage, Buffer::Memory memory,
             const std::string& name);

/// @brief reserve() device memory for @a bytes in @a b, then upload() them: a per-frame buffer allocated once.
void reserveAndUpload(const VulkanContext& ctx, Buffer& b, const void* data, std::size_t bytes,
                      VkBufferUsageFlags usage, const std::string& name);

/// @brief Copy @a bytes from host memory into @a dst (through a staging buffer when it is device memory).
void upload(const VulkanContext& ctx, const Buffer& dst, const void* data, std::size_t bytes);
/// @brief Copy @a bytes of @a src into host memory (through a staging buffer when it is device memory).
void download(const VulkanContext& ctx, const Buffer& src, void* data, std::size_t bytes);

/// @brief Ceiling division for dispatch sizes.
inline std::uint32_t groupsFor(std::uint64_t n, std::uint32_t groupSize) {
  return std::uint32_t((n + groupSize - 1) / groupSize);
}

} // namespace rtsdf::gpu
