#include "gpu/VulkanContext.h"

#include "gpu/EmbeddedShaders.h"
#include "gpu/VulkanError.h"
#include "util/Text.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <dlfcn.h>
#include <link.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <set>

namespace rtsdf::gpu {
namespace {

const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";


const char* typeName(VkPhysicalDeviceType t) {
  switch (t) {
  case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete";
  case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated";
  case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual";
  case VK_PHYSICAL_DEVICE_TYPE_CPU: return "cpu";
  default: return "other";
  }
}

int typeRank(VkPhysicalDeviceType t) {
  switch (t) {
  case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
  case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
  case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
  case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
  default: return 4;
  }
}

bool layerAvailable(const char* name) {
  std::uint32_t n = 0;
  vkEnumerateInstanceLayerProperties(&n, nullptr);
  std::vector<VkLayerProperties> layers(n);
  vkEnumerateInstanceLayerProperties(&n, layers.data());
  for (const auto& l : layers)
    if (std::strcmp(l.layerName, name) == 0) return true;
  return false;
}

/// The shared objects loaded in the process now (by path).
std::set<std::string> loadedObjects() {
  std::set<std::string> names;
  dl_iterate_phdr(
      [](dl_phdr_info* info, std::size_t, void* out) {
        if (info->dlpi_name && *info->dlpi_name) static_cast<std::set<std::string>*>(out)->insert(info->dlpi_name);
        return 0;
      },
      &names);
  return names;
}

/// Keep the objects that vkCreateInstance loaded (drivers, layers, their LLVM) loaded until the process exits.
/// The loader unloads them at vkDestroyInstance, which loses their one-time state (lavapipe's pthread_once
/// initialisation runs, and allocates, again in every instance) and leaves what their globals held
/// unreachable: LeakSanitizer then reports it as leaked, in stacks of an unloaded library that name nothing.
void keepLoadedSince(const std::set<std::string>& before) {
  for (const std::string& name : loadedObjects())
    if (!before.count(name)) dlopen(name.c_str(), RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
}

VkInstance createInstance(bool validation, bool sync, const std::vector<std::string>& extra,
                          const VkDebugUtilsMessengerCreateInfoEXT* messenger) {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "rtsdf";
  app.pEngineName = "rtsdf";
  app.apiVersion = VK_API_VERSION_1_1;
  std::vector<const char*> layers, extensions;
  if (validation) {
    if (!layerAvailable(kValidationLayer))
      throw Error("Vulkan validation was requested but VK_LAYER_KHRONOS_validation is not installed "
                  "(Debian package vulkan-validationlayers)");
    layers.push_back(kValidationLayer);
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  }
  for (const std::string& e : extra) extensions.push_back(e.c_str());
  sync = sync && validation;
  VkValidationFeatureEnableEXT syncFeature = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
  VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
  features.enabledValidationFeatureCount = 1;
  features.pEnabledValidationFeatures = &syncFeature;
  features.pNext = messenger;
  VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  // The messenger here covers vkCreateInstance itself; a separate messenger covers the device's life.
  ci.pNext = sync ? static_cast<const void*>(&features) : static_cast<const void*>(messenger);
  ci.pApplicationInfo = &app;
  ci.enabledLayerCount = std::uint32_t(layers.size());
  ci.ppEnabledLayerNames = layers.data();
  ci.enabledExtensionCount = std::uint32_t(extensions.size());
  ci.ppEnabledExtensionNames = extensions.data();
  VkInstance instance = VK_NULL_HANDLE;
  const std::set<std::string> loaded = loadedObjects();
  const VkResult r = vkCreateInstance(&ci, nullptr, &instance);
  keepLoadedSince(loaded);
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER)
    throw VulkanError(r, "creating a Vulkan instance: no Vulkan driver is installed (on Debian: mesa-vulkan-drivers "
                         "provides lavapipe)");
  check(r, "creating a Vulkan instance");
  return instance;
}

DeviceInfo describe(VkPhysicalDevice pd, std::uint32_t index) {
  VkPhysicalDeviceSubgroupProperties subgroup{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
  VkPhysicalDeviceProperties2 props2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  props2.pNext = &subgroup;
  vkGetPhysicalDeviceProperties2(pd, &props2);
  const VkPhysicalDeviceProperties& p = props2.properties;
  DeviceInfo info;
  info.index = index;
  info.name = p.deviceName;
  info.type = p.deviceType;
  info.typeName = typeName(p.deviceType);
  info.apiVersion = p.apiVersion;
  info.driver = fmt::format("{}.{}.{}", VK_VERSION_MAJOR(p.driverVersion), VK_VERSION_MINOR(p.driverVersion),
                            VK_VERSION_PATCH(p.driverVersion));
  info.maxStorageBufferRange = p.limits.maxStorageBufferRange;
  info.maxComputeSharedMemory = p.limits.maxComputeSharedMemorySize;
  info.maxComputeInvocations = p.limits.maxComputeWorkGroupInvocations;
  info.maxWorkGroupCount = glm::uvec3(p.limits.maxComputeWorkGroupCount[0], p.limits.maxComputeWorkGroupCount[1],
                                      p.limits.maxComputeWorkGroupCount[2]);
  info.maxImageDimension3D = p.limits.maxImageDimension3D;
  info.subgroupSize = subgroup.subgroupSize;
  const VkSubgroupFeatureFlags ballot = VK_SUBGROUP_FEATURE_BASIC_BIT | VK_SUBGROUP_FEATURE_BALLOT_BIT |
                                        VK_SUBGROUP_FEATURE_ARITHMETIC_BIT;
  info.computeSubgroupBallot = (subgroup.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) &&
                               (subgroup.supportedOperations & ballot) == ballot;
  info.timestampPeriodNs = p.limits.timestampPeriod;
  std::uint32_t nq = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &nq, nullptr);
  std::vector<VkQueueFamilyProperties> qf(nq);
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &nq, qf.data());
  for (const auto& q : qf)
    if ((q.queueFlags & VK_QUEUE_COMPUTE_BIT) && q.timestampValidBits > 0) info.computeTimestamps = true;
  VkPhysicalDeviceMemoryProperties mem;
  vkGetPhysicalDeviceMemoryProperties(pd, &mem);
  for (std::uint32_t h = 0; h < mem.memoryHeapCount; ++h)
    if (mem.memoryHeaps[h].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
      info.deviceLocalBytes = std::max<std::uint64_t>(info.deviceLocalBytes, mem.memoryHeaps[h].size);
  return info;
}

std::vector<VkPhysicalDevice> physicalDevices(VkInstance instance) {
  std::uint32_t n = 0;
  check(vkEnumeratePhysicalDevices(instance, &n, nullptr), "enumerating Vulkan devices");
  std::vector<VkPhysicalDevice> devices(n);
  check(vkEnumeratePhysicalDevices(instance, &n, devices.data()), "enumerating Vulkan devices");
  if (devices.empty())
    throw VulkanError(VK_ERROR_INITIALIZATION_FAILED,
                      "finding a Vulkan device: none present (on Debian: mesa-vulkan-drivers provides lavapipe)");
  return devices;
}

/// A deliberate validation error for the tests that prove every job refuses one (RTSDF_TEST_VALIDATION_ERROR:
/// "now", an invalid shader module at once; "leak", a buffer left alive, reported at vkDestroyDevice). Only in a
/// build with test hooks (RTSDF_TEST_HOOKS, on with the test suite).
void provokeValidationErrorForTests([[maybe_unused]] VkDevice device) {
#ifdef RTSDF_TEST_HOOKS
  const char* v = std::getenv("RTSDF_TEST_VALIDATION_ERROR");
  const std::string kind = v ? v : "";
  if (kind == "now") {
    const std::uint32_t junk[5] = {0x07230203u, 0x00010000u, 0u, 0u, 0u};
    VkShaderModuleCreateInfo ci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    ci.codeSize = sizeof(junk);
    ci.pCode = junk;
    VkShaderModule m = VK_NULL_HANDLE;
    vkCreateShaderModule(device, &ci, nullptr, &m);
    if (m) vkDestroyShaderModule(device, m, nullptr);
  } else if (kind == "leak") {
    VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bi.size = 256;
    bi.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    VkBuffer b = VK_NULL_HANDLE;
    vkCreateBuffer(device, &bi, nullptr, &b);
  }
#endif
}

} // namespace

struct VulkanContext::Messages {
  std::atomic<std::int64_t> live{0};
  std::atomic<std::int64_t> deviceBytes{0};
  std::atomic<std::uint32_t> errors{0};
  std::mutex mutex;
  std::string last;
};


bool ContextOptions::syncValidationRequestedByEnvironment() {
  const char* v = std::getenv("RTSDF_SYNC_VALIDATION");
  return v && std::string(v) == "1";
}

bool ContextOptions::validationRequestedByEnvironment() {
  const char* v = std::getenv("RTSDF_VALIDATION");
  return v && std::string(v) != "0" && std::string(v) != "";
}

std::vector<DeviceInfo> listDevices() {
  VkInstance instance = createInstance(false, false, {}, nullptr);
  std::vector<DeviceInfo> out;
  try {
    const auto devices = physicalDevices(instance);
    for (std::uint32_t i = 0; i < devices.size(); ++i) out.push_back(describe(devices[i], i));
  } catch (...) {
    vkDestroyInstance(instance, nullptr);
    throw;
  }
  vkDestroyInstance(instance, nullptr);
  return out;
}

std::uint32_t chooseDevice(const std::vector<DeviceInfo>& devices, const std::string& request) {
  if (devices.empty()) throw Error("no Vulkan device to choose from");
  if (request.empty()) {
    const auto best = std::min_element(devices.begin(), devices.end(), [](const DeviceInfo& a, const DeviceInfo& b) {
      return typeRank(a.type) < typeRank(b.type);
    });
    return best->index;
  }
  if (std::all_of(request.begin(), request.end(), [](unsigned char c) { return std::isdigit(c); })) {
    const unsigned long i = request.size() > 9 ? devices.size() : std::stoul(request);
    if (i >= devices.size())
      throw SettingError("device", fmt::format("device {}: there are only {} Vulkan device(s) (see 'rtsdf info')",
                                               request, devices.size()));
    return std::uint32_t(i);
  }
  for (const auto& d : devices)
    if (toLower(d.name).find(toLower(request)) != std::string::npos) return d.index;
  throw SettingError("device", fmt::format("device '{}': no Vulkan device has that name (see 'rtsdf info')", request));
}

VulkanContext::VulkanContext(const ContextOptions& options) : mMessages(new Messages) {
  try {
    VkDebugUtilsMessengerCreateInfoEXT mci{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    mci.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT;
    mci.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                      VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    mci.pfnUserCallback = [](VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT,
                             const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) -> VkBool32 {
      auto* m = static_cast<Messages*>(user);
      if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
        ++m->errors;
        std::lock_guard<std::mutex> lock(m->mutex);
        m->last = data->pMessage ? data->pMessage : "";
        spdlog::error("Vulkan validation: {}", m->last);
      } else {
        spdlog::debug("Vulkan validation: {}", data->pMessage ? data->pMessage : "");
      }
      return VK_FALSE;
    };
    mci.pUserData = mMessages;
    mInstance = createInstance(options.validation, options.syncValidation, options.instanceExtensions,
                               options.validation ? &mci : nullptr);
    if (options.validation) {
      auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(mInstance, "vkCreateDebugUtilsMessengerEXT"));
      if (!create) throw VulkanError(VK_ERROR_EXTENSION_NOT_PRESENT, "loading vkCreateDebugUtilsMessengerEXT");
      check(create(mInstance, &mci, nullptr, &mMessenger), "creating the validation messenger");
    }
    const auto devices = physicalDevices(mInstance);
    std::vector<DeviceInfo> infos;
    for (std::uint32_t i = 0; i < devices.size(); ++i) infos.push_back(describe(devices[i], i));
    const std::uint32_t chosen = chooseDevice(infos, options.device);
    mPhysical = devices[chosen];
    mInfo = infos[chosen];

    std::uint32_t nq = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(mPhysical, &nq, nullptr);
    std::vector<VkQueueFamilyProperties> qf(nq);
    vkGetPhysicalDeviceQueueFamilyProperties(mPhysical, &nq, qf.data());
    bool found = false;
    for (std::uint32_t i = 0; i < nq && !found; ++i)
      if (qf[i].queueFlags & VK_QUEUE_COMPUTE_BIT) { mQueueFamily = i; found = true; }
    if (!found) throw VulkanError(VK_ERROR_FEATURE_NOT_PRESENT, fmt::format("finding a compute queue on {}", mInfo.name));
    if (!mInfo.computeSubgroupBallot)
      throw VulkanError(VK_ERROR_FEATURE_NOT_PRESENT,
                        fmt::format("{} lacks subgroup ballots and arithmetic in compute shaders (rtsdf's ray mask "
                                    "reserves its list slots by subgroup)", mInfo.name));

    std::uint32_t next = 0;
    vkEnumerateDeviceExtensionProperties(mPhysical, nullptr, &next, nullptr);
    std::vector<VkExtensionProperties> exts(next);
    vkEnumerateDeviceExtensionProperties(mPhysical, nullptr, &next, exts.data());
    auto has = [&exts](const std::string& name) {
      return std::any_of(exts.begin(), exts.end(), [&name](const VkExtensionProperties& e) {
        return name == e.extensionName;
      });
    };
    if (!has(VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME))
      throw VulkanError(VK_ERROR_EXTENSION_NOT_PRESENT,
                        fmt::format("enabling {} on {} (rtsdf binds buffers with push descriptors)",
                                    VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME, mInfo.name));
    std::vector<const char*> deviceExtensions = {VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};
    for (const std::string& e : options.deviceExtensions) {
      if (!has(e))
        throw VulkanError(VK_ERROR_EXTENSION_NOT_PRESENT, fmt::format("enabling {} on {}", e, mInfo.name));
      deviceExtensions.push_back(e.c_str());
    }

    const float priority = 1.0f;
    VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qci.queueFamilyIndex = mQueueFamily;
    qci.queueCount = 1;
    qci.pQueuePriorities = &priority;
    VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    dci.queueCreateInfoCount = 1;
    dci.pQueueCreateInfos = &qci;
    dci.enabledExtensionCount = std::uint32_t(deviceExtensions.size());
    dci.ppEnabledExtensionNames = deviceExtensions.data();
    check(vkCreateDevice(mPhysical, &dci, nullptr, &mDevice), fmt::format("creating a device on {}", mInfo.name).c_str());
    vkGetDeviceQueue(mDevice, mQueueFamily, 0, &mQueue);
    mPushDescriptorSet = reinterpret_cast<PFN_vkCmdPushDescriptorSetKHR>(
        vkGetDeviceProcAddr(mDevice, "vkCmdPushDescriptorSetKHR"));
    if (!mPushDescriptorSet) throw VulkanError(VK_ERROR_EXTENSION_NOT_PRESENT, "loading vkCmdPushDescriptorSetKHR");
    vkGetPhysicalDeviceMemoryProperties(mPhysical, &mMemory);
    if (options.validation) provokeValidationErrorForTests(mDevice);
    spdlog::debug("Vulkan device: {} ({}){}", mInfo.name, mInfo.typeName, options.validation ? ", validation on" : "");
  } catch (...) {
    release();
    throw;
  }
}

