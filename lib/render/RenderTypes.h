#pragma once
/// @file RenderTypes.h
/// @brief What every shadow technique of the renderer shares: the camera as the GPU sees it, the lights,
///        the per-pixel primary visibility (G-buffer) and per-light visibility images.
#include "render/RenderParams.h"
#include "scene/Scene.h"

#include <glm/glm.hpp>

#include <vector>

namespace rtsdf {

/// @brief Primary visibility of every pixel (row 0 at the top, x fastest).
struct GBuffer {
  int width = 0, height = 0;
  std::vector<glm::vec4> position; ///< xyz: hit point relative to origin; w: ray distance, < 0 where the ray
                                   ///< hits nothing
  std::vector<glm::vec4> normal;   ///< xyz: unit geometric normal turned towards the camera; w: instance
                                   ///< index (as a float), -1 where the ray hits nothing
  glm::dvec3 origin{0.0};          ///< the world point positions are measured from (the renderer's frame)
  bool hit(std::size_t i) const { return position[i].w >= 0.0f; }
  /// @brief Pixel @a i's hit point in world coordinates.
  glm::dvec3 worldPosition(std::size_t i) const { return origin + glm::dvec3(glm::vec3(position[i])); }
  std::size_t pixelCount() const { return std::size_t(width) * std::size_t(height); }
};

/// @brief Visibility in [0, 1] of each light at each pixel: visibility[light][pixel] (0: fully shadowed).
using LightVisibility = std::vector<std::vector<float>>;

/// @brief The camera parameters of @a camera for a @a width x @a height image.
/// @param frameOrigin the world point the GPU's coordinates are measured from (the eye is placed at
///        position - frameOrigin, in double).
/// @throw Error when the camera is degenerate (position == target, up parallel to the view) or the size is
///        not positive.
gpu::shared::CameraParams makeCameraParams(const Camera& camera, int width, int height,
                                           const glm::dvec3& frameOrigin = glm::dvec3(0.0));

/// @brief The scene's lights as the GPU sees them (directions normalised towards the light; sphere lights
///        placed relative to @a frameOrigin).
std::vector<gpu::shared::GpuLight> makeGpuLights(const std::vector<Light>& lights,
                                                 const glm::dvec3& frameOrigin = glm::dvec3(0.0));

} // namespace rtsdf
