#pragma once
/// @file VulkanError.h
/// @brief Vulkan failures as exceptions that carry the VkResult and what was being attempted.
#include "util/Error.h"

#include <vulkan/vulkan.h>

#include <string>

namespace rtsdf::gpu {

/// @brief A failed Vulkan call: the result code and the reason.
class VulkanError : public Error {
public:
  VulkanError(VkResult result, const std::string& what);
  VkResult result() const { return mResult; }

private:
  VkResult mResult;
};

/// @brief Name of a VkResult, e.g. "VK_ERROR_OUT_OF_DEVICE_MEMORY".
const char* resultName(VkResult result);

/// @brief Throw VulkanError unless @a result is VK_SUCCESS.
inline void check(VkResult result, const char* what) {
  if (result != VK_SUCCESS) throw VulkanError(result, what);
}

} // namespace rtsdf::gpu
