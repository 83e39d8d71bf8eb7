#pragma once
/// @file RenderReference.h
/// @brief CPU references of the renderer's GPU passes, evaluating the same shared functions
///        (gpu/shared/Render.h) so the tests can compare GPU and CPU results on real scenes.
#include "gpu/shared/Compose.h"
#include "render/RenderTypes.h"
#include "scene/SceneGeometry.h"

#include <vector>

namespace rtsdf {

/// @brief SdfShadowPass on the CPU: the same march (sdfShadowMarch, or sdfShadowUmbra for kPenumbraUmbra) over the
///        same field for every pixel and light.
LightVisibility sdfShadowsCpu(const GBuffer& gbuffer, const std::vector<float>& field,
                              const std::vector<gpu::shared::GpuLight>& lights,
                              const gpu::shared::SdfShadowParams& params);

/// @brief The shadow maps' depths (6 N^2 per light) by Embree rays along the same texel rays.
std::vector<float> shadowMapDepthsCpu(const SceneGeometry& geometry, const std::vector<gpu::shared::GpuLight>& lights,
                                      const std::vector<gpu::shared::ShadowMapParams>& maps);

/// @brief The PCF lookups of ShadowMapPass on the CPU, given the depths.
LightVisibility shadowMapLookupCpu(const GBuffer& gbuffer, const std::vector<float>& depths,
                                   const std::vector<gpu::shared::GpuLight>& lights,
                                   const std::vector<gpu::shared::ShadowMapParams>& maps);

/// @brief One TaaPass step on the CPU: @a history (light-major, updated in place) from @a current.
void taaCpu(const LightVisibility& current, LightVisibility& history, const gpu::shared::TaaParams& params);

/// @brief ComposePass on the CPU: the packed pixels of @a params's view of @a gbuffer and @a visibility.
/// @param fine, coarse the dense SDFs on the grids of @a params (read by the slice and mask views only).
/// @param overlay the text strip: params.fineDims.w rows of coverage bytes (0: none), x fastest.
std::vector<std::uint32_t> composePixelsCpu(const GBuffer& gbuffer, const LightVisibility& visibility,
                                            const std::vector<gpu::shared::GpuLight>& lights,
                                            const std::vector<float>& fine, const std::vector<float>& coarse,
                                            const std::vector<std::uint8_t>& overlay,
                                            const gpu::shared::ComposeParams& params);

} // namespace rtsdf
