#include "render/RenderTypes.h"

#include "util/Error.h"

#include <fmt/format.h>

#include <cmath>

namespace rtsdf {

gpu::shared::CameraParams makeCameraParams(const Camera& camera, int width, int height,
                                           const glm::dvec3& frameOrigin) {
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    throw Error(fmt::format("image size {}x{} is out of range [1, 16384]", width, height));
  const glm::dvec3 f = camera.target - camera.position;
  if (!(glm::length(f) > 0.0)) throw Error("camera: position and target coincide");
  const glm::dvec3 forward = glm::normalize(f);
  const glm::dvec3 r = glm::cross(forward, camera.up);
  if (!(glm::length(r) > 1e-9 * glm::length(camera.up)) || !(glm::length(camera.up) > 0.0))
    throw Error("camera: 'up' is zero or parallel to the view direction");
  if (!(camera.verticalFov > 0.0 && camera.verticalFov < 3.14))
    throw Error(fmt::format("camera: field of view {} rad is out of range (0, 3.14)", camera.verticalFov));
  const glm::dvec3 right = glm::normalize(r);
  const glm::dvec3 up = glm::cross(right, forward);
  const double ty = std::tan(0.5 * camera.verticalFov), tx = ty * double(width) / double(height);
  gpu::shared::CameraParams c{};
  c.position = glm::vec4(glm::vec3(camera.position - frameOrigin), 1.0f);
  c.forward = glm::vec4(glm::vec3(forward), 0.0f);
  c.right = glm::vec4(glm::vec3(right * tx), 0.0f);
  c.up = glm::vec4(glm::vec3(up * ty), 0.0f);
  c.size = glm::ivec4(width, height, 0, 0);
  return c;
}

std::vector<gpu::shared::GpuLight> makeGpuLights(const std::vector<Light>& lights,
                                                 const glm::dvec3& frameOrigin) {
  std::vector<gpu::shared::GpuLight> out;
  for (const Light& l : lights) {
    gpu::shared::GpuLight g{};
    if (l.type == Light::Type::Directional) {
      g.position = glm::vec4(glm::vec3(-glm::normalize(l.direction)), float(gpu::shared::kLightDirectional));
      g.size = glm::vec4(float(std::tan(l.angularRadius)), 0.0f, 0.0f, 0.0f);
    } else {
      g.position = glm::vec4(glm::vec3(l.position - frameOrigin), float(gpu::shared::kLightSphere));
      g.size = glm::vec4(float(l.radius), 0.0f, 0.0f, 0.0f);
    }
    g.color = glm::vec4(glm::vec3(l.color * l.intensity), 1.0f);
    out.push_back(g);
  }
  return out;
}

} // namespace rtsdf
