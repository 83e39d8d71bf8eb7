#include "view/Window.h"

#include "render/compose/ComposeParams.h"
#include "util/Error.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <mutex>

namespace rtsdf {
namespace {
std::mutex gGlfwMutex;
std::string gGlfwError; // the last message of GLFW's error callback

void onGlfwError(int code, const char* message) {
  std::lock_guard<std::mutex> lock(gGlfwMutex);
  gGlfwError = fmt::format("{} (GLFW error 0x{:x})", message ? message : "unknown", code);
}

std::string lastGlfwError() {
  std::lock_guard<std::mutex> lock(gGlfwMutex);
  return gGlfwError.empty() ? "no reason given" : gGlfwError;
}

Window* windowOf(GLFWwindow* w) { return static_cast<Window*>(glfwGetWindowUserPointer(w)); }
} // namespace

Window::Window(int width, int height, const std::string& title) {
  glfwSetErrorCallback(onGlfwError);
  if (!glfwInit())
    throw Error(fmt::format("no window system: {}; the viewer needs an X11 display (over SSH or on a server: "
                            "xvfb-run rtsdf view ...)",
                            lastGlfwError()));
  if (!glfwVulkanSupported()) {
    glfwTerminate();
    throw Error("no window system for Vulkan: GLFW found no Vulkan loader that can draw into windows");
  }
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
  mWindow = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!mWindow) {
    const std::string why = lastGlfwError();
    glfwTerminate();
    throw Error(fmt::format("no window system: cannot open a {}x{} window: {}", width, height, why));
  }
  glfwSetWindowUserPointer(mWindow, this);
  glfwSetKeyCallback(mWindow, [](GLFWwindow* w, int key, int, int action, int mods) {
    if (action == GLFW_PRESS || action == GLFW_REPEAT)
      windowOf(w)->mInput.keys.emplace_back(key, (mods & GLFW_MOD_SHIFT) != 0);
  });
  glfwSetScrollCallback(mWindow, [](GLFWwindow* w, double, double dy) { windowOf(w)->mInput.scroll += dy; });
  glfwSetMouseButtonCallback(mWindow, [](GLFWwindow* w, int button, int action, int) {
    if (button == GLFW_MOUSE_BUTTON_LEFT) windowOf(w)->mDragging = action == GLFW_PRESS;
  });
  glfwSetCursorPosCallback(mWindow, [](GLFWwindow* w, double x, double y) {
    Window* self = windowOf(w);
    const glm::dvec2 now(x, y);
    if (self->mDragging) self->mInput.drag += now - self->mCursor;
    self->mCursor = now;
  });
}

Window::~Window() {
  if (mWindow) glfwDestroyWindow(mWindow);
  glfwTerminate();
}

std::vector<std::string> Window::requiredInstanceExtensions() {
  std::uint32_t n = 0;
  const char** names = glfwGetRequiredInstanceExtensions(&n);
  if (!names) throw Error(fmt::format("no window system for Vulkan: {}", lastGlfwError()));
  return std::vector<std::string>(names, names + n);
}

glm::ivec2 Window::framebufferSize() const {
  int w = 0, h = 0;
  glfwGetFramebufferSize(mWindow, &w, &h);
  return {w, h};
}

bool Window::closeRequested() const { return glfwWindowShouldClose(mWindow) != 0; }

void Window::setTitle(const std::string& title) { glfwSetWindowTitle(mWindow, title.c_str()); }

WindowInput Window::pollEvents() {
  glfwPollEvents();
  return std::exchange(mInput, WindowInput{});
}

