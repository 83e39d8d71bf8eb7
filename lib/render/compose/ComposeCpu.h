#pragma once
/// @file ComposeCpu.h
/// @brief The CPU copy of ComposePass: the same colours (render/compose/ComposeParams.h) for every pixel.
#include "render/RenderTypes.h"
#include "render/compose/ComposeParams.h"

#include <vector>

namespace rtsdf {

/// @brief ComposePass on the CPU: the packed pixels of @a params's view of @a gbuffer and @a visibility.
/// @param fine, coarse the dense SDFs on the grids of @a params (read by the slice and mask views only).
/// @param overlay the text strip: params.fineDims.w rows of coverage bytes (0: none), x fastest.
std::vector<std::uint32_t> composePixelsCpu(const GBuffer& gbuffer, const LightVisibility& visibility,
                                            const std::vector<gpu::shared::GpuLight>& lights,
                                            const std::vector<float>& fine, const std::vector<float>& coarse,
                                            const std::vector<std::uint8_t>& overlay,
                                            const gpu::shared::ComposeParams& params);

} // namespace rtsdf
