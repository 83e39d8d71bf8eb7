#pragma once
/// @file ShadowMapCpu.h
/// @brief The CPU copies of ShadowMapPass: the depths along the same texel rays by Embree, and the same PCF
///        lookups (render/shadowmap/ShadowMapLookup.h).
#include "render/RenderTypes.h"
#include "render/shadowmap/ShadowMapParams.h"
#include "scene/SceneGeometry.h"

#include <vector>

namespace rtsdf {

/// @brief The shadow maps' depths (6 N^2 per light) by Embree rays along the same texel rays.
std::vector<float> shadowMapDepthsCpu(const SceneGeometry& geometry, const std::vector<gpu::shared::GpuLight>& lights,
                                      const std::vector<gpu::shared::ShadowMapParams>& maps);

/// @brief The PCF lookups of ShadowMapPass on the CPU, given the depths.
LightVisibility shadowMapLookupCpu(const GBuffer& gbuffer, const std::vector<float>& depths,
                                   const std::vector<gpu::shared::GpuLight>& lights,
                                   const std::vector<gpu::shared::ShadowMapParams>& maps);

} // namespace rtsdf
