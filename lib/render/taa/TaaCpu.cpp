#include "render/taa/TaaCpu.h"

#include <algorithm>

namespace rtsdf {
namespace sh = gpu::shared;

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