VulkanContext::~VulkanContext() { release(); }

void VulkanContext::close() {
  if (mMessages && mMessages->live.load() != 0)
    spdlog::error("Vulkan: {} object(s) created by rtsdf were still alive at shutdown (leak)",
                  mMessages->live.load());
  const std::uint32_t before = validationErrors();
  if (mDevice) {
    vkDeviceWaitIdle(mDevice);
    vkDestroyDevice(mDevice, nullptr); // the validation layer reports objects left alive here
    mDevice = VK_NULL_HANDLE;
  }
  if (mMessenger) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(mInstance, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy) destroy(mInstance, mMessenger, nullptr);
    mMessenger = VK_NULL_HANDLE;
  }
  if (mInstance) {
    vkDestroyInstance(mInstance, nullptr);
    mInstance = VK_NULL_HANDLE;
  }
  if (validationErrors() > before)
    spdlog::error("Vulkan validation reported {} error(s) while the device was destroyed",
                  validationErrors() - before);
}

void VulkanContext::release() {
  close();
  delete mMessages;
  mMessages = nullptr;
}

std::shared_ptr<void> VulkanContext::shared(const std::string& key,
                                           const std::function<std::shared_ptr<void>()>& make) const {
  const std::lock_guard<std::mutex> lock(mSharedMutex);
  std::weak_ptr<void>& slot = mShared[key];
  std::shared_ptr<void> held = slot.lock();
  if (!held) {
    held = make();
    slot = held;
  }
  return held;
}

