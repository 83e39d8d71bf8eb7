#pragma once
/// @file Window.h
/// @brief A GLFW window without a client API and the Vulkan swapchain that shows pictures in it: the viewer's
///        only contact with the window system.
#include "gpu/Resources.h"
#include "gpu/UniqueHandle.h"

#include <glm/glm.hpp>

#include <functional>
#include <string>
#include <vector>

struct GLFWwindow;

namespace rtsdf {

/// @brief What the window saw since the last pollEvents().
struct WindowInput {
  std::vector<std::pair<int, bool>> keys; ///< GLFW key codes pressed, with Shift held or not, in order
  glm::dvec2 drag{0.0};                   ///< cursor motion in pixels while the left button was held
  double scroll = 0.0;                    ///< wheel steps (positive: away from the user)
};

/// @brief A window of a fixed size (GLFW, no client API: Vulkan draws into it).
class Window {
public:
  /// @throw Error "no window system ..." when GLFW cannot start (no X11 display) or finds no Vulkan loader.
  Window(int width, int height, const std::string& title);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  /// @brief The instance extensions a surface of this window needs (for gpu::ContextOptions).
  static std::vector<std::string> requiredInstanceExtensions();
  GLFWwindow* handle() const { return mWindow; }
  /// @brief Pixels the swapchain's images have (may differ from the size asked for on scaled displays).
  glm::ivec2 framebufferSize() const;
  bool closeRequested() const;
  void setTitle(const std::string& title);
  /// @brief Process the window system's events; returns what the user did since the last call.
  WindowInput pollEvents();

private:
  GLFWwindow* mWindow = nullptr;
  WindowInput mInput;
  glm::dvec2 mCursor{0.0};
  bool mDragging = false;
};

/// @brief The window's surface and swapchain: each present() copies a buffer of packed 8-bit pixels (ComposePass's
///        output) into the next image and presents it. One frame in flight.
class Swapchain {
public:
  /// @throw Error when the context's queue cannot present to the window, or no 8-bit RGBA/BGRA format or
  ///        transfer-destination image is offered; VulkanError with the VkResult otherwise.
  Swapchain(const gpu::VulkanContext& ctx, const Window& window);
  ~Swapchain();
  Swapchain(const Swapchain&) = delete;
  Swapchain& operator=(const Swapchain&) = delete;

  glm::ivec2 extent() const { return mExtent; }
  /// @brief gpu::shared::kComposeRgba or kComposeBgra: the byte order the images expect.
  std::uint32_t byteOrder() const { return mByteOrder; }
  /// @brief Record @a record (the passes that write @a pixels) and the copy of @a pixels into the next image in one
  ///        submission, then present it. Waits for the previous frame's submission first.
  /// @return false when the swapchain is out of date (the window changed): nothing was presented.
  bool present(const std::function<void(VkCommandBuffer)>& record, const gpu::Buffer& pixels);
  /// @brief Wait until the GPU has finished the last frame's submission (its buffers may then change).
  void waitForFrame();
  /// @brief waitForFrame(), then until the queue is idle (presentation included): before destroying anything.
  void waitIdle();

private:
  void recordCopy(VkCommandBuffer cmd, const gpu::Buffer& pixels, std::uint32_t image) const;
  const gpu::VulkanContext& mCtx;
  VkSurfaceKHR mSurface = VK_NULL_HANDLE;
  gpu::UniqueHandle<vkDestroySwapchainKHR> mSwapchain;
  std::vector<VkImage> mImages; // owned by the swapchain
  std::vector<gpu::UniqueHandle<vkDestroySemaphore>> mRendered; // per image: the copy is done, present it
  gpu::UniqueHandle<vkDestroySemaphore> mAcquired;
  gpu::CommandBuffer mCmd;
  glm::ivec2 mExtent{0};
  std::uint32_t mByteOrder = 0;
};

} // namespace rtsdf
