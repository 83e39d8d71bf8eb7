#include "render/compose/ComposeCpu.h"

#include <tbb/parallel_for.h>
#include <cmath>

namespace rtsdf {
namespace sh = gpu::shared;

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
      const std::uint32_t view = std::uint32_t(c.image.w);
      if (view == sh::kViewLevels && c.cascade.x > 0 && g.hit(i))
        display = sh::levelTint(display, sh::finestLevelAt(c, glm::vec3(g.position[i])));
      if ((view == sh::kViewSlice || view == sh::kViewMask) && c.fineDims.x > 1) {
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
