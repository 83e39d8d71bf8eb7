#include "render/contactshadow/ContactShadowCpu.h"

#include "reference/ExactSdf.h"
#include "util/Error.h"

#include <tbb/parallel_for.h>
#include <algorithm>

namespace rtsdf {
namespace sh = gpu::shared;

void contactShadowsCpu(const SceneGeometry& geometry, const GBuffer& g, const std::vector<sh::GpuLight>& lights,
                       const sh::ContactShadowParams& params, LightVisibility& visibility) {
  if (params.image.x != g.width || params.image.y != g.height || visibility.size() != lights.size() ||
      params.lights != lights.size())
    throw Error("contact shadows: the parameters, lights and visibility do not match the G-buffer");
  for (const auto& v : visibility)
    if (v.size() != g.pixelCount()) throw Error("contact shadows: the visibility does not match the G-buffer");
  if (params.rays == 0u || g.pixelCount() == 0) return;
  const ExactDistanceField field(geometry);
  const glm::vec3 far(3.0e38f);
  tbb::parallel_for(std::size_t(0), g.pixelCount(), [&](std::size_t i) {
    if (!g.hit(i)) return;
    const glm::vec3 p(g.position[i]);
    const glm::vec3 o = p + glm::vec3(g.normal[i]) * params.normalOffset;
    const float turn = sh::contactRayTurn(params, std::uint32_t(i));
    for (std::size_t l = 0; l < lights.size(); ++l) {
      float& v = visibility[l][i];
      glm::vec3 L;
      float tMax = 0.0f, w = 0.0f;
      if (v < sh::kContactPending || !sh::lightGeometry(lights[l], p, -far, far, L, tMax, w)) continue;
      const float scale = sh::contactReachScale(v); // 1 for one box; 2^i for a receiver in cascade level i
      const float reach = std::min(params.distance * scale, tMax);
      std::uint32_t open = 0;
      for (std::uint32_t k = 0; k < params.rays; ++k) {
        float t = 0.0f;
        bool front = false;
        open += field.intersect(o, sh::lightDiscDirection(L, w, k, params.rays, turn), reach, t, front) ? 0u : 1u;
      }
      v = std::min(v - sh::kContactPending * scale, float(open) / float(params.rays));
    }
  });
}

} // namespace rtsdf
