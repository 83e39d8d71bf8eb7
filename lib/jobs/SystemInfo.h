#pragma once
/// @file SystemInfo.h
/// @brief What rtsdf runs on: library versions, embedded shaders, Vulkan devices and their limits.
#include <string>

namespace rtsdf {

/// @brief The report `rtsdf info` prints.
struct SystemInfo {
  std::string text;     ///< versions, shaders, and the devices (or why Vulkan has none)
  bool vulkanOk = true; ///< false when Vulkan could not list devices (no loader or no driver)
};

/// @brief Versions of rtsdf and its libraries, the embedded shaders, and every Vulkan device with its limits.
SystemInfo systemInfo();

} // namespace rtsdf
