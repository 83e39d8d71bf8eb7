#pragma once
/// @file Resources.h
/// @brief Move-only RAII owners of the Vulkan objects rtsdf's compute passes use: buffers, one-shot
///        command buffers, compute pipelines (push descriptors, push constants) and barriers.
/// @note Each wrapper holds its Vulkan objects in UniqueHandle members (gpu/UniqueHandle.h), which destroy
///       them, keep the context's live-object count and make the wrapper move-only with no hand-written
///       destructor or move operations. Members are declared so that destruction goes dependents first; a move
///       assignment replaces them in declaration order (e.g. old memory freed before its old buffer), which
///       Vulkan allows as the old objects are never used again.
#include "gpu/UniqueHandle.h"
#include "gpu/VulkanContext.h"

#include <glm/glm.hpp>

#include <array>
#include <cstddef>
#include <initializer_list>
#include <string>
#include <vector>

namespace rtsdf::gpu {

/// @brief A VkBuffer with its own memory. Move-only; its buffer and memory are counted by its context (leak
///        report).
/// @brief The usages of the pipeline's storage buffers: read and written by shaders only (kStorage), also filled
///        or uploaded by transfers (kStorageFilled), also read back (kStorageRead).
inline constexpr VkBufferUsageFlags kStorage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
inline constexpr VkBufferUsageFlags kStorageFilled = kStorage | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
inline constexpr VkBufferUsageFlags kStorageRead = kStorageFilled | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;

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

  VkBuffer handle() const { return mBuffer.get(); }
  /// @brief Bytes (0 when empty or moved from).
  VkDeviceSize size() const { return mBuffer ? mSize : 0; }
  const std::string& name() const { return mName; }
  /// @brief Host pointer of a Memory::Host buffer (nullptr for device memory, or when empty or moved from).
  void* mapped() const { return mBuffer ? mMapped : nullptr; }
  explicit operator bool() const { return bool(mBuffer); }

private:
  UniqueHandle<vkFreeMemory> mMemory; // freed after the buffer (and implicitly unmapped)
  DeviceMemoryCharge mCharge;         // its bytes, where device-local
  UniqueHandle<vkDestroyBuffer> mBuffer;
  VkDeviceSize mSize = 0;
  void* mMapped = nullptr;
  std::string mName;
};

/// @brief A 3D single-channel float texture (R32_SFLOAT, optimal tiling) with its view, its own memory and a
///        sampler (trilinear filtering, clamp to edge, normalized coordinates), for fields the shaders sample
///        with hardware filtering. Filled from a dense buffer by copyFrom(); move-only; its objects are counted
///        by its context (leaks).
class SampledVolume {
public:
  SampledVolume() = default;
  /// @param dims voxels per axis; texel (i, j, k) is the buffer's value i + dims.x (j + dims.y k).
  /// @throw Error when a dimension is 0 or beyond maxImageDimension3D, or when the device cannot filter
  ///        R32_SFLOAT linearly (an optional feature); VulkanError (with the VkResult) when creation fails.
  SampledVolume(const VulkanContext& ctx, glm::uvec3 dims, std::string name);

  /// @brief Record: copy @a src (dims.x * dims.y * dims.z floats, x fastest, written by earlier shaders or
  ///        transfers) into the texture and make it ready for sampling by later compute shaders.
  /// @throw Error when @a src is smaller than the texture.
  void copyFrom(VkCommandBuffer cmd, const Buffer& src) const;

  /// @brief Record: make the texture writable by later compute shaders as a storage image (layout GENERAL), after
  ///        earlier shader and transfer writes. Its old contents, read by earlier shaders, are discarded, or where
  ///        @a keep kept (the texture ready for sampling before: the shaders write only some of its texels).
  /// @throw Error when the texture was made without storage use (see storageSupported).
  void beginShaderWrite(VkCommandBuffer cmd, bool keep = false) const;
  /// @brief Record: the compute shaders' writes done, make the texture ready for sampling by later ones.
  void endShaderWrite(VkCommandBuffer cmd) const;

  /// @brief Record: copy the texture (ready for sampling: after copyFrom or endShaderWrite) into @a dst, x
  ///        fastest, for tests and read-back; the texture stays ready for sampling.
  /// @throw Error when @a dst is smaller than the texture.
  void copyTo(VkCommandBuffer cmd, const Buffer& dst) const;

  /// @brief Whether @a ctx's device filters R32_SFLOAT 3D textures linearly.
  static bool supported(const VulkanContext& ctx);
  /// @brief Whether @a ctx's device also stores to R32_SFLOAT 3D textures from shaders (then every volume
  ///        is made for storage use too).
  static bool storageSupported(const VulkanContext& ctx);

