#pragma once
/// @file RenderPasses.h
/// @brief The renderer's GPU passes, each a small named unit (inputs, outputs, execute): GBufferPass,
///        SdfShadowPass, ContactShadowPass, ShadowMapPass, TaaPass, ComposePass.
///        Their CPU references are in RenderReference.h.
#include "gpu/ComputePass.h"
#include "gpu/Profiler.h"
#include "gpu/Resources.h"
#include "gpu/shared/Compose.h"
#include "gpu/shared/Render.h"
#include "gpu/shared/RenderBindings.h"
#include "sdf/GpuSceneBvh.h"
#include "sdf/SdfPipeline.h"

namespace rtsdf {

/// @brief The G-buffer on the GPU: vec4 position (w: ray distance, < 0 on a miss) and vec4 normal (w: instance).
struct GpuGBuffer {
  int width = 0, height = 0;
  gpu::Buffer position, normal;
  void reserve(const gpu::VulkanContext& ctx, int width, int height);
};

// The passes have the shape of gpu/ComputePass.h; buffers are bound at the indices gpu/shared/RenderBindings.h
// names.

/// @brief Primary visibility: one camera ray per pixel through the scene's BVH.
class GBufferPass : gpu::ComputePass {
public:
  static constexpr const char* kName = "GBufferPass";
  struct Inputs { const GpuSceneBvh& bvh; };
  struct Outputs { const GpuGBuffer& gbuffer; }; ///< reserved for the camera's image size
  using Params = gpu::shared::CameraParams;
  explicit GBufferPass(const gpu::VulkanContext& ctx)
      : ComputePass(ctx, "gbuffer.comp", gpu::shared::kGBufferBindingCount, sizeof(Params)) {}
  /// @throw Error when the G-buffer is not reserved for the camera's image size.
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& camera) const;
};

/// @brief The dense fine SDF into the 3D texture that SdfShadowPass samples with hardware filtering.
class VolumeFillPass {
public:
  static constexpr const char* kName = "FineSdfTextureCopy";
  /// How the texels are written: a copy command (vkCmdCopyBufferToImage), or a compute shader's stores.
  enum class Method { Transfer, Compute };
  struct Inputs { const gpu::Buffer& field; }; ///< texture.dims() floats, x fastest
  struct Outputs { const gpu::SampledVolume& texture; };
  using Params = Method;
  explicit VolumeFillPass(const gpu::VulkanContext& ctx);
  /// @brief Compute where the device stores to R32F 3D textures and is no CPU device (lavapipe copies faster
  ///        than it runs shaders: measured in docs/results.md), else Transfer.
  static Method defaultMethod(const gpu::VulkanContext& ctx);
  /// @throw Error when @a method is Compute and the device cannot store to the texture, or when the field is
  ///        smaller than the texture.
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               Method method) const;

private:
  gpu::ComputePipeline mCompute; ///< empty where SampledVolume::storageSupported is false
};

/// @brief SDF soft shadows: per pixel and light, sphere tracing of the fine SDF towards the light.
class SdfShadowPass {
public:
  static constexpr const char* kName = "SdfShadowPass";
  static constexpr const char* kCopyName = VolumeFillPass::kName; ///< the fine buffer into the 3D texture
  struct Inputs {
    const GpuGBuffer& gbuffer;
    /// Dense fine SDF (x fastest) on the grid of Params::gridOriginH / gridDims (unread when @a bricks is given).
    const gpu::Buffer& field;
    /// Where given, @a field is first copied into it and the march samples it with hardware trilinear
    /// filtering (one fetch per step); null: the march filters @a field itself, exactly as the CPU reference
    /// does (eight fetches per step).
    const gpu::SampledVolume* texture;
    const gpu::Buffer& lights;
    /// Where given (and no texture), the march fetches the fine SDF from the brick pool and the coarse SDF
    /// (SdfPipeline::brickField(): the same values as the dense fine SDF), eight fetches per step.
    const GpuBrickField* bricks = nullptr;
  };
  struct Outputs { const gpu::Buffer& visibility; }; ///< params.gridDims.w * width * height floats, light-major
  using Params = gpu::shared::SdfShadowParams;
  /// @param umbra build the umbra estimate's variants (kPenumbraUmbra: several marches per pixel and light),
  ///        else the single-march ones (classic, improved, centred).
  /// @note The texture variant is built only where the device filters R32_SFLOAT 3D textures linearly.
  explicit SdfShadowPass(const gpu::VulkanContext& ctx, bool umbra = false);
  /// @throw Error when a texture is given but the device cannot filter it (see gpu::SampledVolume::supported),
  ///        or when params.penumbra is (or is not) kPenumbraUmbra and the pass was built otherwise.
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;

private:
  gpu::ComputePipeline mTexturePipeline, mBufferPipeline, mBrickPipeline;
  VolumeFillPass mFill;
  VolumeFillPass::Method mFillMethod;
  bool mUmbra = false;
};

