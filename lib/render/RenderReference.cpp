// The shared functions fetch through these macros, defined before anything includes gpu/shared/Render.h.
// The pointers are set per call (worker threads only read them).
namespace {
const float* gField = nullptr;
const float* gDepth = nullptr;
} // namespace
#define RTSDF_SDF_FETCH(i) gField[i]
#define RTSDF_DEPTH_FETCH(i) gDepth[i]
#include "render/RenderReference.h"

#include "reference/ExactSdf.h"

#include <tbb/parallel_for.h>

#include <algorithm>

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
        vis[l][i] = params.penumbra == sh::kPenumbraUmbra
                        ? sh::sdfShadowUmbra(params, p, n, L, tMax, w, jitter)
                        : sh::sdfShadowMarch(params, params.penumbra, p, n, L, tMax, w, jitter);
      }
    }
  });
  return vis;
}

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

void taaCpu(const LightVisibility& current, LightVisibility& history, const sh::TaaParams& p) {
  const int w = p.image.x, h = p.image.y;
  for (std::size_t l = 0; l < current.size(); ++l)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        float nmin = 1.0e30f, nmax = -1.0e30f;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int qx = std::clamp(x + dx, 0, w - 1), qy = std::clamp(y + dy, 0, h - 1);
            const float c = current[l][std::size_t(qy * w + qx)];
            nmin = std::min(nmin, c);
            nmax = std::max(nmax, c);
          }
        const std::size_t i = std::size_t(y * w + x);
        history[l][i] = sh::taaResolve(p, history[l][i], current[l][i], nmin, nmax);
      }
}

} // namespace rtsdf
