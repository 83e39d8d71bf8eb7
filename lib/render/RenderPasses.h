#pragma once
/// @file RenderPasses.h
/// @brief The renderer's GPU passes, each a small named unit (inputs, outputs, execute): GBufferPass,
///        SdfShadowPass, ShadowMapPass, TaaPass. Each records into a command buffer; the caller submits.
///        Their CPU references are in RenderReference.h.
#include "gpu/Profiler.h"
#include "gpu/Resources.h"
#include "gpu/shared/Render.h"
#include "sdf/GpuSceneBvh.h"

namespace rtsdf {

/// @brief The G-buffer on the GPU: vec4 position (w: ray distance, < 0 on a miss) and vec4 normal (w: instance).
struct GpuGBuffer {
  int width = 0, height = 0;
  gpu::Buffer position, normal;
  void reserve(const gpu::VulkanContext& ctx, int width, int height);
};

/// @brief Primary visibility: one camera ray per pixel through the scene's BVH.
class GBufferPass {
public:
  static constexpr const char* kName = "GBufferPass";
  explicit GBufferPass(const gpu::VulkanContext& ctx);
  /// @param out reserved for the camera's image size.
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const GpuSceneBvh& bvh,
               const gpu::shared::CameraParams& camera, GpuGBuffer& out) const;

private:
  gpu::ComputePipeline mPipeline;
};

/// @brief SDF soft shadows: per pixel and light, sphere tracing of the fine SDF towards the light.
class SdfShadowPass {
public:
  static constexpr const char* kName = "SdfShadowPass";
  static constexpr const char* kCopyName = "FineSdfTextureCopy"; ///< the fine buffer into the 3D texture
  /// @note The texture variant is built only where the device filters R32_SFLOAT 3D textures linearly.
  explicit SdfShadowPass(const gpu::VulkanContext& ctx);
  /// @param field dense fine SDF (x fastest) on the grid described by @a params.gridOriginH / gridDims.
  /// @param texture where given, @a field is first copied into it and the march samples it with hardware
  ///        trilinear filtering (one fetch per step); null: the march filters @a field itself, exactly as the
  ///        CPU reference does (eight fetches per step).
  /// @param visibility params.gridDims.w * width * height floats, light-major.
  /// @throw Error when @a texture is given but the device cannot filter it (see gpu::SampledVolume::supported).
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const GpuGBuffer& gbuffer, const gpu::Buffer& field,
               const gpu::SampledVolume* texture, const gpu::Buffer& lights,
               const gpu::shared::SdfShadowParams& params, const gpu::Buffer& visibility) const;

private:
  gpu::ComputePipeline mTexturePipeline, mBufferPipeline;
};

/// @brief Shadow maps (the baseline games use): a depth map per light (orthographic for directional lights,
///        a cube map for sphere lights), then PCF lookups per pixel.
class ShadowMapPass {
public:
  static constexpr const char* kBuildName = "ShadowMapBuildPass";
  static constexpr const char* kLookupName = "ShadowMapLookupPass";
  explicit ShadowMapPass(const gpu::VulkanContext& ctx);
  /// @param maps one ShadowMapParams per light (host copy of @a mapsBuffer).
  /// @param depth 6 * N^2 floats per light.
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const GpuSceneBvh& bvh, const GpuGBuffer& gbuffer,
               const gpu::Buffer& lights, const std::vector<gpu::shared::ShadowMapParams>& maps,
               const gpu::Buffer& mapsBuffer, const gpu::Buffer& depth, const gpu::Buffer& visibility) const;

private:
  gpu::ComputePipeline mBuild, mLookup;
};

/// @brief Temporal accumulation of the visibility with neighbourhood clamping.
class TaaPass {
public:
  static constexpr const char* kName = "TaaPass";
  explicit TaaPass(const gpu::VulkanContext& ctx);
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const gpu::Buffer& current, const gpu::Buffer& history,
               const gpu::shared::TaaParams& params) const;

private:
  gpu::ComputePipeline mPipeline;
};

} // namespace rtsdf
