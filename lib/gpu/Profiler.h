#pragma once
/// @file Profiler.h
/// @brief GPU timestamps per named pass: the numbers the benchmarks read.
#include "gpu/UniqueHandle.h"
#include "gpu/VulkanContext.h"

#include <string>
#include <utility>
#include <vector>

namespace rtsdf::gpu {

/// @brief Records a timestamp pair around each named scope of a command buffer and reads them back.
class GpuProfiler {
public:
  explicit GpuProfiler(const VulkanContext& ctx, std::uint32_t maxScopes = 256);
  GpuProfiler(const GpuProfiler&) = delete; // ProfileScopes point at it: neither copied nor moved
  GpuProfiler& operator=(const GpuProfiler&) = delete;

  /// @brief Record the reset of all queries; call once per command buffer before the first scope.
  void reset(VkCommandBuffer cmd);
  /// @brief Record the start of a scope named @a pass (e.g. "JumpFloodPass").
  void begin(VkCommandBuffer cmd, const std::string& pass);
  /// @brief Record the end of the innermost open scope.
  void end(VkCommandBuffer cmd);
  /// @brief After the command buffer finished: milliseconds per scope, in recording order (a pass recorded
  ///        several times appears several times). Empty when the device has no compute timestamps.
  std::vector<std::pair<std::string, double>> results() const;
  /// @brief Sum of the milliseconds of every scope named @a pass.
  double totalMs(const std::string& pass) const;

private:
  const VulkanContext* mCtx;
  UniqueHandle<vkDestroyQueryPool> mPool; // none when the device has no compute timestamps
  std::uint32_t mMax;
  std::vector<std::string> mNames;
  std::vector<std::uint32_t> mOpen;
  bool mEnabled;
};

/// @brief Begins a profiler scope on construction and ends it on destruction (nullptr: no profiling).
class ProfileScope {
public:
  ProfileScope(GpuProfiler* p, VkCommandBuffer cmd, const std::string& pass) : mP(p), mCmd(cmd) {
    if (mP) mP->begin(mCmd, pass);
  }
  ~ProfileScope() { if (mP) mP->end(mCmd); }
  ProfileScope(const ProfileScope&) = delete;
  ProfileScope& operator=(const ProfileScope&) = delete;

private:
  GpuProfiler* mP;
  VkCommandBuffer mCmd;
};

} // namespace rtsdf::gpu
