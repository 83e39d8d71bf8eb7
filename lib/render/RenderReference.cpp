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
#include "util/Error.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

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
      const float reach = std::min(params.distance, tMax);
      std::uint32_t open = 0;
      for (std::uint32_t k = 0; k < params.rays; ++k) {
        float t = 0.0f;
        bool front = false;
        open += field.intersect(o, sh::lightDiscDirection(L, w, k, params.rays, turn), reach, t, front) ? 0u : 1u;
      }
      v = std::min(v - sh::kContactPending, float(open) / float(params.rays));
    }
  });
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

namespace {
/// compose.comp's sliceAt: the slice's colour at frame point @a p, or vec3(-1) outside the fine grid.
glm::vec3 sliceColorCpu(const sh::ComposeParams& c, const std::vector<float>& fine, const std::vector<float>& coarse,
                        const glm::vec3& p) {
  const glm::vec3 g = (p - glm::vec3(c.fineOriginH)) / c.fineOriginH.w;
  const glm::ivec3 d(c.fineDims);
  if (glm::any(glm::lessThan(g, glm::vec3(0.0f))) || glm::any(glm::greaterThan(g, glm::vec3(d - 1))))
    return glm::vec3(-1.0f);
  if (std::uint32_t(c.image.w) == sh::kViewMask) {
    const glm::ivec3 cd(c.coarseDims);
    const glm::ivec3 v =
        glm::clamp(glm::ivec3(glm::floor((p - glm::vec3(c.coarseOriginH)) / c.coarseOriginH.w + 0.5f)), glm::ivec3(0),
                   cd - 1);
    const float cv = coarse.at(std::size_t(v.x) + std::size_t(cd.x) * (std::size_t(v.y) + std::size_t(cd.y) * std::size_t(v.z)));
    return sh::maskColor(std::fabs(cv) <= c.slice.y);
  }
  const glm::ivec3 i = glm::min(glm::ivec3(glm::floor(g)), d - 2);
  const glm::vec3 f = g - glm::vec3(i);
  auto at = [&](int dx, int dy, int dz) {
    return fine.at(std::size_t(i.x + dx) +
                   std::size_t(d.x) * (std::size_t(i.y + dy) + std::size_t(d.y) * std::size_t(i.z + dz)));
  };
  const float v = sh::trilinear(at(0, 0, 0), at(1, 0, 0), at(0, 1, 0), at(1, 1, 0), at(0, 0, 1), at(1, 0, 1),
                                at(0, 1, 1), at(1, 1, 1), f);
  return sh::sliceColor(v, c.slice.z, c.fineOriginH.w);
}
} // namespace

std::vector<std::uint32_t> composePixelsCpu(const GBuffer& g, const LightVisibility& visibility,
                                            const std::vector<sh::GpuLight>& lights, const std::vector<float>& fine,
                                            const std::vector<float>& coarse, const std::vector<std::uint8_t>& overlay,
                                            const sh::ComposeParams& c) {
  std::vector<std::uint32_t> out(g.pixelCount());
  tbb::parallel_for(0, g.height, [&](int y) {
    for (int x = 0; x < g.width; ++x) {
      const std::size_t i = std::size_t(y) * std::size_t(g.width) + std::size_t(x);
      glm::vec3 col = sh::skyColor();
      if (g.hit(i)) {
        glm::vec3 e = sh::ambientLight();
        for (std::size_t l = 0; l < lights.size(); ++l)
          e += sh::lightIrradiance(lights[l], glm::vec3(g.position[i]), glm::vec3(g.normal[i]), visibility[l][i]);
        col = sh::instanceAlbedo(int(g.normal[i].w)) * e;
      }
      glm::vec3 display(sh::displayEncode(col.x), sh::displayEncode(col.y), sh::displayEncode(col.z));
      if (std::uint32_t(c.image.w) != sh::kViewShaded && c.fineDims.x > 1) {
        const glm::vec3 dir = sh::cameraDirection(c.camera, float(x) + 0.5f, float(y) + 0.5f);
        const float t = sh::slicePlaneDistance(c, dir, g.position[i].w);
        if (t > 0.0f) {
          const glm::vec3 s = sliceColorCpu(c, fine, coarse, glm::vec3(c.camera.position) + t * dir);
          if (s.x >= 0.0f) display = s;
        }
      }
      if (y < c.fineDims.w) display = overlay.at(i) != 0 ? glm::vec3(1.0f) : display * 0.3f;
      out[i] = sh::packDisplayColor(display, std::uint32_t(c.coarseDims.w));
    }
  });
  return out;
}

} // namespace rtsdf
