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
///        same field for every pixel and light, and the same kContactPending marks where params.contactReach > 0.
LightVisibility sdfShadowsCpu(const GBuffer& gbuffer, const std::vector<float>& field,
                              const std::vector<gpu::shared::GpuLight>& lights,
                              const gpu::shared::SdfShadowParams& params);

/// @brief ContactShadowPass on the CPU: at every pixel and light that @a visibility marks (kContactPending added by
///        sdfShadowsCpu), params.rays short rays from the surface point (offset params.normalOffset along the normal)
///        towards the light's disc (lightDiscDirection, turned by the pixel's jitter as the shader turns them), each
///        blocked by any triangle within min(params.distance, the distance to the light) (Embree, through
///        ExactDistanceField::intersect); the mark is taken off and the visibility lowered to the fraction of rays
///        left open.
/// @param geometry the triangles in the G-buffer's frame (buildSceneGeometry with the G-buffer's origin).
/// @param visibility in: sdfShadowsCpu's; out: the pass's.
/// @note A ray that grazes an edge may hit in one tracer and not in the other (Embree's watertight test against the
///       shader's Moller-Trumbore): compare with a tolerance on the number of pixels.
/// @throw Error when the parameters, lights and visibility do not match the G-buffer.
void contactShadowsCpu(const SceneGeometry& geometry, const GBuffer& gbuffer,
                       const std::vector<gpu::shared::GpuLight>& lights, const gpu::shared::ContactShadowParams& params,
                       LightVisibility& visibility);

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
