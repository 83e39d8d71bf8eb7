#pragma once
/// @file JobSupport.h
/// @brief What the jobs share with the suites, the viewer and the front ends (public: device context options,
///        validation checks, GPU warm-up, bundled data), then what only lib/jobs uses (namespace detail).
#include "gpu/VulkanContext.h"
#include "scene/Scene.h"

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>

namespace rtsdf {
struct Bounds;
struct PipelineSettings;
} // namespace rtsdf

namespace rtsdf {

/// @brief The options of a Vulkan context for a job on @a device; every job, suite, viewer and Python object
///        that opens a context starts from these, so that all pick the device and turn on validation alike.
/// @param device the device by index ("0") or by a case-insensitive substring of its name, as `--device` and
///        the Python keyword `device` take it; "" for the best one (gpu::chooseDevice).
/// @return options with @a device set and validation as the environment asks (RTSDF_VALIDATION,
///         RTSDF_SYNC_VALIDATION); no extra instance or device extensions (a window adds its own).
gpu::ContextOptions deviceContextOptions(const std::string& device);

/// @brief Refuse results computed while the validation layer reported errors.
/// @throw Error with the count and the last message.
void throwOnValidationErrors(const gpu::VulkanContext& ctx);

/// @brief Warn (spdlog) when @a cutVoxels fine voxel refinements of a job on device @a device were ended by a CPU
///        device's loop budget (FrameStats::cutVoxels): their distances are upper bounds, not exact.
void warnOfCutWalks(std::uint64_t cutVoxels, const std::string& device);

/// @brief Run @a work on a new Vulkan context of @a options, then destroy the device (gpu::VulkanContext::close)
///        and refuse the result when the validation layer reported any error, those at the device's destruction
///        (objects left alive) included. Every GPU job, suite and sweep opens its context this way.
/// @param work called with the context; every GPU object it makes must be gone when it returns.
/// @throw Error from throwOnValidationErrors, or whatever @a work throws.
template <typename Work> auto runOnDevice(const gpu::ContextOptions& options, Work&& work) {
  gpu::VulkanContext ctx(options);
  auto result = std::forward<Work>(work)(static_cast<const gpu::VulkanContext&>(ctx));
  ctx.close();
  throwOnValidationErrors(ctx);
  return result;
}

/// @brief Seconds since @a t0.
inline double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// @brief Run @a gpuWork (at least once) until @a seconds have passed, so that a GPU's clocks have risen before
///        the frames that are timed.
/// @note A discrete GPU idles at a fraction of its clock (an H100 at 345 of 1980 MHz after a few seconds of
///       light load, measured) and takes a few hundred milliseconds of sustained work to come back up, so short
///       timed runs after host-side work (an exact reference, an error measurement) read up to 6x too slow. A CPU
///       device (lavapipe) has no such clocks: one run is all it costs there. @a seconds <= 0 runs nothing.
void warmUpGpu(double seconds, const std::function<void()>& gpuWork);

/// @brief warmUpGpu with full frames at time 0 of @a settings on an SdfPipeline of its own, destroyed after: the
///        pipeline made next for measuring starts from nothing (its history, pool and frame count) on warm clocks.
void warmUpPipeline(const gpu::VulkanContext& ctx, const Scene& scene, const Bounds& bounds,
                    const PipelineSettings& settings, double seconds);

/// @brief The path of a bundled scene in the source tree's data/scenes (e.g. "default.json").
std::string bundledScene(const std::string& name);

/// @brief The path of a bundled mesh in the source tree's data/meshes (e.g. "bunny.obj").
std::string bundledMesh(const std::string& name);

} // namespace rtsdf

namespace rtsdf::detail {

/// @brief "N meshes (K open), M instances, T triangles, Z zero-area dropped".
std::string meshSummary(const Scene& scene);

/// @brief rtsdf's version, for file metadata and reports.
const char* version();

} // namespace rtsdf::detail
