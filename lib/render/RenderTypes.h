#pragma once
/// @file RenderTypes.h
/// @brief What every shadow technique of the renderer shares: the camera as the GPU sees it, the lights,
///        the per-pixel primary visibility (G-buffer) and per-light visibility images.
#include "gpu/shared/Render.h"
#include "scene/Scene.h"

#include <glm/glm.hpp>

#include <vector>

namespace rtsdf {

/// @brief Primary visibility of every pixel (row 0 at the top, x fastest).
struct GBuffer {
  int width = 0, height = 0;
  std::vector<glm::vec4> position; ///< xyz: world hit point; w: ray distance, < 0 where the ray hits nothing
  std::vector<glm::vec4> normal;   ///< xyz: unit geometric normal turned towards the camera; w: instance
                                   ///< index (as a float), -1 where the ray hits nothing
  bool hit(std::size_t i) const { return position[i].w >= 0.0f; }
  std::size_t pixelCount() const { return std::size_t(width) * std::size_t(height); }
};

/// @brief Visibility in [0, 1] of each light at each pixel: visibility[light][pixel] (0: fully shadowed).
using LightVisibility = std::vector<std::vector<float>>;

/// @brief The camera parameters of @a camera for a @a width x @a height image.
/// @throw Error when the camera is degenerate (position == target, up parallel to the view) or the size is
///        not positive.
gpu::shared::CameraParams makeCameraParams(const Camera& camera, int width, int height);

/// @brief The scene's lights as the GPU sees them (directions normalised towards the light).
std::vector<gpu::shared::GpuLight> makeGpuLights(const std::vector<Light>& lights);

} // namespace rtsdf
