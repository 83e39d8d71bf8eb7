#pragma once
/// @file TaaCpu.h
/// @brief The CPU copy of TaaPass: the same blend and clamp (render/taa/TaaParams.h).
#include "render/RenderTypes.h"
#include "render/taa/TaaParams.h"

#include <vector>

namespace rtsdf {

/// @brief One TaaPass step on the CPU: @a history (light-major, updated in place) from @a current.
void taaCpu(const LightVisibility& current, LightVisibility& history, const gpu::shared::TaaParams& params);

} // namespace rtsdf
