#include "sdf/cascade/CascadeSamplerCpu.h"

#include "util/Error.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace rtsdf {

CascadeSamplerCpu::CascadeSamplerCpu(CascadeLayout layout, std::vector<std::vector<float>> fields, double blendVoxels)
    : mLayout(std::move(layout)), mFields(std::move(fields)), mBlendVoxels(blendVoxels) {
  if (mFields.size() != mLayout.levels.size())
    throw Error(fmt::format("cascade sampler: {} fields for {} levels", mFields.size(), mLayout.levels.size()));
  for (std::size_t i = 0; i < mFields.size(); ++i)
    if (mFields[i].size() != mLayout.levels[i].fine.voxelCount())
      throw Error(fmt::format("cascade sampler: level {}'s field has {} values for {} voxels", i, mFields[i].size(),
                              mLayout.levels[i].fine.voxelCount()));
  if (!(blendVoxels >= 0.0)) throw Error("cascade sampler: the blend band must be >= 0 voxels");
}

float CascadeSamplerCpu::sampleLevel(int level, const glm::dvec3& p) const {
  const GridSpec& g = mLayout.levels.at(std::size_t(level)).fine;
  const std::vector<float>& f = mFields[std::size_t(level)];
  const glm::dvec3 t = glm::clamp(g.worldToIndex(p), glm::dvec3(0.0), glm::dvec3(g.dims - 1));
  const glm::ivec3 i0 = glm::min(glm::ivec3(glm::floor(t)), glm::max(g.dims - 2, glm::ivec3(0)));
  const glm::dvec3 w = t - glm::dvec3(i0);
  double v = 0.0;
  for (int c = 0; c < 8; ++c) {
    const glm::ivec3 o((c & 1) ? 1 : 0, (c & 2) ? 1 : 0, (c & 4) ? 1 : 0);
    const glm::ivec3 i = glm::min(i0 + o, g.dims - 1);
    const double wx = o.x ? w.x : 1.0 - w.x, wy = o.y ? w.y : 1.0 - w.y, wz = o.z ? w.z : 1.0 - w.z;
    v += wx * wy * wz * double(f[g.linear(i.x, i.y, i.z)]);
  }
  return float(v);
}

double CascadeSamplerCpu::insideDistance(int level, const glm::dvec3& p) const {
  const Bounds b = mLayout.levels.at(std::size_t(level)).box();
  const glm::dvec3 d = glm::min(p - b.min, b.max - p);
  return std::min({d.x, d.y, d.z});
}

float CascadeSamplerCpu::sample(const glm::dvec3& p) const {
  const int levels = int(mLayout.levels.size());
  for (int i = 0; i < levels; ++i) {
    const double h = mLayout.levels[std::size_t(i)].fine.voxelSize;
    const double inside = insideDistance(i, p) - h; // the trilinear stencil stays within the level
    if (inside <= 0.0) continue;
    const float here = sampleLevel(i, p);
    const double band = mBlendVoxels * h;
    if (i + 1 == levels || inside >= band) return here;
    const double w = inside / band;
    return float(w * double(here) + (1.0 - w) * double(sampleLevel(i + 1, p)));
  }
  return sampleLevel(levels - 1, p);
}

} // namespace rtsdf
