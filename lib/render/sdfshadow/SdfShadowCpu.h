#pragma once
/// @file SdfShadowCpu.h
/// @brief The CPU copy of SdfShadowPass: the same march (render/sdfshadow/SdfShadowMarch.h) over the same field,
///        so the tests can compare GPU and CPU results on real scenes.
#include "render/RenderTypes.h"
#include "render/sdfshadow/SdfShadowParams.h"

#include <vector>

namespace rtsdf {

/// @brief SdfShadowPass on the CPU: the same march (sdfShadowMarch, or sdfShadowUmbra for kPenumbraUmbra) over the
///        same field for every pixel and light, and the same kContactPending marks where params.contactReach > 0.
LightVisibility sdfShadowsCpu(const GBuffer& gbuffer, const std::vector<float>& field,
                              const std::vector<gpu::shared::GpuLight>& lights,
                              const gpu::shared::SdfShadowParams& params);

} // namespace rtsdf