std::int64_t VulkanContext::liveObjects() const { return mMessages ? mMessages->live.load() : 0; }

void VulkanContext::trackObject(int delta) const {
  if (mMessages) mMessages->live += delta;
}

std::uint64_t VulkanContext::deviceBytesInUse() const {
  return mMessages ? std::uint64_t(std::max<std::int64_t>(0, mMessages->deviceBytes.load())) : 0;
}

void VulkanContext::trackDeviceBytes(std::int64_t delta) const {
  if (mMessages) mMessages->deviceBytes += delta;
}

std::uint32_t VulkanContext::memoryType(std::uint32_t typeBits, VkMemoryPropertyFlags properties) const {
  for (std::uint32_t i = 0; i < mMemory.memoryTypeCount; ++i)
    if ((typeBits & (1u << i)) && (mMemory.memoryTypes[i].propertyFlags & properties) == properties) return i;
  throw VulkanError(VK_ERROR_FEATURE_NOT_PRESENT,
                    fmt::format("finding a memory type with properties 0x{:x} on {}", properties, mInfo.name));
}

std::uint32_t VulkanContext::validationErrors() const { return mMessages ? mMessages->errors.load() : 0; }

std::string VulkanContext::lastValidationMessage() const {
  if (!mMessages) return {};
  std::lock_guard<std::mutex> lock(mMessages->mutex);
  return mMessages->last;
}

VkShaderModule VulkanContext::createShaderModule(const std::string& name) const {
  const EmbeddedShader& s = embeddedShader(name);
  VkShaderModuleCreateInfo ci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  ci.codeSize = s.count * sizeof(std::uint32_t);
  ci.pCode = s.words;
  VkShaderModule module = VK_NULL_HANDLE;
  check(vkCreateShaderModule(mDevice, &ci, nullptr, &module), fmt::format("creating shader module {}", name).c_str());
  return module;
}

} // namespace rtsdf::gpu
