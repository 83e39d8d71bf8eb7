#include "sdf/pipeline/RayMask.h"

#include "grid/VdbIO.h"
#include "sdf/refine/RefinePasses.h"

#include <openvdb/tree/LeafManager.h>
#include <tbb/parallel_sort.h>

#include <cmath>
#include <mutex>

namespace rtsdf {

RayMask buildRayMask(const std::vector<float>& coarse, const GridSpec& cs, const GridSpec& fs, double band) {
  RayMask mask;
  if (band <= 0.0) return mask; // d = 0: nothing is refined, the fine SDF is the upsampled coarse one
  // The mask needs index space only. Voxels too small for an OpenVDB transform (scenes in tiny units) are
  // mirrored on the same grid measured in voxels: values and band divided by h, transform of voxel size 1.
  if (cs.voxelSize >= minVdbVoxelSize()) {
    mask.coarse = denseToLevelSet(coarse, cs, float(band));
  } else {
    GridSpec unit = cs;
    unit.voxelSize = 1.0;
    unit.origin = cs.origin / cs.voxelSize;
    std::vector<float> scaled(coarse.size());
    for (std::size_t i = 0; i < coarse.size(); ++i) scaled[i] = float(double(coarse[i]) / cs.voxelSize);
    // The same voxels must be active: |c| <= band exactly as in world units.
    const float unitBand = float(double(band) / cs.voxelSize);
    for (std::size_t i = 0; i < coarse.size(); ++i)
      if ((std::fabs(coarse[i]) <= float(band)) != (std::fabs(scaled[i]) <= unitBand))
        scaled[i] = std::fabs(coarse[i]) <= float(band) ? std::copysign(unitBand, scaled[i])
                                                         : std::copysign(std::nextafter(unitBand, INFINITY), scaled[i]);
    mask.coarse = denseToLevelSet(scaled, unit, unitBand);
  }
  mask.coarseVoxels = mask.coarse->activeVoxelCount();
  // Fine voxels whose centres fall in each active coarse voxel, leaf by leaf in parallel.
  openvdb::tree::LeafManager<const openvdb::FloatTree> leaves(mask.coarse->tree());
  std::mutex m;
  const std::vector<glm::ivec2> ranges = maskFineRanges(cs, fs);
  leaves.foreach([&](const openvdb::FloatTree::LeafNodeType& leaf, std::size_t) {
    std::vector<std::uint32_t> local;
    for (auto it = leaf.cbeginValueOn(); it; ++it) {
      const openvdb::Coord c = it.getCoord();
      appendFineVoxelsUnder(ranges, cs.dims, {c.x(), c.y(), c.z()}, 0u, local);
    }
    std::lock_guard<std::mutex> lock(m);
    mask.fineVoxels.insert(mask.fineVoxels.end(), local.begin(), local.end());
  });
  tbb::parallel_sort(mask.fineVoxels.begin(), mask.fineVoxels.end());
  return mask;
}

} // namespace rtsdf
