#pragma once
/// @file JobSupport.h
/// @brief Small pieces the jobs share (internal to lib/jobs and lib/bench).
#include "gpu/VulkanContext.h"
#include "scene/Scene.h"

#include <chrono>
#include <string>

namespace rtsdf::detail {

/// @brief "N meshes (K open), M instances, T triangles, Z zero-area dropped".
std::string meshSummary(const Scene& scene);

/// @brief A Vulkan context on @a device ("" for the best one), validation as the environment asks (RTSDF_VALIDATION).
gpu::ContextOptions contextOptions(const std::string& device);

/// @brief Refuse results computed while the validation layer reported errors.
/// @throw Error with the count and the last message.
void throwOnValidationErrors(const gpu::VulkanContext& ctx);

/// @brief Seconds since @a t0.
inline double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// @brief The path of a bundled scene in the source tree's data/scenes (e.g. "default.json").
std::string bundledScene(const std::string& name);

/// @brief The path of a bundled mesh in the source tree's data/meshes (e.g. "bunny.obj").
std::string bundledMesh(const std::string& name);

/// @brief rtsdf's version, for file metadata and reports.
const char* version();

} // namespace rtsdf::detail
