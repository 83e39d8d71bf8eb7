// The march fetches the field through this macro, defined before anything includes SdfShadowMarch.h. The pointer
// is set per call (worker threads only read it).
namespace {
const float* gField = nullptr;
} // namespace
#define RTSDF_SDF_FETCH(i) gField[i]
#include "render/sdfshadow/SdfShadowMarch.h"
#include "render/sdfshadow/SdfShadowCpu.h"

#include <tbb/parallel_for.h>

namespace rtsdf {
namespace sh = gpu::shared;

LightVisibility sdfShadowsCpu(const GBuffer& g, const std::vector<float>& field, const std::vector<sh::GpuLight>& lights,
                              const sh::SdfShadowParams& params) {
  gField = field.data();
  LightVisibility vis(lights.size(), std::vector<float>(g.pixelCount(), 1.0f));
  const glm::vec3 lo(params.gridOriginH), hi = lo + glm::vec3(glm::ivec3(params.gridDims)) * params.gridOriginH.w;
  tbb::parallel_for(0, g.height, [&](int y) {
    for (int x = 0; x < g.width; ++x) {
      const std::size_t i = std::size_t(y) * std::size_t(g.width) + std::size_t(x);
      if (!g.hit(i)) continue;
      const float jitter = sh::pixelJitter(std::uint32_t(i), std::uint32_t(params.image.z), std::uint32_t(params.image.w));
      for (std::size_t l = 0; l < lights.size(); ++l) {
        glm::vec3 L;
        float tMax, w;
        const glm::vec3 p(g.position[i]), n(g.normal[i]);
        if (!sh::lightGeometry(lights[l], p, lo, hi, L, tMax, w)) continue;
        float& v = vis[l][i];
        bool contact = false;
        v = params.penumbra == sh::kPenumbraUmbra
                ? sh::sdfShadowUmbra(params, p, n, L, tMax, w, jitter, contact)
                : sh::sdfShadowMarch(params, params.penumbra, p, n, L, tMax, w, jitter, contact);
        if (contact && v > 0.0f) v += sh::kContactPending;
      }
    }
  });
  return vis;
}

} // namespace rtsdf
