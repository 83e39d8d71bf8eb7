#pragma once
/// @file VulkanContext.h
/// @brief Vulkan instance and device choice for compute: prefers a discrete GPU, then any GPU, then a CPU
///        device (Mesa lavapipe); optional validation layers with a device-lifetime messenger that counts
///        errors.
#include <glm/glm.hpp>
#include <vulkan/vulkan.h>

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace rtsdf::gpu {

/// @brief What rtsdf needs to know about a physical device.
struct DeviceInfo {
  std::uint32_t index = 0;
  std::string name;
  std::string typeName; ///< "discrete", "integrated", "virtual", "cpu" or "other"
  VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
  std::uint32_t apiVersion = 0;
  std::string driver;
  std::uint64_t maxStorageBufferRange = 0;
  std::uint32_t maxComputeSharedMemory = 0;
  std::uint32_t maxComputeInvocations = 0;
  glm::uvec3 maxWorkGroupCount{0};
  std::uint32_t maxImageDimension3D = 0;
  std::uint32_t subgroupSize = 0;
  /// Compute shaders may use subgroup ballots and arithmetic (MaskCompactPass reserves its list slots by subgroup).
  bool computeSubgroupBallot = false;
  float timestampPeriodNs = 0.0f;
  bool computeTimestamps = false;
  std::uint64_t deviceLocalBytes = 0;
};

/// @brief Options for creating a VulkanContext.
struct ContextOptions {
  /// Device by index or by a case-insensitive substring of its name; empty picks the best one.
  std::string device;
  /// Enable VK_LAYER_KHRONOS_validation and count its errors. The default follows the environment
  /// variable RTSDF_VALIDATION (1 = on), which the test suite sets.
  bool validation = validationRequestedByEnvironment();
  /// With validation, also synchronization validation. Default: RTSDF_SYNC_VALIDATION=1 (a CI step).
  bool syncValidation = syncValidationRequestedByEnvironment();
  /// Instance extensions to enable besides rtsdf's own (a window's surface extensions, for a swapchain).
  std::vector<std::string> instanceExtensions;
  /// Device extensions to enable besides rtsdf's own (VK_KHR_swapchain); a device without one is refused.
  std::vector<std::string> deviceExtensions;
  static bool validationRequestedByEnvironment();
  static bool syncValidationRequestedByEnvironment();
};

/// @brief The devices Vulkan reports, in its order, without creating a device.
/// @throw VulkanError with a clear message when no Vulkan driver or device is present.
std::vector<DeviceInfo> listDevices();

/// @brief Index of the device rtsdf would choose among @a devices for @a request (see ContextOptions).
/// @throw Error when the request matches none.
std::uint32_t chooseDevice(const std::vector<DeviceInfo>& devices, const std::string& request);

/// @brief A Vulkan instance and a logical device with one compute queue. Neither copied nor moved: the
///        RAII wrappers keep a pointer to their context (hold it in a std::unique_ptr to pass it around).
class VulkanContext {
public:
  explicit VulkanContext(const ContextOptions& options = {});
  ~VulkanContext();
  VulkanContext(VulkanContext&&) = delete;
  VulkanContext& operator=(VulkanContext&&) = delete;
  VulkanContext(const VulkanContext&) = delete;
  VulkanContext& operator=(const VulkanContext&) = delete;

  VkInstance instance() const { return mInstance; }
  VkPhysicalDevice physicalDevice() const { return mPhysical; }
  VkDevice device() const { return mDevice; }
  VkQueue queue() const { return mQueue; }
  std::uint32_t queueFamily() const { return mQueueFamily; }
  const DeviceInfo& info() const { return mInfo; }
  bool validationEnabled() const { return mMessenger != VK_NULL_HANDLE; }
  /// @brief Destroy the device and the instance now, before the context itself: the validation layer reports
  ///        objects still alive at vkDestroyDevice, and those errors are counted. The counts stay readable;
  ///        nothing else may be used after. Every object made on this context must be destroyed first.
  void close();
  /// @brief Validation errors reported since the context was created (those at close() included).
  std::uint32_t validationErrors() const;
  /// @brief The last validation error message (empty if none).
  std::string lastValidationMessage() const;

  /// @brief Create a shader module from an embedded shader (embeddedShader(@a name)). The caller owns it.
  VkShaderModule createShaderModule(const std::string& name) const;

  /// @brief Index of a memory type allowed by @a typeBits with all of @a properties.
  /// @throw VulkanError when there is none.
  std::uint32_t memoryType(std::uint32_t typeBits, VkMemoryPropertyFlags properties) const;
  /// @brief vkCmdPushDescriptorSetKHR (VK_KHR_push_descriptor is required and enabled).
  PFN_vkCmdPushDescriptorSetKHR pushDescriptorSet() const { return mPushDescriptorSet; }

  /// @brief The objects stored under @a key while some holder still keeps them, else those @a make returns (then
  ///        stored under @a key). A cache of weak references: compute pipelines of the same shader and layout are
  ///        compiled once for every pass alive that uses them (compiling is nearly all of a pipeline's set-up: 130
  ///        ms for one cascade level's passes on lavapipe), and destroyed with their last holder as before.
  std::shared_ptr<void> shared(const std::string& key, const std::function<std::shared_ptr<void>()>& make) const;

  /// @brief Objects created through the RAII wrappers and not yet destroyed; a leak report is logged at
  ///        shutdown when it is not zero.
  std::int64_t liveObjects() const;
  /// @brief Called by the wrappers: +1 on creation, -1 on destruction.
  void trackObject(int delta) const;
  /// @brief Bytes of device-local memory allocated through the RAII wrappers (Buffer, SampledVolume) and not yet
  ///        freed: what the objects on this context hold, as the driver sized them (alignment included).
  std::uint64_t deviceBytesInUse() const;
  /// @brief Called by the wrappers: + the bytes of a device-local allocation, - the same when it is freed.
  void trackDeviceBytes(std::int64_t delta) const;

private:
  void release();
  struct Messages;
  VkInstance mInstance = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT mMessenger = VK_NULL_HANDLE;
  VkPhysicalDevice mPhysical = VK_NULL_HANDLE;
  VkDevice mDevice = VK_NULL_HANDLE;
  VkQueue mQueue = VK_NULL_HANDLE;
  std::uint32_t mQueueFamily = 0;
  DeviceInfo mInfo;
  Messages* mMessages = nullptr;
  PFN_vkCmdPushDescriptorSetKHR mPushDescriptorSet = nullptr;
  VkPhysicalDeviceMemoryProperties mMemory{};
  mutable std::mutex mSharedMutex;
  mutable std::map<std::string, std::weak_ptr<void>> mShared;
};

} // namespace rtsdf::gpu