/// @brief Contact shadows: per pixel and light, a few short rays through the scene's BVH over the first fine voxels
///        off the surface, towards points of the light's disc; the SDF's visibility is lowered to the fraction of
///        them that nothing blocks (what lies within a voxel of the receiver is below the SDF's resolution: a gap
///        under a wall, a crease, the contact of two boxes). Runs after SdfShadowPass, in place, and traces only the
///        pixels that pass marked (kContactPending: its march saw something nearer than the receiver's own plane).
class ContactShadowPass : gpu::ComputePass {
public:
  static constexpr const char* kName = "ContactShadowPass";
  struct Inputs {
    const GpuSceneBvh& bvh;
    const GpuGBuffer& gbuffer;
    const gpu::Buffer& lights;
  };
  struct Outputs { const gpu::Buffer& visibility; }; ///< in: SdfShadowPass's; out: lowered (light-major)
  using Params = gpu::shared::ContactShadowParams;
  explicit ContactShadowPass(const gpu::VulkanContext& ctx)
      : ComputePass(ctx, "contact_shadow.comp", gpu::shared::kContactShadowBindingCount, sizeof(Params)) {}
  /// @throw Error when params.rays is 0 (the caller skips the pass instead) or the image size is not the
  ///        G-buffer's.
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;
};

/// @brief Shadow maps (the baseline games use): a depth map per light (orthographic for directional lights,
///        a cube map for sphere lights), then PCF lookups per pixel.
class ShadowMapPass {
public:
  static constexpr const char* kBuildName = "ShadowMapBuildPass";
  static constexpr const char* kLookupName = "ShadowMapLookupPass";
  struct Inputs {
    const GpuSceneBvh& bvh;
    const GpuGBuffer& gbuffer;
    const gpu::Buffer& lights;
    const gpu::Buffer& maps; ///< the ShadowMapParams of every light, on the GPU
  };
  /// Depth maps (6 N^2 floats per light) and the visibility (light-major).
  struct Outputs { const gpu::Buffer &depth, &visibility; };
  using Params = std::vector<gpu::shared::ShadowMapParams>; ///< one per light (host copy of Inputs::maps)
  explicit ShadowMapPass(const gpu::VulkanContext& ctx);
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& maps) const;

private:
  gpu::ComputePipeline mBuild, mLookup;
};

/// @brief Temporal accumulation of the visibility with neighbourhood clamping.
class TaaPass : gpu::ComputePass {
public:
  static constexpr const char* kName = "TaaPass";
  struct Inputs { const gpu::Buffer& current; };
  struct Outputs { const gpu::Buffer& history; }; ///< in: the last output; out: this frame's
  using Params = gpu::shared::TaaParams;
  explicit TaaPass(const gpu::VulkanContext& ctx)
      : ComputePass(ctx, "taa.comp", gpu::shared::kTaaBindingCount, sizeof(Params)) {}
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;
};

/// @brief The picture for a window (gpu/shared/Compose.h): the lit scene as composeImage and displayImage make it,
///        or a horizontal slice through the fine SDF or the ray mask, under a strip of text; one packed 8-bit
///        pixel per uint, in the byte order of ComposeParams::coarseDims.w (a swapchain's format).
class ComposePass : gpu::ComputePass {
public:
  static constexpr const char* kName = "ComposePass";
  struct Inputs {
    const GpuGBuffer& gbuffer;
    const gpu::Buffer& visibility; ///< light-major (after TAA)
    const gpu::Buffer& lights;
    const gpu::Buffer& fine;       ///< dense fine SDF (any buffer when params.fineDims.x is 0)
    const gpu::Buffer& coarse;     ///< dense coarse SDF (read by the mask view)
    const gpu::Buffer& overlay;    ///< params.fineDims.w rows of text coverage, one byte per pixel
  };
  struct Outputs { const gpu::Buffer& pixels; }; ///< width * height uints
  using Params = gpu::shared::ComposeParams;     ///< recorded into the pass's own parameter buffer
  explicit ComposePass(const gpu::VulkanContext& ctx);
  /// @throw Error when the G-buffer's size differs from params.image.
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;

private:
  gpu::Buffer mParams;
};

} // namespace rtsdf