  VkImageView view() const { return mView.get(); }
  VkSampler sampler() const { return mSampler.get(); }
  glm::uvec3 dims() const { return mDims; }
  const std::string& name() const { return mName; }
  explicit operator bool() const { return bool(mImage); }

private:
  // Destroyed in reverse order: sampler, view, image, memory.
  UniqueHandle<vkFreeMemory> mMemory;
  DeviceMemoryCharge mCharge;
  UniqueHandle<vkDestroyImage> mImage;
  UniqueHandle<vkDestroyImageView> mView;
  UniqueHandle<vkDestroySampler> mSampler;
  glm::uvec3 mDims{0};
  std::string mName;
  bool mStorage = false;
};

/// @brief What a compute pipeline binds at one binding: a storage buffer, or a volume (sampled, or a storage
///        image where the pipeline's layout says VK_DESCRIPTOR_TYPE_STORAGE_IMAGE).
struct Binding {
  Binding() = default;                           ///< unset: a dispatch with an unset binding throws
  Binding(const Buffer* b) : buffer(b) {}        // NOLINT(google-explicit-constructor): {&a, &b} lists
  Binding(const SampledVolume* v) : volume(v) {} // NOLINT(google-explicit-constructor)
  const Buffer* buffer = nullptr;
  const SampledVolume* volume = nullptr;
};

/// @brief A primary command buffer from its own pool, begun on construction. submitAndWait() for one-off work;
///        submit(), wait() and restart() for a frame loop that records into one buffer frame after frame without
///        waiting inside the frame. Destruction waits for a pending submission. Move-only.
class CommandBuffer {
public:
  explicit CommandBuffer(const VulkanContext& ctx);
  ~CommandBuffer();
  CommandBuffer(CommandBuffer&&) = default;
  CommandBuffer& operator=(CommandBuffer&&) = default;

  VkCommandBuffer handle() const { return mCmd; }
  /// @brief End recording, submit to the context's queue and wait (with a timeout, never forever).
  /// @throw VulkanError on failure or when the GPU does not finish within @a timeoutSeconds.
  void submitAndWait(double timeoutSeconds = 600.0);
  /// @brief End recording and submit to the context's queue without waiting.
  /// @param wait, waitStage a semaphore the work waits for at that stage (a swapchain image's acquisition);
  /// @param signal a semaphore signalled when the work is done (the image's presentation waits for it).
  /// @throw Error when not recording; VulkanError on failure.
  void submit(VkSemaphore wait = VK_NULL_HANDLE, VkPipelineStageFlags waitStage = 0,
              VkSemaphore signal = VK_NULL_HANDLE);
  /// @brief Wait for the last submit() to finish (no-op when none is pending).
  /// @throw VulkanError on failure or when the GPU does not finish within @a timeoutSeconds.
  void wait(double timeoutSeconds = 600.0);
  /// @brief Whether a submission has not been waited for.
  bool pending() const { return mPending; }
  /// @brief Whether commands can be recorded (begun, not yet submitted).
  bool recording() const { return mRecording; }
  /// @brief Wait for the last submission, then begin recording again (the pool's memory is reused).
  void restart();

private:
  void begin();
  const VulkanContext* mCtx = nullptr;
  UniqueHandle<vkDestroyCommandPool> mPool; // destroyed last; frees mCmd (recording or not)
  VkCommandBuffer mCmd = VK_NULL_HANDLE;    // owned by mPool
  UniqueHandle<vkDestroyFence> mFence;
  bool mRecording = false;
  bool mPending = false;
};

/// @brief A compute pipeline from an embedded shader whose bindings 0..n-1 are storage buffers (or, where
///        given, combined image samplers), bound by push descriptors, with an optional push-constant block.
///        Move-only. Pipelines of the same shader, bindings and push block alive at once share their Vulkan
///        objects (VulkanContext::shared: push descriptors leave no state in them), compiled once.
class ComputePipeline {
public:
  ComputePipeline() = default;
  ComputePipeline(ComputePipeline&&) = default;
  ComputePipeline& operator=(ComputePipeline&&) = default;
  ComputePipeline(const ComputePipeline&) = delete;
  ComputePipeline& operator=(const ComputePipeline&) = delete;
  /// @brief Bindings 0..storageBuffers-1 are all storage buffers.
  ComputePipeline(const VulkanContext& ctx, const std::string& shader, std::uint32_t storageBuffers,
                  std::uint32_t pushConstantBytes);
  /// @brief Binding i has descriptor type @a bindings[i]: VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
  ///        VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER (a SampledVolume, sampled) or VK_DESCRIPTOR_TYPE_STORAGE_IMAGE
  ///        (a SampledVolume between beginShaderWrite and endShaderWrite).
  ComputePipeline(const VulkanContext& ctx, const std::string& shader, std::vector<VkDescriptorType> bindings,
                  std::uint32_t pushConstantBytes);

