#include "gpu/Profiler.h"

#include "gpu/VulkanError.h"

#include <fmt/format.h>

namespace rtsdf::gpu {

GpuProfiler::GpuProfiler(const VulkanContext& ctx, std::uint32_t maxScopes)
    : mCtx(&ctx), mMax(maxScopes), mEnabled(ctx.info().computeTimestamps) {
  if (!mEnabled) return;
  VkQueryPoolCreateInfo ci{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  ci.queryType = VK_QUERY_TYPE_TIMESTAMP;
  ci.queryCount = 2 * maxScopes;
  mPool.create(ctx, vkCreateQueryPool, ci, "creating the timestamp query pool");
}

void GpuProfiler::reset(VkCommandBuffer cmd) {
  mNames.clear();
  mOpen.clear();
  if (mEnabled) vkCmdResetQueryPool(cmd, mPool.get(), 0, 2 * mMax);
}

void GpuProfiler::begin(VkCommandBuffer cmd, const std::string& pass) {
  if (mNames.size() >= mMax) throw Error(fmt::format("GPU profiler: more than {} scopes", mMax));
  const auto i = std::uint32_t(mNames.size());
  mNames.push_back(pass);
  mOpen.push_back(i);
  if (mEnabled) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, mPool.get(), 2 * i);
}

void GpuProfiler::end(VkCommandBuffer cmd) {
  if (mOpen.empty()) throw Error("GPU profiler: end() without begin()");
  const std::uint32_t i = mOpen.back();
  mOpen.pop_back();
  if (mEnabled) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, mPool.get(), 2 * i + 1);
}

std::vector<std::pair<std::string, double>> GpuProfiler::results() const {
  std::vector<std::pair<std::string, double>> out;
  if (!mEnabled || mNames.empty()) return out;
  std::vector<std::uint64_t> ticks(2 * mNames.size());
  check(vkGetQueryPoolResults(mCtx->device(), mPool.get(), 0, std::uint32_t(ticks.size()),
                              ticks.size() * sizeof(std::uint64_t), ticks.data(), sizeof(std::uint64_t),
                              VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
        "reading GPU timestamps");
  const double msPerTick = double(mCtx->info().timestampPeriodNs) * 1e-6;
  for (std::size_t i = 0; i < mNames.size(); ++i)
    out.emplace_back(mNames[i], double(ticks[2 * i + 1] - ticks[2 * i]) * msPerTick);
  return out;
}

double GpuProfiler::totalMs(const std::string& pass) const {
  double t = 0.0;
  for (const auto& [name, ms] : results())
    if (name == pass) t += ms;
  return t;
}

} // namespace rtsdf::gpu
