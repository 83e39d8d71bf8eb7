#pragma once
/// @file UniqueHandle.h
/// @brief The one move-only owner of a Vulkan device object that rtsdf's RAII wrappers are made of: it
///        destroys the object through its context and keeps the context's live-object count (leak report).
#include "gpu/VulkanContext.h"
#include "gpu/VulkanError.h"

#include <cstdint>
#include <string>
#include <utility>

namespace rtsdf::gpu {

namespace detail {
/// The handle type a vkDestroyXxx / vkFreeMemory function takes.
template <class DestroyFn>
struct DestroyedHandle;
template <class H>
struct DestroyedHandle<void(VKAPI_PTR*)(VkDevice, H, const VkAllocationCallbacks*)> {
  using type = H;
};
} // namespace detail

/// @brief Owns one device object, destroyed with @a Destroy (vkDestroyBuffer, vkFreeMemory, ...) on reset,
///        destruction or move assignment; the handle type follows from @a Destroy: UniqueHandle<vkDestroyBuffer>
///        owns a VkBuffer.
/// @note Counts +1 on the context when it takes an object and -1 when it destroys it, so every live object
///       shows in VulkanContext::liveObjects(). Wrappers made of UniqueHandles (and plain values) need no
///       hand-written destructor or move operations; they destroy their objects in reverse member order.
template <auto Destroy>
class UniqueHandle {
public:
  using Handle = typename detail::DestroyedHandle<decltype(Destroy)>::type;
  /// @brief vkCreateXxx(device, &info, nullptr, &handle): the shape of most Vulkan create functions.
  template <class Info>
  using CreateFn = VkResult(VKAPI_PTR*)(VkDevice, const Info*, const VkAllocationCallbacks*, Handle*);

  UniqueHandle() = default;
  ~UniqueHandle() { reset(); }
  UniqueHandle(UniqueHandle&& other) noexcept
      : mCtx(other.mCtx), mHandle(std::exchange(other.mHandle, Handle(VK_NULL_HANDLE))) {}
  UniqueHandle& operator=(UniqueHandle&& other) noexcept {
    if (this != &other) {
      reset();
      mCtx = other.mCtx;
      mHandle = std::exchange(other.mHandle, Handle(VK_NULL_HANDLE));
    }
    return *this;
  }
  UniqueHandle(const UniqueHandle&) = delete;
  UniqueHandle& operator=(const UniqueHandle&) = delete;

  /// @brief Create the object with @a create from @a info, replacing (destroying) any owned one on success.
  /// @throw VulkanError (with the VkResult) naming @a what when creation fails; the owned object is kept.
  template <class Info>
  void create(const VulkanContext& ctx, CreateFn<Info> create, const Info& info, const std::string& what) {
    Handle handle = VK_NULL_HANDLE;
    check(create(ctx.device(), &info, nullptr, &handle), what.c_str());
    reset(ctx, handle);
  }
  /// @brief Destroy the owned object (if any) and own @a handle, just made on @a ctx's device (for create
  ///        functions of another shape). A null handle leaves it empty.
  void reset(const VulkanContext& ctx, Handle handle) noexcept {
    reset();
    mCtx = &ctx;
    mHandle = handle;
    if (mHandle != VK_NULL_HANDLE) ctx.trackObject(+1);
  }
  /// @brief Destroy the owned object now (no-op when empty).
  void reset() noexcept {
    if (mHandle == VK_NULL_HANDLE) return;
    Destroy(mCtx->device(), mHandle, nullptr);
    mCtx->trackObject(-1);
    mHandle = VK_NULL_HANDLE;
  }

  Handle get() const { return mHandle; }
  /// @brief Address of the handle, for Vulkan calls that take arrays of handles (count 1).
  const Handle* address() const { return &mHandle; }
  explicit operator bool() const { return mHandle != VK_NULL_HANDLE; }

private:
  const VulkanContext* mCtx = nullptr;
  Handle mHandle = VK_NULL_HANDLE;
};

/// @brief Device-local bytes charged to a context while held (VulkanContext::deviceBytesInUse): a Buffer or
///        SampledVolume holds one beside its memory, so the context knows what its objects hold. Move-only.
class DeviceMemoryCharge {
public:
  DeviceMemoryCharge() = default;
  DeviceMemoryCharge(const VulkanContext& ctx, std::uint64_t bytes) : mCtx(&ctx), mBytes(bytes) {
    ctx.trackDeviceBytes(std::int64_t(bytes));
  }
  ~DeviceMemoryCharge() { release(); }
  DeviceMemoryCharge(DeviceMemoryCharge&& other) noexcept
      : mCtx(std::exchange(other.mCtx, nullptr)), mBytes(std::exchange(other.mBytes, 0)) {}
  DeviceMemoryCharge& operator=(DeviceMemoryCharge&& other) noexcept {
    if (this != &other) {
      release();
      mCtx = std::exchange(other.mCtx, nullptr);
      mBytes = std::exchange(other.mBytes, 0);
    }
    return *this;
  }
  DeviceMemoryCharge(const DeviceMemoryCharge&) = delete;
  DeviceMemoryCharge& operator=(const DeviceMemoryCharge&) = delete;

private:
  void release() noexcept {
    if (mCtx) mCtx->trackDeviceBytes(-std::int64_t(mBytes));
    mCtx = nullptr;
  }
  const VulkanContext* mCtx = nullptr;
  std::uint64_t mBytes = 0;
};

} // namespace rtsdf::gpu
