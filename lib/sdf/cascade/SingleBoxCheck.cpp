#include "sdf/cascade/SingleBoxCheck.h"

#include "sdf/cascade/CascadeScene.h"

#include <fmt/format.h>

#include <algorithm>
#include <vector>

namespace rtsdf {

SingleBoxFit singleBoxFit(const Scene& scene, const GridSpec& coarse, const GridSpec& fine) {
  SingleBoxFit fit;
  fit.fineVoxel = fine.voxelSize;
  fit.coarseVoxelsAcross = std::min({coarse.dims.x, coarse.dims.y, coarse.dims.z});
  fit.coarseVoxelsAlong = std::max({coarse.dims.x, coarse.dims.y, coarse.dims.z});
  std::vector<Bounds> meshBounds;
  for (const Mesh& mesh : scene.meshes) meshBounds.push_back(positionBounds(mesh));
  std::vector<double> thinnest;
  for (const Instance& inst : scene.instances) {
    const glm::dvec3 e = instanceBoxAt(inst, meshBounds.at(inst.mesh), 0.0).extent();
    const double t = std::min({e.x, e.y, e.z});
    if (t > 0.0) thinnest.push_back(t);
  }
  if (!thinnest.empty()) {
    std::nth_element(thinnest.begin(), thinnest.begin() + std::ptrdiff_t(thinnest.size() / 2), thinnest.end());
    fit.typicalFeature = thinnest[thinnest.size() / 2];
  }
  return fit;
}

std::string singleBoxAdvice(const Scene& scene, const GridSpec& coarse, const GridSpec& fine) {
  const SingleBoxFit fit = singleBoxFit(scene, coarse, fine);
  std::string why;
  if (fit.fineOverFeature() > kMaxFineOverFeature)
    why = fmt::format("fine voxel {:.3g} is {:.2f} of a typical feature ({:.3g}; at most {})", fit.fineVoxel,
                      fit.fineOverFeature(), fit.typicalFeature, kMaxFineOverFeature);
  if (fit.coarseVoxelsAcross < kMinCoarseVoxelsAcross && fit.coarseVoxelsAlong >= 4 * kMinCoarseVoxelsAcross)
    why += fmt::format("{}{} coarse voxels on the shortest axis (at least {})", why.empty() ? "" : "; ",
                       fit.coarseVoxelsAcross, kMinCoarseVoxelsAcross);
  if (why.empty()) return "";
  return fmt::format("one box is too coarse for this scene: {}; use camera-centred cascades (--cascades K)", why);
}

} // namespace rtsdf
