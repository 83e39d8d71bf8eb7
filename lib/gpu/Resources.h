#pragma once
/// @file Resources.h
/// @brief Move-only RAII owners of the Vulkan objects rtsdf's compute passes use: buffers, one-shot
///        command buffers, compute pipelines (push descriptors, push constants) and barriers.
#include "gpu/VulkanContext.h"

#include <glm/glm.hpp>

#include <cstddef>
#include <initializer_list>
#include <string>

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

/// @brief A compute pipeline from an embedded shader whose bindings 0..n-1 are all storage buffers, bound
///        by push descriptors, with an optional push-constant block.
class ComputePipeline {
public:
  ComputePipeline() = default;
  ComputePipeline(const VulkanContext& ctx, const std::string& shader, std::uint32_t storageBuffers,
                  std::uint32_t pushConstantBytes);
  ~ComputePipeline();
  ComputePipeline(ComputePipeline&& other) noexcept;
  ComputePipeline& operator=(ComputePipeline&& other) noexcept;
  ComputePipeline(const ComputePipeline&) = delete;
  ComputePipeline& operator=(const ComputePipeline&) = delete;

  /// @brief Record: bind, push @a buffers to bindings 0.. in order and @a push constants, dispatch @a groups.
  /// @note @a push must point at exactly the pushConstantBytes given at creation (or be null when 0).
  void dispatch(VkCommandBuffer cmd, std::initializer_list<const Buffer*> buffers, const void* push,
                glm::uvec3 groups) const;
  /// @brief The same with the group counts read on the GPU from @a indirect (a VkDispatchIndirectCommand at
  ///        offset 0; the buffer needs VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT).
  void dispatchIndirect(VkCommandBuffer cmd, std::initializer_list<const Buffer*> buffers, const void* push,
                        const Buffer& indirect) const;
  const std::string& name() const { return mName; }

private:
  void bind(VkCommandBuffer cmd, std::initializer_list<const Buffer*> buffers, const void* push) const;
  void reset();
  const VulkanContext* mCtx = nullptr;
  std::string mName;
  std::uint32_t mBindings = 0, mPushBytes = 0;
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

/// @brief Copy @a bytes from host memory into @a dst (through a staging buffer when it is device memory).
void upload(const VulkanContext& ctx, const Buffer& dst, const void* data, std::size_t bytes);
/// @brief Copy @a bytes of @a src into host memory (through a staging buffer when it is device memory).
void download(const VulkanContext& ctx, const Buffer& src, void* data, std::size_t bytes);

/// @brief Ceiling division for dispatch sizes.
inline std::uint32_t groupsFor(std::uint64_t n, std::uint32_t groupSize) {
  return std::uint32_t((n + groupSize - 1) / groupSize);
}

} // namespace rtsdf::gpu