  /// @brief Record: bind @a bindings (in binding order: a braced list {&a, &b}, or a std::array a pass fills by
  ///        the named binding indices of its shared header, gpu/shared/*.h), push @a push, dispatch @a groups.
  /// @note @a push must point at exactly the pushConstantBytes given at creation (or be null when 0).
  /// @throw Error when a binding is unset or its kind differs from the pipeline's layout.
  void dispatch(VkCommandBuffer cmd, std::initializer_list<Binding> bindings, const void* push,
                glm::uvec3 groups) const {
    record(cmd, bindings.begin(), bindings.size(), push, &groups, nullptr);
  }
  template <std::size_t N>
  void dispatch(VkCommandBuffer cmd, const std::array<Binding, N>& bindings, const void* push,
                glm::uvec3 groups) const {
    record(cmd, bindings.data(), N, push, &groups, nullptr);
  }
  /// @brief The same with the group counts read on the GPU from @a indirect (a VkDispatchIndirectCommand at
  ///        byte @a offset, a multiple of 4; the buffer needs VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT).
  template <std::size_t N>
  void dispatchIndirect(VkCommandBuffer cmd, const std::array<Binding, N>& bindings, const void* push,
                        const Buffer& indirect, VkDeviceSize offset = 0) const {
    record(cmd, bindings.data(), N, push, nullptr, &indirect, offset);
  }
  const std::string& name() const { return mName; }

private:
  /// Bind, push, then dispatch @a groups or, where given, indirectly from @a indirect at byte @a offset.
  void record(VkCommandBuffer cmd, const Binding* bindings, std::size_t count, const void* push,
              const glm::uvec3* groups, const Buffer* indirect, VkDeviceSize offset = 0) const;
  const VulkanContext* mCtx = nullptr;
  std::string mName;
  std::vector<VkDescriptorType> mTypes;
  std::uint32_t mPushBytes = 0;
  struct Compiled {
    // Destroyed in reverse order: pipeline, pipeline layout, set layout, shader module.
    UniqueHandle<vkDestroyShaderModule> module;
    UniqueHandle<vkDestroyDescriptorSetLayout> setLayout;
    UniqueHandle<vkDestroyPipelineLayout> layout;
    UniqueHandle<vkDestroyPipeline> pipeline;
  };
  /// Compile the shader with this pipeline's bindings and push block.
  std::shared_ptr<Compiled> compile() const;
  std::shared_ptr<const Compiled> mCompiled;
};

/// @brief Make every earlier shader and transfer write visible to every later shader and transfer access.
/// @note Between dependent dispatches (e.g. jump-flooding ping-pong). Proven by GPU == CPU tests, since the
///       validation layer misses dispatch-to-dispatch hazards on this driver version.
void computeBarrier(VkCommandBuffer cmd);

/// @brief Make every earlier transfer write visible to the host once the command buffer's fence is waited for (a
///        read-back into host memory that the host reads mapped).
void transferToHostBarrier(VkCommandBuffer cmd);

/// @brief (Re)create @a b when it is empty or smaller than @a bytes (at least 16); keeps it otherwise, so
///        per-frame buffers are allocated once.
void reserve(const VulkanContext& ctx, Buffer& b, VkDeviceSize bytes, VkBufferUsageFlags usage, Buffer::Memory memory,
             const std::string& name);

/// @brief Copy @a bytes from host memory into @a dst (through a staging buffer when it is device memory).
void upload(const VulkanContext& ctx, const Buffer& dst, const void* data, std::size_t bytes);
/// @brief reserve() device memory of at least @a bytes in @a b (grown, never shrunk), then upload() @a data.
/// @note For inputs re-sent whenever they change (BVHs, masks): the buffer is reallocated only when it grows.
void reserveAndUpload(const VulkanContext& ctx, Buffer& b, const void* data, std::size_t bytes,
                      VkBufferUsageFlags usage, const std::string& name);
/// @brief Record into @a cmd a copy of @a bytes of host data into @a dst (vkCmdUpdateBuffer, in pieces of at
///        most 64 KiB): the data travels inside the command buffer, so a frame's small inputs (transforms) need no
///        staging buffer and no wait. Later reads need a barrier (computeBarrier).
/// @throw Error when @a bytes is not a multiple of 4 or exceeds the buffer.
void recordUpload(VkCommandBuffer cmd, const Buffer& dst, const void* data, std::size_t bytes);
/// @brief Copy @a bytes of @a src into host memory (through a staging buffer when it is device memory).
void download(const VulkanContext& ctx, const Buffer& src, void* data, std::size_t bytes);

/// @brief Ceiling division for dispatch sizes.
inline std::uint32_t groupsFor(std::uint64_t n, std::uint32_t groupSize) {
  return std::uint32_t((n + groupSize - 1) / groupSize);
}

} // namespace rtsdf::gpu