namespace {
VkSurfaceFormatKHR chooseFormat(VkPhysicalDevice pd, VkSurfaceKHR surface, std::uint32_t& byteOrder) {
  std::uint32_t n = 0;
  gpu::check(vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface, &n, nullptr), "listing the window's formats");
  std::vector<VkSurfaceFormatKHR> formats(n);
  gpu::check(vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface, &n, formats.data()), "listing the window's formats");
  // ComposePass writes sRGB-encoded bytes and the copy moves them as they are: UNORM and SRGB formats both show
  // them right (an SRGB image's bytes are read as sRGB-encoded).
  for (const VkSurfaceFormatKHR& f : formats) {
    if (f.format == VK_FORMAT_B8G8R8A8_UNORM || f.format == VK_FORMAT_B8G8R8A8_SRGB) {
      byteOrder = gpu::shared::kComposeBgra;
      return f;
    }
    if (f.format == VK_FORMAT_R8G8B8A8_UNORM || f.format == VK_FORMAT_R8G8B8A8_SRGB) {
      byteOrder = gpu::shared::kComposeRgba;
      return f;
    }
  }
  throw Error(fmt::format("the window offers no 8-bit RGBA or BGRA swapchain format ({} formats)", n));
}

VkPresentModeKHR choosePresentMode(VkPhysicalDevice pd, VkSurfaceKHR surface) {
  std::uint32_t n = 0;
  gpu::check(vkGetPhysicalDeviceSurfacePresentModesKHR(pd, surface, &n, nullptr), "listing present modes");
  std::vector<VkPresentModeKHR> modes(n);
  gpu::check(vkGetPhysicalDeviceSurfacePresentModesKHR(pd, surface, &n, modes.data()), "listing present modes");
  // Mailbox shows the newest picture without tearing or waiting for the display; FIFO is always there.
  return std::find(modes.begin(), modes.end(), VK_PRESENT_MODE_MAILBOX_KHR) != modes.end() ? VK_PRESENT_MODE_MAILBOX_KHR
                                                                                         : VK_PRESENT_MODE_FIFO_KHR;
}
} // namespace

Swapchain::Swapchain(const gpu::VulkanContext& ctx, const Window& window) : mCtx(ctx), mCmd(ctx) {
  gpu::check(glfwCreateWindowSurface(ctx.instance(), window.handle(), nullptr, &mSurface),
             "creating the window's Vulkan surface");
  try {
    VkBool32 presentable = VK_FALSE;
    gpu::check(vkGetPhysicalDeviceSurfaceSupportKHR(ctx.physicalDevice(), ctx.queueFamily(), mSurface, &presentable),
               "asking whether the queue can present");
    if (!presentable)
      throw Error(fmt::format("{}: its compute queue cannot present to this window", ctx.info().name));
    VkSurfaceCapabilitiesKHR caps{};
    gpu::check(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(ctx.physicalDevice(), mSurface, &caps),
               "reading the window's surface capabilities");
    if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT))
      throw Error("the window's swapchain images cannot be copied into (no VK_IMAGE_USAGE_TRANSFER_DST_BIT)");
    const VkSurfaceFormatKHR format = chooseFormat(ctx.physicalDevice(), mSurface, mByteOrder);
    VkExtent2D extent = caps.currentExtent;
    if (extent.width == std::numeric_limits<std::uint32_t>::max()) {
      const glm::ivec2 fb = window.framebufferSize();
      extent = {std::uint32_t(fb.x), std::uint32_t(fb.y)};
    }
    mExtent = glm::ivec2(int(extent.width), int(extent.height));
    VkSwapchainCreateInfoKHR sci{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    sci.surface = mSurface;
    sci.minImageCount = caps.maxImageCount ? std::min(caps.minImageCount + 1, caps.maxImageCount) : caps.minImageCount + 1;
    sci.imageFormat = format.format;
    sci.imageColorSpace = format.colorSpace;
    sci.imageExtent = extent;
    sci.imageArrayLayers = 1;
    sci.imageUsage = VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    sci.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    sci.preTransform = caps.currentTransform;
    sci.compositeAlpha = (caps.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR)
                             ? VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR
                             : VkCompositeAlphaFlagBitsKHR(caps.supportedCompositeAlpha & -caps.supportedCompositeAlpha);
    sci.presentMode = choosePresentMode(ctx.physicalDevice(), mSurface);
    sci.clipped = VK_TRUE;
    mSwapchain.create(ctx, vkCreateSwapchainKHR, sci, "creating the window's swapchain");
    std::uint32_t n = 0;
    gpu::check(vkGetSwapchainImagesKHR(ctx.device(), mSwapchain.get(), &n, nullptr), "listing swapchain images");
    mImages.resize(n);
    gpu::check(vkGetSwapchainImagesKHR(ctx.device(), mSwapchain.get(), &n, mImages.data()), "listing swapchain images");
    const VkSemaphoreCreateInfo semaphore{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    mAcquired.create(ctx, vkCreateSemaphore, semaphore, "creating a semaphore");
    mRendered.resize(n);
    for (auto& s : mRendered) s.create(ctx, vkCreateSemaphore, semaphore, "creating a semaphore");
  } catch (...) {
    mRendered.clear();
    mAcquired.reset();
    mSwapchain.reset();
    vkDestroySurfaceKHR(ctx.instance(), mSurface, nullptr);
    throw;
  }
}

