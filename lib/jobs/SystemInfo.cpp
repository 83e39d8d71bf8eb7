#include "jobs/SystemInfo.h"

#include "gpu/EmbeddedShaders.h"
#include "gpu/VulkanContext.h"
#include "jobs/JobSupport.h"
#include "util/Error.h"

#include <assimp/version.h>
#include <embree3/rtcore_config.h>
#include <fmt/format.h>
#include <oneapi/tbb/version.h>
#include <openvdb/version.h>

namespace rtsdf {

namespace {

std::string describeDevice(const gpu::DeviceInfo& d, bool chosen) {
  std::string t = fmt::format("  [{}] {}{} ({}, Vulkan {}.{}.{}, driver {})\n", d.index, d.name,
                              chosen ? " *default*" : "", d.typeName, VK_VERSION_MAJOR(d.apiVersion),
                              VK_VERSION_MINOR(d.apiVersion), VK_VERSION_PATCH(d.apiVersion), d.driver);
  t += fmt::format("      maxStorageBufferRange {} MiB, shared memory {} KiB, workgroup invocations {}, "
                   "3D image {}, subgroup {} (ballots {}), timestamps {} ({} ns/tick), device-local {} MiB\n",
                   d.maxStorageBufferRange >> 20, d.maxComputeSharedMemory >> 10, d.maxComputeInvocations,
                   d.maxImageDimension3D, d.subgroupSize, d.computeSubgroupBallot ? "yes" : "no (rtsdf needs them)",
                   d.computeTimestamps ? "yes" : "no", d.timestampPeriodNs,
                   d.deviceLocalBytes >> 20);
  return t;
}

} // namespace

SystemInfo systemInfo() {
  SystemInfo info;
  std::string& t = info.text;
  t = fmt::format("rtsdf {}\n", detail::version());
  t += fmt::format("OpenVDB {} (ABI {}), Embree {}, oneTBB {}, assimp {}.{}.{}\n", OPENVDB_LIBRARY_VERSION_STRING,
                   OPENVDB_ABI_VERSION_NUMBER, RTC_VERSION_STRING, TBB_VERSION_STRING, aiGetVersionMajor(),
                   aiGetVersionMinor(), aiGetVersionPatch());
  t += "embedded shaders:";
  for (const auto& n : gpu::embeddedShaderNames()) t += " " + n;
  t += "\n";
  std::vector<gpu::DeviceInfo> devices;
  try {
    devices = gpu::listDevices();
  } catch (const Error& e) {
    t += fmt::format("Vulkan: {}\n", e.what());
    info.vulkanOk = false;
    return info;
  }
  const std::uint32_t chosen = gpu::chooseDevice(devices, "");
  t += fmt::format("Vulkan devices ({}):\n", devices.size());
  for (const auto& d : devices) t += describeDevice(d, d.index == chosen);
  return info;
}

} // namespace rtsdf
