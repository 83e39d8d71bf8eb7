// The lookup fetches the depths through this macro, defined before anything includes ShadowMapLookup.h. The
// pointer is set per light (worker threads only read it).
namespace {
const float* gDepth = nullptr;
} // namespace
#define RTSDF_DEPTH_FETCH(i) gDepth[i]
#include "render/shadowmap/ShadowMapLookup.h"
#include "render/shadowmap/ShadowMapCpu.h"

#include "reference/ExactSdf.h"

#include <tbb/parallel_for.h>

namespace rtsdf {
namespace sh = gpu::shared;

std::vector<float> shadowMapDepthsCpu(const SceneGeometry& geometry, const std::vector<sh::GpuLight>& lights,
                                      const std::vector<sh::ShadowMapParams>& maps) {
  const ExactDistanceField field(geometry);
  if (maps.empty()) return {};
  const std::uint32_t n = std::uint32_t(maps[0].info.x);
  std::vector<float> depth(lights.size() * 6 * std::size_t(n) * n, 0.0f);
  for (std::size_t l = 0; l < lights.size(); ++l) {
    const std::uint32_t faces = std::uint32_t(lights[l].position.w) == sh::kLightSphere ? 6u : 1u;
    tbb::parallel_for(0u, faces * n, [&](std::uint32_t fy) {
      const std::uint32_t face = fy / n, y = fy % n;
      for (std::uint32_t x = 0; x < n; ++x) {
        glm::vec3 o, d;
        sh::shadowMapRay(maps[l], lights[l], x, y, face, o, d);
        float t = 0.0f;
        bool front = false;
        depth[l * 6 * n * n + face * n * n + y * n + x] = field.intersect(o, d, 3.0e38f, t, front) ? t : 3.0e38f;
      }
    });
  }
  return depth;
}

LightVisibility shadowMapLookupCpu(const GBuffer& g, const std::vector<float>& depths,
                                   const std::vector<sh::GpuLight>& lights, const std::vector<sh::ShadowMapParams>& maps) {
  LightVisibility vis(lights.size(), std::vector<float>(g.pixelCount(), 1.0f));
  for (std::size_t l = 0; l < lights.size(); ++l) {
    const std::size_t n = std::size_t(maps[l].info.x);
    gDepth = depths.data() + l * 6 * n * n;
    tbb::parallel_for(std::size_t(0), g.pixelCount(), [&](std::size_t i) {
      if (g.hit(i)) vis[l][i] = sh::shadowMapLookup(maps[l], lights[l], glm::vec3(g.position[i]), glm::vec3(g.normal[i]));
    });
  }
  return vis;
}

} // namespace rtsdf
