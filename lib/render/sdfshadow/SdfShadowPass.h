#pragma once
/// @file SdfShadowPass.h
/// @brief SDF soft shadows on the GPU: SdfShadowPass (sdf_shadow_main.glsl's variants, lib/Shaders.cmake) and the
///        copy of the fine SDF into the 3D texture it may sample (VolumeFillPass, volume_fill.comp). Buffers are
///        bound at the indices render/sdfshadow/SdfShadowParams.h names; the CPU copy is SdfShadowCpu.h.
#include "gpu/ComputePass.h"
#include "gpu/Profiler.h"
#include "gpu/Resources.h"
#include "render/gbuffer/GBufferPass.h"
#include "render/sdfshadow/SdfShadowParams.h"
#include "sdf/SdfPipeline.h"

namespace rtsdf {

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

/// @brief The 3D texture brought up to date with the dense fine SDF where the last SdfPipeline frame wrote it
///        (DenseFineWrites::Extent::Listed): the fine voxels of the blocks its upsampling listed and of the coarse
///        voxels its mask listed for refinement, by compute shader stores dispatched indirectly from those lists on
///        the GPU. The texture's other texels must hold the field's values already (the fill or update after the
///        frame before).
class VolumeUpdatePass {
public:
  static constexpr const char* kName = "FineSdfTextureUpdate";
  struct Inputs {
    const gpu::Buffer& field;      ///< the dense fine SDF (texture.dims() floats, x fastest)
    const DenseFineWrites& writes; ///< its last frame's writes: Extent::Listed
  };
  struct Outputs { const gpu::SampledVolume& texture; };
  using Params = gpu::shared::RefineParams; ///< the frame's (DenseFineWrites::params)
  explicit VolumeUpdatePass(const gpu::VulkanContext& ctx);
  /// @brief Whether the device can run the pass (it stores to R32_SFLOAT 3D textures: storageSupported).
  bool available() const { return !mBlocks.name().empty(); }
  /// @throw Error when the pass is not available, @a in.writes is not Extent::Listed, or the field is smaller than
  ///        the texture.
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;

private:
  /// The blocks' and the refined voxels' shaders; empty where SampledVolume::storageSupported is false.
  gpu::ComputePipeline mBlocks, mRefined;
};

/// @brief Camera-centred cascade levels as SdfShadowPass samples them (Params::cascadeLevels of them).
struct GpuCascadeField {
  const gpu::Buffer& levels;              ///< a CascadeFieldLevel per level, finest first
  std::vector<const gpu::Buffer*> fields; ///< each level's dense fine SDF (x fastest), finest first
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
    /// filtering (one fetch per step); null: the march filters @a field itself, exactly as the CPU copy
    /// does (eight fetches per step).
    const gpu::SampledVolume* texture;
    const gpu::Buffer& lights;
    /// Where given (and no texture), the march fetches the fine SDF from the brick pool and the coarse SDF
    /// (SdfPipeline::brickField(): the same values as the dense fine SDF), eight fetches per step.
    const GpuBrickField* bricks = nullptr;
    /// Whether @a texture is filled from @a field first; false where it still holds @a field's values (the field
    /// unchanged since the last fill: FrameStats::fieldChanged), so the copy is skipped.
    bool fillTexture = true;
    /// Where given (and no texture or bricks), the march samples these cascade levels (sdf_shadow_cascade.comp);
    /// @a field is unread.
    const GpuCascadeField* cascade = nullptr;
    /// Where given (with fillTexture and Extent::Listed), the texture held the field's values before this frame's
    /// writes: on a device whose whole fill is by compute shader (VolumeFillPass::defaultMethod, a GPU) only those
    /// are copied (VolumeUpdatePass); else, and on a CPU device (its whole fill a copy command, as fast there), the
    /// whole field is (VolumeFillPass).
    const DenseFineWrites* fillOnly = nullptr;
  };
  struct Outputs { const gpu::Buffer& visibility; }; ///< params.gridDims.w * width * height floats, light-major
  using Params = gpu::shared::SdfShadowParams;
  /// @param umbra build the umbra estimate's variants (kPenumbraUmbra: several marches per pixel and light),
  ///        else the single-march ones (classic, improved, centred).
  /// @note The texture variant is built only where the device filters R32_SFLOAT 3D textures linearly.
  explicit SdfShadowPass(const gpu::VulkanContext& ctx, bool umbra = false);
  /// @throw Error when a texture is given but the device cannot filter it (see gpu::SampledVolume::supported),
  ///        when params.penumbra is (or is not) kPenumbraUmbra and the pass was built otherwise, or when the cascade
  ///        levels given are not params.cascadeLevels (1 to RTSDF_MAX_CASCADE_LEVELS).
  void execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
               const Params& params) const;

private:
  gpu::ComputePipeline mTexturePipeline, mBufferPipeline, mBrickPipeline;
  gpu::ComputePipeline mCascade4Pipeline, mCascadePipeline; ///< up to 4 levels (a cheaper switch), up to 10
  VolumeFillPass mFill;
  VolumeUpdatePass mUpdate;
  VolumeFillPass::Method mFillMethod;
  bool mUmbra = false;
};

} // namespace rtsdf