Swapchain::~Swapchain() {
  waitIdle();
  mRendered.clear();
  mAcquired.reset();
  mSwapchain.reset();
  vkDestroySurfaceKHR(mCtx.instance(), mSurface, nullptr);
}

void Swapchain::waitForFrame() { mCmd.wait(); }

void Swapchain::waitIdle() {
  try {
    mCmd.wait();
  } catch (const std::exception&) {
    // Shutting down: nothing more can be done about a failed wait.
  }
  vkQueueWaitIdle(mCtx.queue()); // presentation, which no fence covers
}

void Swapchain::recordCopy(VkCommandBuffer cmd, const gpu::Buffer& pixels, std::uint32_t image) const {
  VkImageMemoryBarrier toCopy{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  toCopy.srcAccessMask = 0;
  toCopy.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  toCopy.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  toCopy.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
  toCopy.srcQueueFamilyIndex = toCopy.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  toCopy.image = mImages[image];
  toCopy.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  VkBufferMemoryBarrier written{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER};
  written.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
  written.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
  written.srcQueueFamilyIndex = written.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  written.buffer = pixels.handle();
  written.size = VK_WHOLE_SIZE;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 1, &written, 1, &toCopy);
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {std::uint32_t(mExtent.x), std::uint32_t(mExtent.y), 1};
  vkCmdCopyBufferToImage(cmd, pixels.handle(), mImages[image], VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
  VkImageMemoryBarrier toPresent = toCopy;
  toPresent.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  toPresent.dstAccessMask = 0;
  toPresent.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
  toPresent.newLayout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, 0, 0, nullptr, 0,
                       nullptr, 1, &toPresent);
}

bool Swapchain::present(const std::function<void(VkCommandBuffer)>& record, const gpu::Buffer& pixels) {
  if (!mCmd.recording()) mCmd.restart(); // waits for the previous frame: its semaphores and buffers are free again
  std::uint32_t image = 0;
  const VkResult acquired = vkAcquireNextImageKHR(mCtx.device(), mSwapchain.get(), std::uint64_t(10e9),
                                                  mAcquired.get(), VK_NULL_HANDLE, &image);
  if (acquired == VK_ERROR_OUT_OF_DATE_KHR) return false;
  if (acquired != VK_SUBOPTIMAL_KHR) gpu::check(acquired, "acquiring a swapchain image");
  record(mCmd.handle());
  recordCopy(mCmd.handle(), pixels, image);
  mCmd.submit(mAcquired.get(), VK_PIPELINE_STAGE_TRANSFER_BIT, mRendered[image].get());
  VkPresentInfoKHR pi{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
  pi.waitSemaphoreCount = 1;
  pi.pWaitSemaphores = mRendered[image].address();
  pi.swapchainCount = 1;
  pi.pSwapchains = mSwapchain.address();
  pi.pImageIndices = &image;
  const VkResult presented = vkQueuePresentKHR(mCtx.queue(), &pi);
  if (presented == VK_ERROR_OUT_OF_DATE_KHR || presented == VK_SUBOPTIMAL_KHR) return presented == VK_SUBOPTIMAL_KHR;
  gpu::check(presented, "presenting a swapchain image");
  return true;
}

} // namespace rtsdf
